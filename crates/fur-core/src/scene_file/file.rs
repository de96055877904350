//! Reading and writing TOML scene files through the setting definitions: every section
//! and key is looked up in `keys/`; an unknown one, a value of the wrong type and a
//! value out of range are errors naming the file, the line and column, and the key.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::keys::GROUPS;
use super::{list, FieldValue, Kind, Scene, Setting, Value};
use crate::error::{Error, Result};
use crate::scene::{ModelSpec, TextureSpec};

/// A scene file: any part of a [`Scene`], each key checked against its definition.
#[derive(Clone, Debug, Default)]
pub struct SceneFile {
    /// `blob`, `sphere`, `critter`, or a model path relative to the scene file.
    model: Option<String>,
    /// `tabby`, or an image path relative to the scene file (over the model's own).
    texture: Option<String>,
    /// Every setting the file gives: its section and its value, in the file's order.
    values: Vec<(&'static str, &'static Setting, Value)>,
}

impl SceneFile {
    /// Reads and parses a scene file; syntax, type and unknown-key errors name the file,
    /// line, column and key.
    pub fn load(path: &Path) -> Result<(Self, String)> {
        let text =
            crate::files::read_text_bounded(path, crate::files::MAX_SCENE_BYTES, "scene file")
                .map_err(|e| error(path, At::default(), format!("cannot read it: {e}")))?;
        let table: toml::Table = toml::from_str(&text).map_err(|e: toml::de::Error| {
            let at = e
                .span()
                .map_or(At::default(), |s| line_column(&text, s.start));
            error(path, at, e.message().trim().to_string())
        })?;
        let file = Self::parse(&table, &text, path)?;
        Ok((file, text))
    }

    fn parse(table: &toml::Table, text: &str, path: &Path) -> Result<Self> {
        let mut file = Self::default();
        for (name, item) in table {
            let at = |key: &str| locate(text, None, key);
            match (name.as_str(), item) {
                ("model", toml::Value::String(s)) => file.model = Some(s.clone()),
                ("texture", toml::Value::String(s)) => file.texture = Some(s.clone()),
                ("model" | "texture", other) => {
                    return Err(error(
                        path,
                        at(name),
                        format!(
                            "`{name}`: expected a name or a path, got {}",
                            other.type_str()
                        ),
                    ))
                }
                (_, toml::Value::Table(keys)) => {
                    let Some(group) = GROUPS.iter().find(|g| g.section == name) else {
                        let sections: Vec<String> =
                            GROUPS.iter().map(|g| format!("[{}]", g.section)).collect();
                        return Err(error(
                            path,
                            header(text, name),
                            format!(
                                "unknown section `[{name}]` (expected {})",
                                list(&sections, "or")
                            ),
                        ));
                    };
                    for (key, value) in keys {
                        let at = locate(text, Some(name), key);
                        let Some(setting) = group.settings.iter().find(|s| s.key == key) else {
                            let known: Vec<&str> = group.settings.iter().map(|s| s.key).collect();
                            return Err(error(
                                path,
                                at,
                                format!(
                                    "unknown key `{name}.{key}` (expected {})",
                                    list(&known, "or")
                                ),
                            ));
                        };
                        let value = from_toml(setting.kind, value)
                            .map_err(|m| error(path, at, format!("`{name}.{key}`: {m}")))?;
                        file.values.push((group.section, setting, value));
                    }
                }
                (_, _) => {
                    return Err(error(
                        path,
                        at(name),
                        format!("unknown key `{name}` (expected model, texture or a section)"),
                    ))
                }
            }
        }
        Ok(file)
    }

    /// The model the file names, resolved against the file's folder.
    pub fn model(&self, path: &Path) -> Option<ModelSpec> {
        self.model.as_ref().map(|m| match m.parse::<ModelSpec>() {
            Ok(ModelSpec::File(p)) if p.is_relative() => {
                let dir = path.parent().unwrap_or(Path::new("."));
                ModelSpec::File(dir.join(p))
            }
            Ok(spec) => spec,
            Err(_) => ModelSpec::File(PathBuf::from(m)),
        })
    }

    /// Applies every key the file sets onto `scene`; an out-of-range value is an error
    /// naming the file, line and key (`text` is the file's contents, `path` its name).
    pub fn apply(&self, scene: &mut Scene, path: &Path, text: &str) -> Result<()> {
        if let Some(name) = &self.texture {
            scene.options.texture = Some(match name.parse::<TextureSpec>() {
                Ok(TextureSpec::File(p)) if p.is_relative() => {
                    TextureSpec::File(path.parent().unwrap_or(Path::new(".")).join(p))
                }
                Ok(spec) => spec,
                Err(_) => TextureSpec::File(PathBuf::from(name)),
            });
        }
        for (section, setting, value) in &self.values {
            setting.check(value).map_err(|m| {
                let at = locate(text, Some(section), setting.key);
                error(path, at, format!("`{section}.{}`: {m}", setting.key))
            })?;
            setting.set(scene, value.clone());
        }
        // A groom file the scene file names is found beside the scene file.
        let names_groom = self
            .values
            .iter()
            .any(|(section, setting, _)| *section == "groom" && setting.key == "file");
        if let (true, Some(groom)) = (names_groom, &mut scene.options.groom_file) {
            if Path::new(groom.as_str()).is_relative() {
                let dir = path.parent().unwrap_or(Path::new("."));
                *groom = dir.join(&*groom).to_string_lossy().into_owned();
            }
        }
        Ok(())
    }
}

