//! A setting's value whatever its type ([`Value`]), and how the definitions reach the
//! fields they set ([`FieldValue`], the `field!` macro).

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
pub(super) fn short(v: f64) -> String {
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

/// A field of a scene as a [`Value`] and back: how the definitions in `keys/` reach
/// the structs they set (through the `field!` macro).
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

impl FieldValue for crate::scene::FlowFrom {
    fn to_value(&self) -> Value {
        Value::Text(self.to_string())
    }
    fn from_value(value: Value) -> Option<Self> {
        match value {
            Value::Text(v) => v.parse().ok(),
            _ => None,
        }
    }
}

/// A named choice (an enum with `name()` and `FromStr`) as a [`FieldValue`].
macro_rules! named_choice {
    ($($t:ty),+) => {$(
        impl FieldValue for $t {
            fn to_value(&self) -> Value {
                Value::Text(self.name().to_string())
            }
            fn from_value(value: Value) -> Option<Self> {
                match value {
                    Value::Text(v) => v.parse().ok(),
                    _ => None,
                }
            }
        }
    )+};
}

named_choice!(
    crate::render::Primitive,
    crate::render::Raster,
    crate::render::Shading,
    crate::render::LightingModel,
    crate::render::Stage,
    crate::render::stage::Arrows,
    crate::sim::MotionKind,
    crate::scene::Outside,
    crate::scene::GroomMode,
    crate::scene::Flow,
    crate::render::FurPreset
);

/// The getter and setter of a setting on the scene field at `$path`, and placeholders
/// for the rest of its definition (every definition overrides them).
macro_rules! field {
    ($($path:ident).+) => {
        $crate::scene_file::Setting {
            key: "",
            flag: $crate::scene_file::Flag::Long(""),
            label: "",
            help: "",
            units: "",
            kind: $crate::scene_file::Kind::Text,
            unset: None,
            effect: $crate::scene_file::Effect::Frame,
            panel: $crate::scene_file::Panel::Hidden,
            get: |s| $crate::scene_file::FieldValue::to_value(&s.$($path).+),
            set: |s, v| {
                if let Some(v) = $crate::scene_file::FieldValue::from_value(v) {
                    s.$($path).+ = v;
                }
            },
        }
    };
}
pub(crate) use field;

#[cfg(test)]
mod tests;
