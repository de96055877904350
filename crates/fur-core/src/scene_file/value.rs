//! The field types only a scene has as settings' values ([`FieldValue`]: the named
//! choices), and how a definition in `keys/` reaches the scene field it sets (the
//! `field!` macro).

use crate::setting::{FieldValue, Value};

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

/// The setting of the scene field at `$path`, its other parts placeholders that every
/// definition overrides (`..field!(options.hair_length)`).
macro_rules! field {
    ($($path:ident).+) => {
        $crate::scene_file::Setting::reaching($crate::scene_file::Access::Scene(
            $crate::setting::accessor!($crate::scene_file::Scene: $($path).+),
        ))
    };
}
pub(crate) use field;
