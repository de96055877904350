//! The table of every setting for `fur settings` and docs/scene-files.md, made from the
//! definitions.

use super::keys::GROUPS;
use super::{Flag, Kind, Scene, Value};
use crate::scene::ModelSpec;

/// The line before the generated table in a Markdown file.
pub const BEGIN: &str = "<!-- BEGIN fur settings -->";
/// The line after it.
pub const END: &str = "<!-- END fur settings -->";

/// Every setting as Markdown: one table per section (key, flag, values, default,
/// meaning).
pub fn markdown() -> String {
    let blob = Scene::defaults(ModelSpec::Blob);
    let sphere = Scene::defaults(ModelSpec::Sphere);
    let mut out = String::new();
    for group in GROUPS {
        out += &format!(
            "\n### `[{}]` {}\n\n| key | flag | values | default | meaning |\n| --- | --- | --- | --- | --- |\n",
            group.section, group.heading
        );
        for s in group.settings {
            let flag = match s.flag {
                Flag::Long(name) => format!("`--{name}`"),
                Flag::Switch(name, value) => format!("`--{name}` (sets {value})"),
            };
            let mut values = match s.kind {
                Kind::Bool => "true, false".to_string(),
                Kind::Choice(names) => names
                    .iter()
                    .map(|n| format!("`{n}`"))
                    .collect::<Vec<_>>()
                    .join(", "),
                Kind::Vector { down: true, .. } => "[x, y, z] or g".to_string(),
                Kind::Vector { .. } => "[x, y, z]".to_string(),
                Kind::Text => "text".to_string(),
                Kind::Place => "`auto`, `+x` … `-z`, or x,y,z".to_string(),
                kind => kind.range_text().unwrap_or_default(),
            };
            if !s.units.is_empty() {
                values += &format!(" {}", s.units);
            }
            let shown = |v: Value| match (v, s.unset) {
                (Value::Unset, Some(meaning)) => meaning.to_string(),
                (Value::Bool(b), _) => b.to_string(),
                (Value::Vector(v), _) => format!("[{}]", Value::Vector(v)).replace(',', ", "),
                (v, _) => v.to_string(),
            };
            let (a, b) = (s.get(&blob), s.get(&sphere));
            let default = if a == b {
                shown(a)
            } else {
                format!("{}; sphere: {}", shown(a), shown(b))
            };
            out += &format!(
                "| `{}` | {flag} | {} | {} | {} |\n",
                s.key,
                values.replace('|', "\\|"),
                default,
                s.help.replace('|', "\\|")
            );
        }
    }
    out
}
