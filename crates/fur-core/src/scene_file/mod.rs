//! A scene and its settings. A [`Scene`] is everything a run draws (model, groom,
//! camera, lighting, drawing, simulation, collision, motion, image size). Each of its
//! settings is defined once, in `keys/` ([`Setting`]: key, flag, type, range, units,
//! help, panel); from those definitions come the command line's flags
//! (the application's `SettingArgs`), the TOML scene files ([`SceneFile`]: a look saved, shared and
//! versioned, every key optional), the viewer's panel and `fur settings`. A run
//! starts from the model's defaults, applies the file, then the command line's flags.
//!
//! Unknown keys (a typo), wrong types and out-of-range values are errors naming the
//! file, the line and column, and the key.

use std::path::Path;

use glam::Vec3;

pub mod docs;
mod file;
mod keys;
mod options;
mod setting;
mod value;

pub use crate::setting::{list, Effect, FieldValue, Flag, Kind, Panel, Value};
pub use file::SceneFile;
pub use keys::GROUPS;
pub use options::{SceneOptions, FOV_DEG};
pub use setting::{Access, Group, Setting};

use crate::error::Result;
use crate::scene::ModelSpec;
use crate::sim::{Motion, MotionKind, SimParams};

/// Everything a run draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub model: ModelSpec,
    pub options: SceneOptions,
    pub sim: SimParams,
    pub motion: MotionSpec,
    /// Which clip a skinned or animated model plays.
    pub animation: crate::skinning::AnimationSpec,
    pub width: u32,
    pub height: u32,
}

/// Scripted head motion, its amplitude relative to the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionSpec {
    pub kind: MotionKind,
    /// Fraction of the bounding radius for shake, degrees for nod.
    pub amplitude: f64,
    /// Hz for shake and nod, turns per second for spin.
    pub rate: f64,
}

impl MotionSpec {
    /// The head motion on a model of bounding radius `radius`.
    pub fn motion(&self, radius: f32) -> Motion {
        Motion {
            kind: self.kind,
            amplitude: match self.kind {
                MotionKind::Shake => self.amplitude * f64::from(radius),
                _ => self.amplitude,
            },
            rate: self.rate,
        }
    }
}

impl Default for MotionSpec {
    /// A shake by a quarter of the bounding radius, once a second.
    fn default() -> Self {
        Self {
            kind: MotionKind::Shake,
            amplitude: 0.25,
            rate: 1.0,
        }
    }
}

impl Scene {
    /// The defaults for `model` (the original demo's scene for the built-in sphere).
    pub fn defaults(model: ModelSpec) -> Self {
        Self {
            options: SceneOptions::for_model(&model),
            model,
            sim: Self::default_sim(),
            motion: MotionSpec::default(),
            animation: Default::default(),
            width: 1280,
            height: 720,
        }
    }

    /// The simulation a scene runs unless told otherwise: the solver's defaults in a
    /// steady wind.
    pub fn default_sim() -> SimParams {
        SimParams {
            wind: Vec3::new(6.0, 0.0, 2.0),
            ..SimParams::default()
        }
    }

    /// The scene a run draws before its command-line options: `model` (else the file's
    /// model, else the blob) with its defaults, then the scene file at `path`, if any.
    pub fn load(path: Option<&Path>, model: Option<ModelSpec>) -> Result<Self> {
        let file = path.map(SceneFile::load).transpose()?;
        let model = model
            .or_else(|| file.as_ref().and_then(|(f, _)| f.model(path?)))
            .unwrap_or_default();
        let mut scene = Self::defaults(model);
        if let (Some((file, text)), Some(path)) = (&file, path) {
            file.apply(&mut scene, path, text)?;
        }
        Ok(scene)
    }

    /// Writes the scene as TOML (every key), for `fur render SCENE` to reproduce.
    pub fn save(&self, path: &Path) -> Result<()> {
        let text = format!(
            "# fur scene: `fur render {}` draws it\n\n{}",
            path.display(),
            file::to_toml(self)?
        );
        crate::files::write_output(path, text.as_bytes(), "write the scene file")
    }
}