/// `path` from the working folder, unchanged when absolute or when the working folder
/// is unknown.
fn absolute(path: &str) -> String {
    let p = Path::new(path);
    if p.is_absolute() {
        return path.to_string();
    }
    std::env::current_dir()
        .map(|d| d.join(p).to_string_lossy().into_owned())
        .unwrap_or_else(|_| path.to_string())
}

/// The scene as TOML holding every key.
pub(super) fn to_toml(scene: &Scene) -> Result<String> {
    let mut table = toml::Table::new();
    table.insert("model".into(), scene.model.name().into());
    if let Some(texture) = &scene.options.texture {
        table.insert("texture".into(), texture.name().into());
    }
    for group in GROUPS {
        let mut section = toml::Table::new();
        for setting in group.settings {
            let value = match setting.get(scene) {
                Value::Number(v) => toml::Value::Float(v),
                Value::Integer(v) => toml::Value::Integer(v.into()),
                Value::Bool(v) => toml::Value::Boolean(v),
                Value::Vector(v) => toml::Value::Array(
                    v.to_array()
                        .iter()
                        .map(|c| match c.to_value() {
                            Value::Number(c) => toml::Value::Float(c),
                            _ => unreachable!("an f32 is a number"),
                        })
                        .collect(),
                ),
                // A groom path read relative to the scene file: saved absolute, so the
                // scene finds it wherever it is saved.
                Value::Text(t) if group.section == "groom" && setting.key == "file" => {
                    toml::Value::String(absolute(&t))
                }
                Value::Text(t) => toml::Value::String(t),
                Value::Unset => continue,
            };
            section.insert(setting.key.into(), value);
        }
        table.insert(group.section.into(), toml::Value::Table(section));
    }
    toml::to_string_pretty(&table)
        .map_err(|e| Error::Parameter(format!("cannot encode the scene: {e}")))
}

/// A TOML value as a value of `kind` (the range is checked when it is applied).
fn from_toml(kind: Kind, value: &toml::Value) -> std::result::Result<Value, String> {
    let number = |v: &toml::Value| match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    };
    let wrong = || format!("expected {}, got {}", kind.wanted(), value.type_str());
    match (kind, value) {
        (Kind::Number { .. }, v) => number(v).map(Value::Number).ok_or_else(wrong),
        (Kind::Integer { .. } | Kind::OneOf(_), toml::Value::Integer(i)) => u32::try_from(*i)
            .map(Value::Integer)
            .map_err(|_| format!("expected a whole number ≥ 0, got {i}")),
        (Kind::Bool, toml::Value::Boolean(b)) => Ok(Value::Bool(*b)),
        (Kind::Choice(_) | Kind::Text | Kind::Place, toml::Value::String(s)) => {
            Ok(Value::Text(s.clone()))
        }
        (Kind::Vector { down: true, .. }, v) if number(v).is_some() => Ok(Value::Vector(
            Vec3::new(0.0, -(number(v).unwrap_or(0.0) as f32), 0.0),
        )),
        (Kind::Vector { .. } | Kind::Colour { .. }, toml::Value::Array(items)) => {
            let xyz: Option<Vec<f64>> = items.iter().map(number).collect();
            match xyz.as_deref() {
                Some([x, y, z]) => Ok(Value::Vector(Vec3::new(*x as f32, *y as f32, *z as f32))),
                Some(v) => Err(format!("expected 3 numbers, got {}", v.len())),
                None => Err(wrong()),
            }
        }
        _ => Err(wrong()),
    }
}

fn error(path: &Path, at: At, message: String) -> Error {
    Error::SceneFile {
        path: path.to_path_buf(),
        line: at.line,
        column: at.column,
        message,
    }
}

/// Where in a scene file: 1-based line and column (0, 0: the file as a whole).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct At {
    line: usize,
    column: usize,
}

/// 1-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> At {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    At { line, column }
}

/// Where `[section]` is written in `text`, or the start.
fn header(text: &str, section: &str) -> At {
    let row = text.lines().position(|l| {
        l.trim()
            .strip_prefix('[')
            .and_then(|l| l.split(']').next())
            .is_some_and(|name| name.trim() == section)
    });
    At {
        line: row.map_or(1, |i| i + 1),
        column: 1,
    }
}

/// Where `key` of `[section]` is written in `text` (line, column), or the section's
/// header, or the start.
fn locate(text: &str, section: Option<&str>, key: &str) -> At {
    let mut in_section = section.is_none();
    let mut found = At { line: 1, column: 1 };
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            in_section = section.is_some_and(|s| trimmed.trim_end() == format!("[{s}]"));
            if in_section {
                found = At {
                    line: i + 1,
                    column: 1,
                };
            }
            continue;
        }
        let name = trimmed.split(['=', ' ']).next().unwrap_or("");
        if in_section && name == key {
            return At {
                line: i + 1,
                column: line.len() - trimmed.len() + 1,
            };
        }
    }
    found
}
