//! A setting's value whatever its type ([`Value`]), and each field type as one and
//! back ([`FieldValue`]).

use glam::Vec3;

/// A setting's value, whatever its type.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Number(f64),
    Integer(u32),
    Bool(bool),
    Vector(Vec3),
    Text(String),
    /// Left unset (see [`Setting::unset`](super::Setting::unset)).
    Unset,
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Number(v) => write!(f, "{}", short(*v)),
            Value::Integer(v) => write!(f, "{v}"),
            Value::Bool(v) => write!(f, "{}", if *v { "on" } else { "off" }),
            Value::Vector(v) => write!(
                f,
                "{},{},{}",
                short(v.x.into()),
                short(v.y.into()),
                short(v.z.into())
            ),
            Value::Text(t) => write!(f, "{t}"),
            Value::Unset => write!(f, "unset"),
        }
    }
}

/// `v` with at most four significant digits, for help texts.
pub fn short(v: f64) -> String {
    let plain = format!("{v}");
    // Zero and the non-finite values (`-0`, `-inf`, `NaN`) are short already.
    if plain.len() <= 6 {
        return plain;
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let rounded = format!("{v:.digits$}");
    if rounded.contains('.') {
        rounded
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        rounded
    }
}

/// A field as a [`Value`] and back: how a setting's [`Accessor`](super::Accessor)
/// reads and writes it.
pub trait FieldValue: Sized {
    fn to_value(&self) -> Value;
    /// `None` when `value` is of another type (a definition's bug, caught by the
    /// round-trip test of every setting).
    fn from_value(value: Value) -> Option<Self>;
}

impl FieldValue for f32 {
    fn to_value(&self) -> Value {
        // Through the shortest decimal that reads back as this f32, so 0.2 is written
        // as 0.2 and not 0.20000000298023224.
        Value::Number(format!("{self}").parse().unwrap_or(f64::from(*self)))
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Number(v) => Some(v as f32),
            _ => None,
        }
    }
}

impl FieldValue for f64 {
    fn to_value(&self) -> Value {
        Value::Number(*self)
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Number(v) => Some(v),
            _ => None,
        }
    }
}

impl FieldValue for u32 {
    fn to_value(&self) -> Value {
        Value::Integer(*self)
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Integer(v) => Some(v),
            _ => None,
        }
    }
}

impl FieldValue for bool {
    fn to_value(&self) -> Value {
        Value::Bool(*self)
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Bool(v) => Some(v),
            _ => None,
        }
    }
}

impl FieldValue for Vec3 {
    fn to_value(&self) -> Value {
        Value::Vector(*self)
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Vector(v) => Some(v),
            _ => None,
        }
    }
}

impl FieldValue for String {
    fn to_value(&self) -> Value {
        Value::Text(self.clone())
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Text(v) => Some(v),
            _ => None,
        }
    }
}

impl<T: FieldValue> FieldValue for Option<T> {
    fn to_value(&self) -> Value {
        self.as_ref().map_or(Value::Unset, T::to_value)
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Unset => Some(None),
            v => T::from_value(v).map(Some),
        }
    }
}

#[cfg(test)]
mod tests;
