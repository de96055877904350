//! A setting's help text, as the scene's defaults complete it.

use super::*;
use crate::setting::Kind;

/// The help text: the help, the range and units, then the default, and the sphere's
/// where it differs; a switch says no default.
#[test]
fn help_texts_carry_range_units_and_both_defaults() {
    let blob = Scene::defaults(crate::scene::ModelSpec::Blob);
    let sphere = Scene::defaults(crate::scene::ModelSpec::Sphere);
    let reading = |get| {
        Access::Scene(Accessor {
            get,
            set: |_, _| {},
        })
    };
    let mut s = Setting {
        key: "key",
        flag: Flag::Long("flag"),
        label: "label",
        help: "help",
        units: "bounding radii",
        kind: Kind::within(0.5, 2.0),
        ..Setting::reaching(reading(|scene| Value::Integer(scene.options.segments)))
    };
    assert_eq!(
        s.help_text(&blob, &sphere),
        "help, 0.5..2 bounding radii [default: 16; sphere: 11]"
    );
    s.access = reading(|_| Value::Integer(3));
    assert_eq!(
        s.help_text(&blob, &blob),
        "help, 0.5..2 bounding radii [default: 3]"
    );
    s.flag = Flag::Switch("flag", true);
    assert_eq!(s.help_text(&blob, &sphere), "help, 0.5..2 bounding radii");
}
