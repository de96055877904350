//! TOML scene files: a look saved, shared and versioned. A [`Scene`] is everything a run
//! draws (model, groom, camera, lighting, drawing, simulation, collision, motion, image
//! size); a [`SceneFile`] holds any part of it, every key optional. A run starts from
//! the model's defaults, applies the file, then the command line's flags.
//!
//! Unknown keys (a typo), wrong types and out-of-range values are errors naming the
//! file, the line and column, and the key.

use std::path::{Path, PathBuf};

use glam::Vec3;

mod checks;
mod sections;

use checks::checks;
pub use sections::*;

use crate::error::{Error, Result};
use crate::render::{LightingModel, Primitive, Shading};
use crate::scene::{ModelSpec, TextureSpec};
use crate::session::SceneOptions;
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

    /// The scene as a file holding every key.
    pub fn to_file(&self) -> SceneFile {
        let o = &self.options;
        let d = &o.draw;
        let l = &o.lighting;
        let s = &self.sim;
        SceneFile {
            model: Some(self.model.name()),
            texture: o.texture.as_ref().map(TextureSpec::name),
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
                thin_hair_aa: Some(d.thin_hair_aa),
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
                secondary_highlight: Some(l.highlights.secondary),
                primary_shift: Some(l.highlights.primary_shift_deg),
                secondary_shift: Some(l.highlights.secondary_shift_deg),
                secondary_shininess: Some(l.highlights.secondary_shininess),
                secondary_strength: Some(l.highlights.secondary_strength),
                lighting_model: Some(l.model.name().into()),
            }),
            fibre: Some(FibreSection {
                longitudinal_roughness: Some(l.fibre.longitudinal_roughness),
                azimuthal_roughness: Some(l.fibre.azimuthal_roughness),
                cuticle_tilt: Some(l.fibre.cuticle_tilt_deg),
                ior: Some(l.fibre.ior),
            }),
            shadows: Some(ShadowsSection {
                enabled: Some(l.shadows.enabled),
                resolution: Some(l.shadows.resolution),
                opacity: Some(l.shadows.opacity),
                spacing: Some(l.shadows.spacing),
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
                skin_blend: s.skin_blend,
            }),
            motion: Some(MotionSection {
                kind: Some(self.motion.kind.name().into()),
                amplitude: Some(self.motion.amplitude),
                rate: Some(self.motion.rate),
            }),
            animation: Some(AnimationSection {
                clip: self.animation.clip.clone(),
                speed: Some(self.animation.speed),
                start: Some(self.animation.start),
                looping: Some(self.animation.looping),
                in_place: Some(self.animation.in_place),
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
        crate::files::write_output(path, text.as_bytes(), "write the scene file")
    }
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
        let text =
            crate::files::read_text_bounded(path, crate::files::MAX_SCENE_BYTES, "scene file")
                .map_err(|e| Error::SceneFile {
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

    /// A texture the file names, a path resolved against the file's folder.
    fn texture_spec(name: &str, path: &Path) -> TextureSpec {
        match name.parse::<TextureSpec>() {
            Ok(TextureSpec::File(p)) if p.is_relative() => {
                TextureSpec::File(path.parent().unwrap_or(Path::new(".")).join(p))
            }
            Ok(spec) => spec,
            Err(_) => TextureSpec::File(PathBuf::from(name)),
        }
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
            set(&mut d.thin_hair_aa, s.thin_hair_aa);
        }
        if let Some(t) = &self.texture {
            o.texture = Some(Self::texture_spec(t, path));
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
            let h = &mut l.highlights;
            set(&mut h.secondary, s.secondary_highlight);
            set(&mut h.primary_shift_deg, s.primary_shift);
            set(&mut h.secondary_shift_deg, s.secondary_shift);
            set(&mut h.secondary_shininess, s.secondary_shininess);
            set(&mut h.secondary_strength, s.secondary_strength);
            if let Some(m) = &s.lighting_model {
                l.model = m
                    .parse::<LightingModel>()
                    .map_err(|e| fail(Some("light"), "lighting_model", e))?;
            }
        }
        if let Some(s) = &self.fibre {
            let f = &mut o.lighting.fibre;
            set(&mut f.longitudinal_roughness, s.longitudinal_roughness);
            set(&mut f.azimuthal_roughness, s.azimuthal_roughness);
            set(&mut f.cuticle_tilt_deg, s.cuticle_tilt);
            set(&mut f.ior, s.ior);
        }
        if let Some(s) = &self.shadows {
            let d = &mut o.lighting.shadows;
            set(&mut d.enabled, s.enabled);
            set(&mut d.resolution, s.resolution);
            set(&mut d.opacity, s.opacity);
            set(&mut d.spacing, s.spacing);
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
            set(&mut p.skin_blend, s.skin_blend.map(Some));
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
        if let Some(s) = &self.animation {
            let a = &mut scene.animation;
            if s.clip.is_some() {
                a.clip = s.clip.clone();
            }
            set(&mut a.speed, s.speed);
            set(&mut a.start, s.start);
            set(&mut a.looping, s.looping);
            set(&mut a.in_place, s.in_place);
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
