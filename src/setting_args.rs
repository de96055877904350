//! Every setting as a command-line flag: `fur render`, `fur view` and `fur
//! export-frame` flatten [`SettingArgs`], whose flags, help (with the range and the
//! defaults) and headings come from the core's definitions
//! (`crates/fur-core/src/scene_file/keys/`).

use clap::builder::{BoolishValueParser, PossibleValuesParser};
use clap::{Arg, ArgAction, ArgMatches, Command};
use glam::Vec3;

use fur_core::error::{Error, Result};
use fur_core::scene::ModelSpec;
use fur_core::scene_file::{Flag, Kind, Scene, Setting, Value, GROUPS};

/// The settings given on the command line, applied over the scene file's.
#[derive(Clone, Debug, Default)]
pub struct SettingArgs {
    given: Vec<(&'static Setting, Given)>,
}

#[derive(Clone, Debug)]
enum Given {
    Text(String),
    Bool(bool),
}

impl SettingArgs {
    /// Sets what the command line gives onto `scene`; a value of the wrong form or out
    /// of range is an error naming the flag and the setting.
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        for (setting, given) in &self.given {
            let flag = setting.flag.name();
            let fail = |message: String| {
                Error::Parameter(format!("`--{flag}` ({}) {message}", setting.label))
            };
            let value = match given {
                Given::Bool(b) => Value::Bool(*b),
                Given::Text(t) => parse(setting.kind, t).map_err(fail)?,
            };
            setting.check(&value).map_err(fail)?;
            setting.set(scene, value);
        }
        Ok(())
    }

    /// Whether the command line gave the setting of flag `--flag`.
    pub fn gives(&self, flag: &str) -> bool {
        self.given.iter().any(|(s, _)| s.flag.name() == flag)
    }
}

/// The setting named `section.key`, as a scene file writes it (`render.raster`).
pub fn find_setting(name: &str) -> Option<&'static Setting> {
    let (section, key) = name.split_once('.')?;
    GROUPS
        .iter()
        .find(|g| g.section == section)
        .and_then(|g| g.settings.iter().find(|s| s.key == key))
}

/// The setting `section.key` (as a scene file writes it: `render.raster`) and `text`
/// as its value, checked against its range: for the viewer's scripted `set=` events.
pub fn setting_value(name: &str, text: &str) -> Result<(&'static Setting, Value)> {
    let Some(setting) = find_setting(name) else {
        return Err(Error::Parameter(format!(
            "no setting `{name}`: settings are named as in a scene file, SECTION.KEY \
             (render.raster, light.lighting_model; docs/scene-files.md lists them)"
        )));
    };
    let fail =
        |message: String| Error::Parameter(format!("`{name}` ({}) {message}", setting.label));
    let value = match setting.kind {
        Kind::Bool => match text.trim() {
            "on" | "true" => Value::Bool(true),
            "off" | "false" => Value::Bool(false),
            _ => return Err(fail(format!("expected on or off, got `{text}`"))),
        },
        kind => parse(kind, text).map_err(fail)?,
    };
    setting.check(&value).map_err(fail)?;
    Ok((setting, value))
}

/// A command-line value of `kind`.
fn parse(kind: Kind, text: &str) -> std::result::Result<Value, String> {
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("expected a number, got `{t}`"))
    };
    match kind {
        Kind::Number { .. } => number(text).map(Value::Number),
        Kind::Integer { .. } | Kind::OneOf(_) => text
            .trim()
            .parse::<u32>()
            .map(Value::Integer)
            .map_err(|_| format!("expected a whole number, got `{text}`")),
        Kind::Bool => Err("expected on or off".into()),
        Kind::Choice(_) | Kind::Text | Kind::Place => Ok(Value::Text(text.to_string())),
        Kind::Vector { .. } | Kind::Colour { .. } => {
            let down = matches!(kind, Kind::Vector { down: true, .. });
            let parts: Vec<&str> = text.split(',').collect();
            match parts[..] {
                [g] if down => Ok(Value::Vector(Vec3::new(0.0, -(number(g)? as f32), 0.0))),
                [x, y, z] => Ok(Value::Vector(Vec3::new(
                    number(x)? as f32,
                    number(y)? as f32,
                    number(z)? as f32,
                ))),
                _ => Err(format!("expected {}, got `{text}`", kind.wanted())),
            }
        }
    }
}

fn every_setting() -> impl Iterator<Item = (&'static str, &'static Setting)> {
    GROUPS
        .iter()
        .flat_map(|g| g.settings.iter().map(move |s| (g.heading, s)))
}

impl clap::FromArgMatches for SettingArgs {
    fn from_arg_matches(matches: &ArgMatches) -> std::result::Result<Self, clap::Error> {
        let mut args = Self::default();
        args.update_from_arg_matches(matches)?;
        Ok(args)
    }

    fn update_from_arg_matches(
        &mut self,
        matches: &ArgMatches,
    ) -> std::result::Result<(), clap::Error> {
        for (_, setting) in every_setting() {
            let id = setting.flag.name();
            let given = match (setting.flag, setting.kind) {
                (Flag::Switch(_, value), _) => matches
                    .try_get_one::<bool>(id)
                    .ok()
                    .flatten()
                    .filter(|on| **on)
                    .map(|_| Given::Bool(value)),
                (Flag::Long(_), Kind::Bool) => matches
                    .try_get_one::<bool>(id)
                    .ok()
                    .flatten()
                    .map(|b| Given::Bool(*b)),
                (Flag::Long(_), _) => matches
                    .try_get_one::<String>(id)
                    .ok()
                    .flatten()
                    .map(|t| Given::Text(t.clone())),
            };
            if let Some(given) = given {
                self.given.retain(|(s, _)| !std::ptr::eq(*s, setting));
                self.given.push((setting, given));
            }
        }
        Ok(())
    }
}

impl clap::Args for SettingArgs {
    fn augment_args(mut cmd: Command) -> Command {
        let blob = Scene::defaults(ModelSpec::Blob);
        let sphere = Scene::defaults(ModelSpec::Sphere);
        for (heading, setting) in every_setting() {
            let name = setting.flag.name();
            let mut arg = Arg::new(name)
                .long(name)
                .help(setting.help_text(&blob, &sphere))
                .help_heading(heading);
            arg = match (setting.flag, setting.kind) {
                (Flag::Switch(..), _) => arg.action(ArgAction::SetTrue),
                (Flag::Long(_), Kind::Bool) => arg
                    .value_parser(BoolishValueParser::new())
                    .value_name("on|off")
                    .hide_possible_values(true),
                (Flag::Long(_), Kind::Choice(names)) => arg
                    .value_parser(PossibleValuesParser::new(names.iter().copied()))
                    .value_name(name.to_uppercase().replace('-', "_")),
                (Flag::Long(_), Kind::Number { .. } | Kind::Integer { .. } | Kind::OneOf(_)) => arg
                    .allow_negative_numbers(true)
                    .value_name(name.to_uppercase().replace('-', "_")),
                (Flag::Long(_), Kind::Vector { .. } | Kind::Colour { .. }) => {
                    arg.allow_hyphen_values(true).value_name("X,Y,Z")
                }
                (Flag::Long(_), Kind::Place) => {
                    arg.allow_hyphen_values(true).value_name("auto|±AXIS|X,Y,Z")
                }
                (Flag::Long(_), Kind::Text) => arg
                    .allow_hyphen_values(true)
                    .value_name(name.to_uppercase().replace('-', "_")),
            };
            cmd = cmd.arg(arg);
        }
        cmd
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}
