//! The light, the hair's colour and highlights, the fibre's physical parameters and
//! self-shadowing (`fur bench --only looks` costs each).

use crate::render::lighting_spans as spans;
use crate::scene_file::value::field;
use crate::scene_file::{Flag, Group, Kind, Panel, Setting};

const SLIDER_0_2: Panel = Panel::Slider {
    min: 0.0,
    max: 2.0,
    log: false,
};
const SHIFT: Panel = Panel::Slider {
    min: -20.0,
    max: 20.0,
    log: false,
};
const EXPONENT: Panel = Panel::Slider {
    min: 1.0,
    max: 200.0,
    log: true,
};

pub const LIGHT: Group = Group {
    section: "light",
    heading: "Lighting",
    settings: &[
        Setting {
            key: "lighting_model",
            flag: Flag::Long("lighting-model"),
            label: "lighting model",
            help: "How the hair is lit: `marschner` (a physically based fibre model on \
                   the `[fibre]` parameters with dual scattering; the default) or \
                   `kajiya-kay` (the seed's model, with shifted highlights)",
            kind: Kind::Choice(&["kajiya-kay", "marschner"]),
            panel: Panel::Plain,
            ..field!(options.lighting.model)
        },
        Setting {
            key: "direction",
            flag: Flag::Long("light-direction"),
            label: "light direction",
            help: "Direction towards the light, \"x,y,z\"",
            kind: Kind::Vector {
                max: f32::MAX as f64,
                nonzero: true,
                down: false,
            },
            ..field!(options.lighting.light_direction)
        },
        Setting {
            key: "intensity",
            flag: Flag::Long("light-intensity"),
            label: "light intensity",
            help: "The light's intensity",
            kind: Kind::span(spans::WEIGHT),
            panel: Panel::Slider {
                min: 0.0,
                max: 3.0,
                log: false,
            },
            ..field!(options.lighting.intensity)
        },
        Setting {
            key: "kd",
            flag: Flag::Long("kd"),
            label: "Kd (diffuse)",
            help: "Diffuse reflectance of hair and skin",
            kind: Kind::span(spans::WEIGHT),
            panel: SLIDER_0_2,
            ..field!(options.lighting.kd)
        },
        Setting {
            key: "ks",
            flag: Flag::Long("ks"),
            label: "Ks (specular)",
            help: "Specular reflectance of the primary highlight (Kajiya–Kay)",
            kind: Kind::span(spans::WEIGHT),
            panel: SLIDER_0_2,
            ..field!(options.lighting.ks)
        },
        Setting {
            key: "shininess",
            flag: Flag::Long("shininess"),
            label: "the specular exponent",
            help: "Specular exponent of the primary highlight",
            kind: Kind::span(spans::EXPONENT),
            panel: EXPONENT,
            ..field!(options.lighting.shininess)
        },
        Setting {
            key: "ambient",
            flag: Flag::Long("ambient"),
            label: "ambient",
            help: "Ambient light",
            kind: Kind::span(spans::WEIGHT),
            panel: Panel::Slider {
                min: 0.0,
                max: 1.0,
                log: false,
            },
            ..field!(options.lighting.ambient)
        },
        Setting {
            key: "root_color",
            flag: Flag::Long("root-color"),
            label: "root colour",
            help: "Hair colour at the root, \"r,g,b\"",
            kind: Kind::Colour {
                max: spans::COLOUR_MAX,
            },
            panel: Panel::Plain,
            ..field!(options.lighting.root_color)
        },
        Setting {
            key: "tip_color",
            flag: Flag::Long("tip-color"),
            label: "tip colour",
            help: "Hair colour at the tip, \"r,g,b\"",
            kind: Kind::Colour {
                max: spans::COLOUR_MAX,
            },
            panel: Panel::Plain,
            ..field!(options.lighting.tip_color)
        },
        Setting {
            key: "fur_preset",
            flag: Flag::Long("fur-preset"),
            label: "fur preset",
            help: "A natural fur colour as melanin (`white`, `blond`, `ginger`, `brown`, \
                   `black`) that replaces the root and tip colours: the colour whose \
                   absorption under Chiang's mapping is the melanin's (docs/design.md); \
                   `none` keeps them",
            kind: Kind::Choice(&["none", "white", "blond", "ginger", "brown", "black"]),
            ..field!(options.lighting.preset)
        },
        Setting {
            key: "skin_color",
            flag: Flag::Long("skin-color"),
            label: "skin colour",
            help: "Skin colour, \"r,g,b\"",
            kind: Kind::Colour {
                max: spans::COLOUR_MAX,
            },
            panel: Panel::Plain,
            ..field!(options.lighting.skin_color)
        },
        Setting {
            key: "root_occlusion",
            flag: Flag::Long("root-occlusion"),
            label: "root occlusion",
            help: "How much darker hair is at the root than at the tip (Kajiya–Kay; the \
                   Marschner model darkens deep hair by the coat's layers instead)",
            kind: Kind::span(spans::FRACTION),
            panel: Panel::Slider {
                min: 0.0,
                max: 1.0,
                log: false,
            },
            ..field!(options.lighting.root_occlusion)
        },
        Setting {
            key: "secondary_highlight",
            flag: Flag::Long("secondary-highlight"),
            label: "secondary highlight",
            help: "A second, wider highlight tinted by the hair colour, shifted toward the \
                   root (the primary shifts toward the tip)",
            kind: Kind::Bool,
            panel: Panel::Plain,
            ..field!(options.lighting.highlights.secondary)
        },
        Setting {
            key: "primary_shift",
            flag: Flag::Long("primary-shift"),
            label: "the primary highlight's shift",
            help: "Shift of the primary highlight, positive toward the tip",
            units: "°",
            kind: Kind::span(spans::SHIFT_DEG),
            panel: SHIFT,
            ..field!(options.lighting.highlights.primary_shift_deg)
        },
        Setting {
            key: "secondary_shift",
            flag: Flag::Long("secondary-shift"),
            label: "the secondary highlight's shift",
            help: "Shift of the secondary highlight",
            units: "°",
            kind: Kind::span(spans::SHIFT_DEG),
            panel: SHIFT,
            ..field!(options.lighting.highlights.secondary_shift_deg)
        },
        Setting {
            key: "secondary_shininess",
            flag: Flag::Long("secondary-shininess"),
            label: "the secondary highlight's exponent",
            help: "Specular exponent of the secondary highlight",
            kind: Kind::span(spans::EXPONENT),
            panel: EXPONENT,
            ..field!(options.lighting.highlights.secondary_shininess)
        },
        Setting {
            key: "secondary_strength",
            flag: Flag::Long("secondary-strength"),
            label: "the secondary highlight's strength",
            help: "Strength of the secondary highlight",
            kind: Kind::span(spans::WEIGHT),
            panel: SLIDER_0_2,
            ..field!(options.lighting.highlights.secondary_strength)
        },
    ],
};

