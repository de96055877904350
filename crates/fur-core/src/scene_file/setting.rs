//! A scene's settings as its file's sections ([`Group`]): each setting reaches the
//! scene's field directly or through the struct that declares it ([`Access`]). Every
//! setting is defined once, in one of the group files of `keys/` or beside the fields
//! of the struct it sets (the drawing style's, `render/style.rs`); the command line
//! (the application's `SettingArgs`), the scene file's reader and writer, the viewer's
//! panel, `fur settings` and the scene-file docs all come from those definitions.

use super::Scene;
use crate::render::FurStyle;
use crate::setting::{Accessor, Flag, Value};

/// One setting of a [`Scene`].
pub type Setting = crate::setting::Setting<Access>;

/// How a setting of the scene reaches its field.
#[derive(Clone, Copy)]
pub enum Access {
    /// A field of the scene (`field!`).
    Scene(Accessor<Scene>),
    /// A field of the scene's drawing style (`SceneOptions::draw`), declared beside it
    /// (`crate::render::style::SETTINGS`).
    Style(Accessor<FurStyle>),
}

impl Setting {
    /// The value of its field in `scene`.
    pub fn get(&self, scene: &Scene) -> Value {
        match self.access {
            Access::Scene(a) => (a.get)(scene),
            Access::Style(a) => (a.get)(&scene.options.draw),
        }
    }

    /// Sets its field in `scene` to `value` (of the setting's type: the caller has
    /// checked it).
    pub fn set(&self, scene: &mut Scene, value: Value) {
        match self.access {
            Access::Scene(a) => (a.set)(scene, value),
            Access::Style(a) => (a.set)(&mut scene.options.draw, value),
        }
    }
}

/// A section of a scene file: a group of settings under one heading.
pub struct Group {
    /// The TOML table's name (`render`).
    pub section: &'static str,
    /// The heading in `--help`, the panel and the docs.
    pub heading: &'static str,
    pub settings: &'static [Setting],
}

impl Setting {
    /// The help text with its range, units and defaults (`[default: 0.2; sphere:
    /// 0.159]`).
    pub fn help_text(&self, blob: &Scene, sphere: &Scene) -> String {
        let mut text = self.help.to_string();
        match (self.kind.range_text(), self.units) {
            (Some(range), "") => text += &format!(", {range}"),
            (Some(range), units) => text += &format!(", {range} {units}"),
            (None, "") => {}
            (None, units) => text += &format!(", in {units}"),
        }
        if matches!(self.flag, Flag::Switch(..)) {
            return text;
        }
        let (a, b) = (self.get(blob), self.get(sphere));
        let shown = |v: &Value| match (v, self.unset) {
            (Value::Unset, Some(meaning)) => meaning.to_string(),
            (v, _) => v.to_string(),
        };
        text += &format!(" [default: {}", shown(&a));
        if a != b {
            text += &format!("; sphere: {}", shown(&b));
        }
        text + "]"
    }
}

#[cfg(test)]
mod tests;
