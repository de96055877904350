//! Scripted head motion and a skinned or animated model's clip.

use crate::scene_file::value::field;
use crate::scene_file::{Effect, Flag, Group, Kind, Setting};

pub const MOTION: Group = Group {
    section: "motion",
    heading: "Scripted motion",
    settings: &[
        Setting {
            key: "kind",
            flag: Flag::Long("motion"),
            label: "motion",
            help: "Scripted head motion when simulating",
            kind: Kind::Choice(&["still", "shake", "spin", "nod"]),
            effect: Effect::Restart,
            ..field!(motion.kind)
        },
        Setting {
            key: "amplitude",
            flag: Flag::Long("amplitude"),
            label: "motion amplitude",
            help: "Motion amplitude: fraction of the model radius for shake, degrees for nod",
            kind: Kind::span_f64(crate::sim::motion::AMPLITUDE),
            effect: Effect::Restart,
            ..field!(motion.amplitude)
        },
        Setting {
            key: "rate",
            flag: Flag::Long("rate"),
            label: "motion rate",
            help: "Motion rate: Hz for shake and nod, turns per second for spin",
            kind: Kind::span_f64(crate::sim::motion::RATE),
            effect: Effect::Restart,
            ..field!(motion.rate)
        },
    ],
};

pub const ANIMATION: Group = Group {
    section: "animation",
    heading: "Animation",
    settings: &[
        Setting {
            key: "clip",
            flag: Flag::Long("animation"),
            label: "clip",
            help: "The clip to play, by name, any case (`walk` finds `Walk`); `none` holds the \
                   rest pose",
            kind: Kind::Text,
            unset: Some("the model's first clip"),
            effect: Effect::Restart,
            ..field!(animation.clip)
        },
        Setting {
            key: "speed",
            flag: Flag::Long("animation-speed"),
            label: "animation speed",
            help: "Clip seconds per simulated second",
            kind: Kind::within(0.0, 100.0),
            effect: Effect::Restart,
            ..field!(animation.speed)
        },
        Setting {
            key: "start",
            flag: Flag::Long("animation-start"),
            label: "animation start",
            help: "Clip time at the first frame",
            units: "s",
            kind: Kind::within(0.0, 1e6),
            effect: Effect::Restart,
            ..field!(animation.start)
        },
        Setting {
            key: "loop",
            flag: Flag::Switch("no-loop", false),
            label: "looping",
            help: "Hold the clip's last pose instead of looping",
            kind: Kind::Bool,
            effect: Effect::Restart,
            ..field!(animation.looping)
        },
        Setting {
            key: "in_place",
            flag: Flag::Switch("root-motion", false),
            label: "walking on the spot",
            help: "Keep the clip's root motion (the body walks away) instead of walking on the \
                   spot",
            kind: Kind::Bool,
            effect: Effect::Restart,
            ..field!(animation.in_place)
        },
    ],
};
