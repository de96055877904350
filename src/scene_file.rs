//! TOML scene files: a look saved, shared and versioned. A [`Scene`] is everything a run
//! draws (model, groom, camera, lighting, drawing, simulation, collision, motion, image
//! size); a [`SceneFile`] holds any part of it, every key optional. A run starts from
//! the model's defaults, applies the file, then the command line's flags.
//!
//! Unknown keys (a typo), wrong types and out-of-range values are errors naming the
//! file, the line and column, and the key.

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::render::{Primitive, Shading};
use crate::scene::ModelSpec;
use crate::session::SceneOptions;
use crate::sim::{Motion, MotionKind, SimParams};

/// Everything a run draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub model: ModelSpec,
    pub options: SceneOptions,
    pub sim: SimParams,
    pub motion: MotionSpec,
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

    /// The scene as a file holding every key.
    pub fn to_file(&self) -> SceneFile {
        let o = &self.options;
        let d = &o.draw;
        let l = &o.lighting;
        let s = &self.sim;
        SceneFile {
            model: Some(self.model.name()),
            image: Some(ImageSection {
                width: Some(self.width),
                height: Some(self.height),
            }),
            camera: Some(CameraSection {
                yaw: Some(o.yaw_deg),
                pitch: Some(o.pitch_deg),
                distance: o.distance,
                fov: Some(o.fov_deg),
            }),
            groom: Some(GroomSection {
                hair_length: Some(o.hair_length),
                segments: Some(o.segments),
                density_scale: Some(o.density_scale),
                comb: Some(o.comb),
                curl: Some(o.curl),
                thickness_limit: Some(o.thickness_limit),
            }),
            render: Some(RenderSection {
                samples: Some(d.samples),
                primitive: Some(d.primitive.name().into()),
                ribbon_above: Some(d.ribbon_above_px),
                shading: Some(d.shading.name().into()),
                vertex_lod: Some(d.vertex_lod_px),
                lod_distance: Some(d.lod_distance),
                thickness_compensation: Some(d.thickness_compensation),
                hair_width: Some(d.hair_width),
                min_pixel_width: Some(d.min_pixel_width),
                jitter: Some(d.jitter),
                length_jitter: Some(d.length_jitter),
                cull: Some(d.cull),
            }),
            light: Some(LightSection {
                direction: Some(l.light_direction.to_array()),
                intensity: Some(l.intensity),
                kd: Some(l.kd),
                ks: Some(l.ks),
                shininess: Some(l.shininess),
                ambient: Some(l.ambient),
                root_color: Some(l.root_color.to_array()),
                tip_color: Some(l.tip_color.to_array()),
                skin_color: Some(l.skin_color.to_array()),
                root_occlusion: Some(l.root_occlusion),
            }),
            simulation: Some(SimulationSection {
                dt: Some(s.dt),
                substeps: Some(s.substeps),
                gravity: Some(s.gravity.to_array()),
                damping: Some(s.damping),
                global_stiffness: Some(s.global_stiffness),
                global_range: Some(s.global_range),
                local_stiffness: Some(s.local_stiffness),
                local_iterations: Some(s.local_iterations),
                length_iterations: Some(s.length_iterations),
                wind: Some(s.wind.to_array()),
                wind_cone: Some(s.wind_cone_deg),
            }),
            collision: Some(CollisionSection {
                enabled: Some(s.collision),
                margin: Some(s.collision_margin),
                friction: Some(s.friction),
                sdf_resolution: Some(s.sdf_resolution),
            }),
            motion: Some(MotionSection {
                kind: Some(self.motion.kind.name().into()),
                amplitude: Some(self.motion.amplitude),
                rate: Some(self.motion.rate),
            }),
        }
    }

    /// Writes the scene as TOML (every key), for `fur render SCENE` to reproduce.
    pub fn save(&self, path: &Path) -> Result<()> {
        let text = toml::to_string_pretty(&self.to_file())
            .map_err(|e| Error::Parameter(format!("cannot encode the scene: {e}")))?;
        let text = format!(
            "# fur scene: `fur render {}` draws it\n\n{text}",
            path.display()
        );
        std::fs::write(path, text).map_err(|e| Error::io("write the scene file", path, e))
    }
}

