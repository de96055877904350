//! A setting's checks and range texts on hand-made kinds, at and past each end.

use super::*;
use glam::Vec3;

/// A setting of `kind`, unset meaning `unset`; the rest is not read by the checks.
fn setting(kind: Kind, unset: Option<&'static str>) -> Setting<()> {
    Setting {
        key: "key",
        flag: Flag::Long("flag"),
        label: "label",
        help: "help",
        kind,
        unset,
        ..Setting::reaching(())
    }
}

fn check(kind: Kind, v: Value) -> Result<(), String> {
    setting(kind, None).check(&v)
}

/// Whether `v` is refused with a message holding `says`.
fn refused(kind: Kind, v: Value, says: &str) -> bool {
    check(kind, v).is_err_and(|e| e.contains(says))
}

#[test]
fn numbers_are_checked_at_both_ends_open_or_closed() {
    let closed = Kind::within(0.5, 2.0);
    for ok in [0.5, 1.0, 2.0] {
        assert_eq!(check(closed, Value::Number(ok)), Ok(()), "{ok}");
    }
    for bad in [0.49, 2.01, f64::NAN, f64::INFINITY] {
        assert!(
            refused(closed, Value::Number(bad), "must be in [0.5, 2]"),
            "{bad}"
        );
    }
    let open = Kind::Number {
        min: 0.5,
        max: 2.0,
        min_open: true,
        double: false,
    };
    assert_eq!(check(open, Value::Number(0.51)), Ok(()));
    assert!(refused(open, Value::Number(0.5), "must be in (0.5, 2]"));
    // Open at 0 with no upper end worth saying: a positive number.
    let positive = Kind::positive(f64::from(f32::MAX));
    assert_eq!(check(positive, Value::Number(1e30)), Ok(()));
    assert!(refused(
        positive,
        Value::Number(0.0),
        "must be a positive number"
    ));
    let bounded = Kind::positive(3.0);
    assert!(refused(bounded, Value::Number(0.0), "must be in (0, 3]"));
    let from_one = Kind::Number {
        min: 1.0,
        max: f64::from(f32::MAX),
        min_open: true,
        double: false,
    };
    assert!(refused(from_one, Value::Number(1.0), "must be in (1,"));
}

#[test]
fn whole_numbers_choices_and_switches_are_checked() {
    let range = Kind::integer(2, 5);
    assert_eq!(check(range, Value::Integer(2)), Ok(()));
    assert_eq!(check(range, Value::Integer(5)), Ok(()));
    assert!(refused(range, Value::Integer(1), "must be 2..=5, got 1"));
    assert!(refused(range, Value::Integer(6), "must be 2..=5"));
    assert!(refused(range, Value::Integer(0), "must be 2..=5"));
    let or_zero = Kind::Integer {
        min: 2,
        max: 5,
        zero: true,
    };
    assert_eq!(check(or_zero, Value::Integer(0)), Ok(()));
    assert!(refused(
        or_zero,
        Value::Integer(1),
        "must be 0 (from the model) or 2..=5"
    ));
    let one_of = Kind::OneOf(&[1, 4]);
    assert_eq!(check(one_of, Value::Integer(4)), Ok(()));
    assert!(refused(one_of, Value::Integer(2), "must be 1 or 4, got 2"));
    let names = Kind::Choice(&["on", "off"]);
    assert_eq!(check(names, Value::Text("off".into())), Ok(()));
    assert!(refused(
        names,
        Value::Text("auto".into()),
        "unknown value `auto` (expected on or off)"
    ));
    assert_eq!(check(Kind::Bool, Value::Bool(false)), Ok(()));
    assert_eq!(check(Kind::Text, Value::Text("x".into())), Ok(()));
    // The wrong type says what is wanted.
    assert!(refused(
        Kind::Bool,
        Value::Integer(1),
        "expected true or false"
    ));
    assert!(refused(
        range,
        Value::Number(3.0),
        "expected a whole number"
    ));
}

