//! The simulation (Han & Harada's constraints, wind) and collision with the body; units
//! as [`crate::sim::SimParams`]: seconds, m/s², degrees.

use crate::scene_file::value::field;
use crate::scene_file::{Effect, Flag, Group, Kind, Panel, Setting};
use crate::sim::params::{spans, MAX_ACCELERATION, MAX_PASSES};

const UNIT: Panel = Panel::Slider {
    min: 0.0,
    max: 1.0,
    log: false,
};
const PASSES: Panel = Panel::Slider {
    min: 0.0,
    max: 16.0,
    log: false,
};

pub const SIMULATION: Group = Group {
    section: "simulation",
    heading: "Simulation",
    settings: &[
        Setting {
            key: "dt",
            flag: Flag::Long("dt"),
            label: "dt",
            help: "Seconds simulated per frame",
            units: "s",
            kind: Kind::span(spans::DT),
            effect: Effect::Simulation,
            ..field!(sim.dt)
        },
        Setting {
            key: "substeps",
            flag: Flag::Long("substeps"),
            label: "substeps",
            help: "Substeps per frame",
            kind: Kind::integer(1, MAX_PASSES),
            effect: Effect::Simulation,
            panel: Panel::Slider {
                min: 1.0,
                max: 16.0,
                log: false,
            },
            ..field!(sim.substeps)
        },
        Setting {
            key: "gravity",
            flag: Flag::Long("gravity"),
            label: "gravity",
            help: "Gravity: \"x,y,z\", or one number g for (0, −g, 0)",
            units: "m/s²",
            kind: Kind::Vector {
                max: MAX_ACCELERATION,
                nonzero: false,
                down: true,
            },
            effect: Effect::Simulation,
            panel: Panel::Plain,
            ..field!(sim.gravity)
        },
        Setting {
            key: "damping",
            flag: Flag::Long("damping"),
            label: "damping",
            help: "Fraction of velocity lost per 1/60 s",
            kind: Kind::span(spans::FRACTION),
            effect: Effect::Simulation,
            panel: UNIT,
            ..field!(sim.damping)
        },
        Setting {
            key: "global_stiffness",
            flag: Flag::Long("global-stiffness"),
            label: "global stiffness S_G",
            help: "Global shape stiffness S_G",
            kind: Kind::span(spans::FRACTION),
            effect: Effect::Simulation,
            panel: UNIT,
            ..field!(sim.global_stiffness)
        },
        Setting {
            key: "global_range",
            flag: Flag::Long("global-range"),
            label: "global range",
            help: "Fraction of each strand the global constraint covers",
            kind: Kind::span(spans::FRACTION),
            effect: Effect::Simulation,
            panel: UNIT,
            ..field!(sim.global_range)
        },
        Setting {
            key: "local_stiffness",
            flag: Flag::Long("local-stiffness"),
            label: "local stiffness S_L",
            help: "Local shape stiffness S_L",
            kind: Kind::span(spans::FRACTION),
            effect: Effect::Simulation,
            panel: UNIT,
            ..field!(sim.local_stiffness)
        },
        Setting {
            key: "local_iterations",
            flag: Flag::Long("local-iterations"),
            label: "local iterations",
            help: "Local shape passes per substep",
            kind: Kind::integer(0, MAX_PASSES),
            effect: Effect::Simulation,
            panel: PASSES,
            ..field!(sim.local_iterations)
        },
        Setting {
            key: "length_iterations",
            flag: Flag::Long("length-iterations"),
            label: "length iterations",
            help: "Edge-length passes per substep",
            kind: Kind::integer(0, MAX_PASSES),
            effect: Effect::Simulation,
            panel: PASSES,
            ..field!(sim.length_iterations)
        },
        Setting {
            key: "wind",
            flag: Flag::Long("wind"),
            label: "wind",
            help: "Wind vector \"x,y,z\", 0,0,0 = no wind",
            units: "m/s²",
            kind: Kind::Vector {
                max: MAX_ACCELERATION,
                nonzero: false,
                down: false,
            },
            effect: Effect::Simulation,
            ..field!(sim.wind)
        },
        Setting {
            key: "wind_cone",
            flag: Flag::Long("wind-cone"),
            label: "wind cone angle",
            help: "Half-angle of the cone the wind's direction wanders in",
            units: "°",
            kind: Kind::span(spans::WIND_CONE_DEG),
            effect: Effect::Simulation,
            ..field!(sim.wind_cone_deg)
        },
    ],
};

pub const COLLISION: Group = Group {
    section: "collision",
    heading: "Collision",
    settings: &[
        Setting {
            key: "enabled",
            flag: Flag::Long("collision"),
            label: "collision",
            help: "Keep the hair out of the body (a signed distance field of the model)",
            kind: Kind::Bool,
            effect: Effect::Simulation,
            panel: Panel::Plain,
            ..field!(sim.collision)
        },
        Setting {
            key: "margin",
            flag: Flag::Long("collision-margin"),
            label: "collision margin",
            help: "How far outside the surface hair is kept, as a fraction of each hair's \
                   length",
            kind: Kind::span(spans::FRACTION),
            effect: Effect::Simulation,
            panel: Panel::Slider {
                min: 0.0,
                max: 0.2,
                log: false,
            },
            ..field!(sim.collision_margin)
        },
        Setting {
            key: "friction",
            flag: Flag::Long("friction"),
            label: "friction",
            help: "Fraction of a colliding vertex's sliding velocity removed per substep",
            kind: Kind::span(spans::FRACTION),
            effect: Effect::Simulation,
            panel: UNIT,
            ..field!(sim.friction)
        },
        Setting {
            key: "sdf_resolution",
            flag: Flag::Long("sdf-resolution"),
            label: "the distance field's resolution",
            help: "Distance-field cells along the model's longest axis; 0 chooses from the \
                   hair length (cells about a third of it, a sixth on a skinned body, \
                   16..=128)",
            kind: Kind::Integer {
                min: crate::geometry::sdf::RESOLUTION_RANGE.0,
                max: crate::geometry::sdf::RESOLUTION_RANGE.1,
                zero: true,
            },
            effect: Effect::Restart,
            ..field!(sim.sdf_resolution)
        },
        Setting {
            key: "skin_blend",
            flag: Flag::Long("skin-blend"),
            label: "skin blend",
            help: "On a skinned body, carry the outer hair back to the rest pose's field \
                   through the skin's own blend of bones, and the hair nearest the root by \
                   the root's heaviest bone: hair stays out where the skin bends between \
                   bones and where it folds over a crease (docs/benchmark.md)",
            kind: Kind::Bool,
            unset: Some("on where its grid fits the device"),
            effect: Effect::Restart,
            ..field!(sim.skin_blend)
        },
    ],
};