/// A scene file: any part of a [`Scene`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// `blob`, `sphere`, or an OBJ path relative to the scene file.
    pub model: Option<String>,
    pub image: Option<ImageSection>,
    pub camera: Option<CameraSection>,
    pub groom: Option<GroomSection>,
    pub render: Option<RenderSection>,
    pub light: Option<LightSection>,
    pub simulation: Option<SimulationSection>,
    pub collision: Option<CollisionSection>,
    pub motion: Option<MotionSection>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImageSection {
    pub width: Option<u32>,
    pub height: Option<u32>,
}

/// Angles in degrees, the distance in bounding radii.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSection {
    pub yaw: Option<f32>,
    pub pitch: Option<f32>,
    pub distance: Option<f32>,
    pub fov: Option<f32>,
}

/// The hair length in bounding radii.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroomSection {
    pub hair_length: Option<f32>,
    pub segments: Option<u32>,
    pub density_scale: Option<f32>,
    pub comb: Option<f32>,
    pub curl: Option<f32>,
    /// Hairs at most this many times the local half-thickness long (0 = off).
    pub thickness_limit: Option<f32>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderSection {
    pub samples: Option<u32>,
    pub primitive: Option<String>,
    pub ribbon_above: Option<f32>,
    pub shading: Option<String>,
    pub vertex_lod: Option<f32>,
    pub lod_distance: Option<f32>,
    pub thickness_compensation: Option<bool>,
    /// In bounding radii, like `jitter`.
    pub hair_width: Option<f32>,
    pub min_pixel_width: Option<f32>,
    pub jitter: Option<f32>,
    pub length_jitter: Option<f32>,
    pub cull: Option<bool>,
}

/// Colours are linear RGB triples; the direction points towards the light.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSection {
    pub direction: Option<[f32; 3]>,
    pub intensity: Option<f32>,
    pub kd: Option<f32>,
    pub ks: Option<f32>,
    pub shininess: Option<f32>,
    pub ambient: Option<f32>,
    pub root_color: Option<[f32; 3]>,
    pub tip_color: Option<[f32; 3]>,
    pub skin_color: Option<[f32; 3]>,
    pub root_occlusion: Option<f32>,
}

/// Units as [`SimParams`]: seconds, m/s², degrees.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSection {
    pub dt: Option<f32>,
    pub substeps: Option<u32>,
    pub gravity: Option<[f32; 3]>,
    pub damping: Option<f32>,
    pub global_stiffness: Option<f32>,
    pub global_range: Option<f32>,
    pub local_stiffness: Option<f32>,
    pub local_iterations: Option<u32>,
    pub length_iterations: Option<u32>,
    pub wind: Option<[f32; 3]>,
    pub wind_cone: Option<f32>,
}

/// The margin is a fraction of the hair length.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CollisionSection {
    pub enabled: Option<bool>,
    pub margin: Option<f32>,
    pub friction: Option<f32>,
    pub sdf_resolution: Option<u32>,
}

/// `kind`: still, shake, spin or nod.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSection {
    pub kind: Option<String>,
    pub amplitude: Option<f64>,
    pub rate: Option<f64>,
}

/// 1-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// The `section.key` written on 1-based `line` of `text`, if that line holds a key.
fn key_at(text: &str, line: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let here = lines.get(line.checked_sub(1)?)?.trim();
    let key = here.split('=').next()?.trim();
    if here.starts_with('[') || !here.contains('=') || key.is_empty() {
        return None;
    }
    let section = lines[..line - 1]
        .iter()
        .rev()
        .map(|l| l.trim())
        .find(|l| l.starts_with('['))
        .map(|l| l.trim_matches(|c| c == '[' || c == ']').trim().to_string());
    Some(match section {
        Some(section) => format!("{section}.{key}"),
        None => key.to_string(),
    })
}