#[test]
fn vectors_and_colours_are_checked() {
    let vector = Kind::Vector {
        max: 10.0,
        nonzero: true,
        down: false,
    };
    assert_eq!(
        check(vector, Value::Vector(Vec3::new(0.0, 10.0, 0.0))),
        Ok(())
    );
    assert!(refused(
        vector,
        Value::Vector(Vec3::new(0.0, 10.1, 0.0)),
        "magnitude ≤ 1e1"
    ));
    assert!(refused(vector, Value::Vector(Vec3::NAN), "must be finite"));
    assert!(refused(vector, Value::Vector(Vec3::ZERO), "non-zero"));
    let may_be_zero = Kind::Vector {
        max: 10.0,
        nonzero: false,
        down: true,
    };
    assert_eq!(check(may_be_zero, Value::Vector(Vec3::ZERO)), Ok(()));
    let colour = Kind::Colour { max: 2.0 };
    assert_eq!(
        check(colour, Value::Vector(Vec3::new(0.0, 2.0, 1.0))),
        Ok(())
    );
    for bad in [
        Vec3::new(-0.1, 1.0, 1.0),
        Vec3::new(1.0, 2.1, 1.0),
        Vec3::new(f32::NAN, 1.0, 1.0),
    ] {
        assert!(
            refused(colour, Value::Vector(bad), "channels in [0, 2]"),
            "{bad}"
        );
    }
}

/// An unset value is accepted only where the setting says what unset means.
#[test]
fn unset_is_accepted_only_where_it_means_something() {
    let kind = Kind::within(0.0, 1.0);
    assert_eq!(
        setting(kind, Some("from the model")).check(&Value::Unset),
        Ok(())
    );
    assert_eq!(
        setting(kind, None).check(&Value::Unset),
        Err("must be set".into())
    );
}

/// The range texts and wanted words: each kind's own.
#[test]
fn each_kind_says_its_range_and_what_it_wants() {
    let text = |k: Kind| k.range_text();
    assert_eq!(text(Kind::positive(1e31)).as_deref(), Some("> 0"));
    assert_eq!(text(Kind::within(1.0, 1e31)).as_deref(), Some("≥ 1"));
    assert_eq!(text(Kind::positive(3.0)).as_deref(), Some("(0, 3]"));
    assert_eq!(text(Kind::within(0.5, 2.0)).as_deref(), Some("0.5..2"));
    assert_eq!(text(Kind::integer(1, 63)).as_deref(), Some("1..=63"));
    let zero = Kind::Integer {
        min: 16,
        max: 512,
        zero: true,
    };
    assert_eq!(text(zero).as_deref(), Some("0 or 16..=512"));
    assert_eq!(text(Kind::OneOf(&[1, 4])).as_deref(), Some("1 or 4"));
    assert_eq!(
        text(Kind::Colour { max: 4.0 }).as_deref(),
        Some("linear RGB, 0..4")
    );
    assert_eq!(text(Kind::Bool), None);
    assert_eq!(Kind::Bool.wanted(), "true or false");
    assert_eq!(Kind::Text.wanted(), "text");
    assert_eq!(Kind::Choice(&["a"]).wanted(), "one of the names");
    let down = Kind::Vector {
        max: 1.0,
        nonzero: false,
        down: true,
    };
    assert!(down.wanted().contains("pointing down"));
    assert_eq!(Flag::Switch("wind", true).name(), "wind");
    assert_eq!(
        format!("{:?}", setting(Kind::Bool, None)),
        "Setting(key / --flag)"
    );
}

/// Open at a minimum other than 0 and unbounded above, a number's range is written
/// in full; a list of one item is the item.
#[test]
fn ranges_open_above_other_minimums_and_single_items_read_right() {
    let from_one = Kind::Number {
        min: 1.0,
        max: 1e31,
        min_open: true,
        double: false,
    };
    assert_eq!(from_one.range_text().as_deref(), Some("(1, 1e31]"));
    assert_eq!(list(&["x"], "or"), "x");
    assert_eq!(list(&["x", "y", "z"], "and"), "x, y and z");
    assert_eq!(list::<&str>(&[], "or"), "");
}
