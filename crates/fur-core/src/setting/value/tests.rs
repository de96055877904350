//! Values as help texts write them, and each field type there and back.

use super::*;

/// At most four significant digits, trailing zeros dropped; short numbers, zero and
/// non-finite values as they are.
#[test]
fn numbers_are_written_short() {
    assert_eq!(short(0.2), "0.2");
    assert_eq!(short(0.158_771_2), "0.1588");
    assert_eq!(short(2.886_751_3), "2.887");
    assert_eq!(short(1234.5678), "1235");
    assert_eq!(short(-0.000_123_456), "-0.0001235");
    assert_eq!(short(12.500_001), "12.5");
    assert_eq!(short(0.0), "0");
    assert_eq!(short(f64::INFINITY), "inf");
    assert_eq!(short(1e-7), "0.0000001");
}

#[test]
fn values_display_as_the_command_line_takes_them() {
    assert_eq!(Value::Number(0.158_771_2).to_string(), "0.1588");
    assert_eq!(Value::Integer(16).to_string(), "16");
    assert_eq!(Value::Bool(true).to_string(), "on");
    assert_eq!(Value::Bool(false).to_string(), "off");
    assert_eq!(
        Value::Vector(Vec3::new(0.5, -1.0, 2.0)).to_string(),
        "0.5,-1,2"
    );
    assert_eq!(Value::Text("blob".into()).to_string(), "blob");
    assert_eq!(Value::Unset.to_string(), "unset");
}

/// Each field type goes to its value and back, and refuses a value of another type.
#[test]
fn each_field_type_round_trips_and_refuses_other_types() {
    fn round<T: FieldValue + PartialEq + std::fmt::Debug + Clone>(x: T) {
        assert_eq!(T::from_value(x.to_value()), Some(x.clone()), "{x:?}");
        let other = match x.to_value() {
            Value::Bool(_) => Value::Integer(1),
            _ => Value::Bool(true),
        };
        assert_eq!(T::from_value(other), None, "{x:?}");
    }
    round(0.2f32);
    round(0.2f64);
    round(7u32);
    round(true);
    round(Vec3::new(1.0, 2.0, 3.0));
    round(String::from("text"));
    round(Some(0.5f32));
    round(crate::render::LightingModel::Marschner);
    assert_eq!(Option::<f32>::from_value(Value::Unset), Some(None));
    // An f32 is written as the shortest decimal that reads back as it.
    assert_eq!(0.2f32.to_value(), Value::Number(0.2));
}