/// Where `key` of `[section]` is written in `text` (line, column), or the section's
/// header, or the start.
fn locate(text: &str, section: Option<&str>, key: &str) -> (usize, usize) {
    let mut in_section = section.is_none();
    let mut header = (1, 1);
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            in_section = section.is_some_and(|s| trimmed.trim_end() == format!("[{s}]"));
            if in_section {
                header = (i + 1, 1);
            }
            continue;
        }
        let name = trimmed.split(['=', ' ']).next().unwrap_or("");
        if in_section && name == key {
            return (i + 1, line.len() - trimmed.len() + 1);
        }
    }
    header
}

impl SceneFile {
    /// Reads and parses a scene file; syntax, type and unknown-key errors name the file,
    /// line, column and key.
    pub fn load(path: &Path) -> Result<(Self, String)> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::SceneFile {
            path: path.to_path_buf(),
            line: 0,
            column: 0,
            message: format!("cannot read it: {e}"),
        })?;
        let file = toml::from_str(&text).map_err(|e: toml::de::Error| {
            let (line, column) = e.span().map_or((0, 0), |s| line_column(&text, s.start));
            let message = match key_at(&text, line) {
                Some(key) if !e.message().contains(&key) => {
                    format!("`{key}`: {}", e.message().trim())
                }
                _ => e.message().trim().to_string(),
            };
            Error::SceneFile {
                path: path.to_path_buf(),
                line,
                column,
                message,
            }
        })?;
        Ok((file, text))
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

    /// Applies every key the file sets onto `scene`, then checks the result; an
    /// out-of-range value is an error naming the file, line and key (`text` is the
    /// file's contents, `path` its name).
    pub fn apply(&self, scene: &mut Scene, path: &Path, text: &str) -> Result<()> {
        let fail = |section: Option<&str>, key: &str, message: String| {
            let (line, column) = locate(text, section, key);
            let name = section.map_or(key.to_string(), |s| format!("{s}.{key}"));
            Error::SceneFile {
                path: path.to_path_buf(),
                line,
                column,
                message: format!("`{name}`: {message}"),
            }
        };
        let o = &mut scene.options;
        if let Some(s) = &self.image {
            set(&mut scene.width, s.width);
            set(&mut scene.height, s.height);
        }
        if let Some(s) = &self.camera {
            set(&mut o.yaw_deg, s.yaw);
            set(&mut o.pitch_deg, s.pitch);
            if s.distance.is_some() {
                o.distance = s.distance;
            }
            set(&mut o.fov_deg, s.fov);
        }
        if let Some(s) = &self.groom {
            set(&mut o.hair_length, s.hair_length);
            set(&mut o.segments, s.segments);
            set(&mut o.density_scale, s.density_scale);
            set(&mut o.comb, s.comb);
            set(&mut o.curl, s.curl);
            set(&mut o.thickness_limit, s.thickness_limit);
        }
        if let Some(s) = &self.render {
            let d = &mut o.draw;
            set(&mut d.samples, s.samples);
            if let Some(p) = &s.primitive {
                d.primitive = p
                    .parse::<Primitive>()
                    .map_err(|e| fail(Some("render"), "primitive", e))?;
            }
            set(&mut d.ribbon_above_px, s.ribbon_above);
            if let Some(v) = &s.shading {
                d.shading = v
                    .parse::<Shading>()
                    .map_err(|e| fail(Some("render"), "shading", e))?;
            }
            set(&mut d.vertex_lod_px, s.vertex_lod);
            set(&mut d.lod_distance, s.lod_distance);
            set(&mut d.thickness_compensation, s.thickness_compensation);
            set(&mut d.hair_width, s.hair_width);
            set(&mut d.min_pixel_width, s.min_pixel_width);
            set(&mut d.jitter, s.jitter);
            set(&mut d.length_jitter, s.length_jitter);
            set(&mut d.cull, s.cull);
        }
        if let Some(s) = &self.light {
            let l = &mut o.lighting;
            set(&mut l.light_direction, s.direction.map(Vec3::from_array));
            set(&mut l.intensity, s.intensity);
            set(&mut l.kd, s.kd);
            set(&mut l.ks, s.ks);
            set(&mut l.shininess, s.shininess);
            set(&mut l.ambient, s.ambient);
            set(&mut l.root_color, s.root_color.map(Vec3::from_array));
            set(&mut l.tip_color, s.tip_color.map(Vec3::from_array));
            set(&mut l.skin_color, s.skin_color.map(Vec3::from_array));
            set(&mut l.root_occlusion, s.root_occlusion);
        }
        let p = &mut scene.sim;
        if let Some(s) = &self.simulation {
            set(&mut p.dt, s.dt);
            set(&mut p.substeps, s.substeps);
            set(&mut p.gravity, s.gravity.map(Vec3::from_array));
            set(&mut p.damping, s.damping);
            set(&mut p.global_stiffness, s.global_stiffness);
            set(&mut p.global_range, s.global_range);
            set(&mut p.local_stiffness, s.local_stiffness);
            set(&mut p.local_iterations, s.local_iterations);
            set(&mut p.length_iterations, s.length_iterations);
            set(&mut p.wind, s.wind.map(Vec3::from_array));
            set(&mut p.wind_cone_deg, s.wind_cone);
        }
        if let Some(s) = &self.collision {
            set(&mut p.collision, s.enabled);
            set(&mut p.collision_margin, s.margin);
            set(&mut p.friction, s.friction);
            set(&mut p.sdf_resolution, s.sdf_resolution);
        }
        if let Some(s) = &self.motion {
            if let Some(k) = &s.kind {
                scene.motion.kind = k
                    .parse::<MotionKind>()
                    .map_err(|e| fail(Some("motion"), "kind", e))?;
            }
            set(&mut scene.motion.amplitude, s.amplitude);
            set(&mut scene.motion.rate, s.rate);
        }
        // Out-of-range values, each traced back to the key that set it.
        for (section, key, check) in checks(scene) {
            if let Err(message) = check {
                return Err(fail(Some(section), key, message));
            }
        }
        Ok(())
    }
}