pub const FIBRE: Group = Group {
    section: "fibre",
    heading: "Fibre (Marschner and the path-traced reference)",
    settings: &[
        Setting {
            key: "longitudinal_roughness",
            flag: Flag::Long("longitudinal-roughness"),
            label: "the longitudinal roughness β_m",
            help: "Longitudinal roughness β_m of the fibre",
            kind: Kind::span(spans::ROUGHNESS),
            panel: Panel::Slider {
                min: 0.01,
                max: 1.0,
                log: false,
            },
            ..field!(options.lighting.fibre.longitudinal_roughness)
        },
        Setting {
            key: "azimuthal_roughness",
            flag: Flag::Long("azimuthal-roughness"),
            label: "the azimuthal roughness β_n",
            help: "Azimuthal roughness β_n of the fibre",
            kind: Kind::span(spans::ROUGHNESS),
            panel: Panel::Slider {
                min: 0.01,
                max: 1.0,
                log: false,
            },
            ..field!(options.lighting.fibre.azimuthal_roughness)
        },
        Setting {
            key: "cuticle_tilt",
            flag: Flag::Long("cuticle-tilt"),
            label: "the cuticle tilt α",
            help: "Tilt α of the cuticle scales",
            units: "°",
            kind: Kind::span(spans::CUTICLE_TILT_DEG),
            panel: Panel::Slider {
                min: -10.0,
                max: 10.0,
                log: false,
            },
            ..field!(options.lighting.fibre.cuticle_tilt_deg)
        },
        Setting {
            key: "ior",
            flag: Flag::Long("ior"),
            label: "the index of refraction η",
            help: "Index of refraction η of the fibre",
            kind: Kind::span(spans::IOR),
            panel: Panel::Slider {
                min: 1.0,
                max: 3.0,
                log: false,
            },
            ..field!(options.lighting.fibre.ior)
        },
        Setting {
            key: "direction_spread",
            flag: Flag::Long("direction-spread"),
            label: "the direction spread",
            help: "Mean squared angle between neighbouring hairs' directions; widens the Marschner model's multiple scattering",
            units: "rad²",
            kind: Kind::span(spans::DIRECTION_SPREAD),
            panel: Panel::Slider {
                min: 0.0,
                max: 1.0,
                log: false,
            },
            ..field!(options.lighting.fibre.direction_spread)
        },
    ],
};

pub const SHADOWS: Group = Group {
    section: "shadows",
    heading: "Self-shadowing",
    settings: &[
        Setting {
            key: "enabled",
            flag: Flag::Long("shadows"),
            label: "self-shadowing",
            help: "Hair shadowing hair and skin, from a light-space depth map of the fur",
            kind: Kind::Bool,
            panel: Panel::Plain,
            ..field!(options.lighting.shadows.enabled)
        },
        Setting {
            key: "resolution",
            flag: Flag::Long("shadow-resolution"),
            label: "shadow map resolution",
            help: "Side of the shadow map",
            units: "texels",
            kind: Kind::integer(16, crate::render::Shadows::MAX_RESOLUTION),
            panel: Panel::Plain,
            ..field!(options.lighting.shadows.resolution)
        },
        Setting {
            key: "opacity",
            flag: Flag::Long("shadow-opacity"),
            label: "shadow opacity",
            help: "Light one layer of hair stops",
            kind: Kind::span(spans::FRACTION),
            panel: Panel::Slider {
                min: 0.0,
                max: 1.0,
                log: false,
            },
            ..field!(options.lighting.shadows.opacity)
        },
        Setting {
            key: "spacing",
            flag: Flag::Long("shadow-spacing"),
            label: "shadow spacing",
            help: "Depth of one hair layer; 0 = the hair spacing",
            units: "bounding radii",
            kind: Kind::span(spans::SPACING),
            ..field!(options.lighting.shadows.spacing)
        },
    ],
};