fn set<T>(field: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *field = v;
    }
}

/// Every range a scene's values must lie in, by section and key.
fn checks(scene: &Scene) -> Vec<(&'static str, &'static str, std::result::Result<(), String>)> {
    let o = &scene.options;
    let positive = |v: f32| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(format!("must be a positive number, got {v}"))
        }
    };
    let within = |v: f32, lo: f32, hi: f32| {
        if v.is_finite() && (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(format!("must be in [{lo}, {hi}], got {v}"))
        }
    };
    let image = |v: u32| {
        if (1..=16384).contains(&v) {
            Ok(())
        } else {
            Err(format!("must be 1..=16384 pixels, got {v}"))
        }
    };
    let mut out = vec![
        ("image", "width", image(scene.width)),
        ("image", "height", image(scene.height)),
        ("camera", "yaw", within(o.yaw_deg, -1e6, 1e6)),
        ("camera", "pitch", within(o.pitch_deg, -1e6, 1e6)),
        ("camera", "distance", positive(o.distance.unwrap_or(1.0))),
        ("camera", "fov", within(o.fov_deg, 1.0, 170.0)),
        ("groom", "hair_length", positive(o.hair_length)),
        (
            "groom",
            "segments",
            if (1..=63).contains(&o.segments) {
                Ok(())
            } else {
                Err(format!("must be 1..=63, got {}", o.segments))
            },
        ),
        ("groom", "density_scale", positive(o.density_scale)),
        ("groom", "comb", within(o.comb, 0.0, 1e3)),
        ("groom", "curl", within(o.curl, 0.0, 1e3)),
        (
            "groom",
            "thickness_limit",
            within(o.thickness_limit, 0.0, 1e3),
        ),
        (
            "render",
            "samples",
            if matches!(o.draw.samples, 1 | 2 | 4 | 8 | 16) {
                Ok(())
            } else {
                Err(format!("must be 1, 2, 4, 8 or 16, got {}", o.draw.samples))
            },
        ),
        (
            "render",
            "ribbon_above",
            within(o.draw.ribbon_above_px, 0.0, 1e6),
        ),
        (
            "render",
            "vertex_lod",
            within(o.draw.vertex_lod_px, 0.0, 1e6),
        ),
        ("render", "lod_distance", positive(o.draw.lod_distance)),
        ("render", "hair_width", positive(o.draw.hair_width)),
        (
            "render",
            "min_pixel_width",
            within(o.draw.min_pixel_width, 0.0, 64.0),
        ),
        ("render", "jitter", within(o.draw.jitter, 0.0, 1e3)),
        (
            "render",
            "length_jitter",
            within(o.draw.length_jitter, 0.0, 1.0),
        ),
    ];
    let light = o.lighting.validate().map_err(|e| e.to_string());
    out.push(("light", light_key(&light), light));
    let sim = scene.sim.validate().map_err(|e| e.to_string());
    out.push((sim_section(&sim), sim_key(&sim), sim));
    let motion = if scene.motion.amplitude.is_finite() && scene.motion.rate.is_finite() {
        if scene.motion.rate >= 0.0 {
            Ok(())
        } else {
            Err(format!("must be ≥ 0, got {}", scene.motion.rate))
        }
    } else {
        Err("amplitude and rate must be finite".to_string())
    };
    out.push(("motion", "rate", motion));
    out
}

/// The key a lighting error is about, from its message.
fn light_key(error: &std::result::Result<(), String>) -> &'static str {
    let Err(message) = error else { return "" };
    [
        ("direction", "direction"),
        ("intensity", "intensity"),
        ("Kd", "kd"),
        ("Ks", "ks"),
        ("ambient", "ambient"),
        ("root occlusion", "root_occlusion"),
        ("exponent", "shininess"),
        ("root colour", "root_color"),
        ("tip colour", "tip_color"),
        ("skin colour", "skin_color"),
    ]
    .iter()
    .find(|(needle, _)| message.contains(needle))
    .map_or("", |(_, key)| key)
}

const SIM_KEYS: [(&str, &str, &str); 15] = [
    ("dt", "simulation", "dt"),
    ("substeps", "simulation", "substeps"),
    ("gravity", "simulation", "gravity"),
    ("damping", "simulation", "damping"),
    ("global stiffness", "simulation", "global_stiffness"),
    ("global range", "simulation", "global_range"),
    ("local stiffness", "simulation", "local_stiffness"),
    ("local iterations", "simulation", "local_iterations"),
    ("length iterations", "simulation", "length_iterations"),
    ("wind cone", "simulation", "wind_cone"),
    ("wind", "simulation", "wind"),
    ("collision margin", "collision", "margin"),
    ("friction", "collision", "friction"),
    ("resolution", "collision", "sdf_resolution"),
    ("collision", "collision", "enabled"),
];

fn sim_entry(error: &std::result::Result<(), String>) -> Option<(&'static str, &'static str)> {
    let Err(message) = error else { return None };
    SIM_KEYS
        .iter()
        .find(|(needle, _, _)| message.contains(needle))
        .map(|(_, section, key)| (*section, *key))
}

fn sim_section(error: &std::result::Result<(), String>) -> &'static str {
    sim_entry(error).map_or("simulation", |e| e.0)
}

fn sim_key(error: &std::result::Result<(), String>) -> &'static str {
    sim_entry(error).map_or("", |e| e.1)
}
