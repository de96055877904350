//! What a scene asks for, relative to the model's size ([`SceneOptions`]).

use crate::error::Error;
use crate::error::Result;
use crate::render::{FrameSettings, FurStyle, Lighting, LightingModel};
use crate::scene::{Camera, GroomParams, Mesh, Rig, TextureSpec};
use crate::skinning::Playback;

/// A scene described relative to the model's size, so one set of defaults suits any
/// model: lengths are fractions of the bounding radius.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptions {
    /// Hair length as a fraction of the bounding radius.
    pub hair_length: f32,
    pub segments: u32,
    pub comb: f32,
    pub curl: f32,
    /// Hairs at most this many times the local half-thickness long (0 = off).
    pub thickness_limit: f32,
    /// How grown fur is combed, and where a body's flow starts.
    pub flow: crate::scene::Flow,
    pub flow_from: crate::scene::FlowFrom,
    pub yaw_deg: f32,
    pub pitch_deg: f32,
    /// Camera distance in bounding radii; `None` frames the whole model, hair included,
    /// in the vertical field of view.
    pub distance: Option<f32>,
    /// Vertical field of view, degrees.
    pub fov_deg: f32,
    /// How the fur is drawn, measured on the model: lengths in bounding radii, the
    /// density per square bounding radius (the `density_scale` setting is its ratio to
    /// [`crate::render::style::DENSITY`]).
    pub draw: FurStyle,
    /// Lighting; the shadows' spacing is in bounding radii here (0 = the hair spacing).
    pub lighting: crate::render::Lighting,
    /// The colour texture, over the model's own (its OBJ material's map_Kd).
    pub texture: Option<TextureSpec>,
    /// The stage of the pipeline the image shows.
    pub show: crate::render::Stage,
    /// The simulation view's arrows: which step, magnified how many times.
    pub arrows: crate::render::stage::Arrows,
    pub arrow_scale: f32,
    /// A groom file (guide curves) the master hairs are made from; `None` grows them.
    pub groom_file: Option<String>,
    /// What vertices outside the groom file's region get.
    pub groom_outside: crate::scene::Outside,
    /// How the groom file's guides are drawn.
    pub groom_mode: crate::scene::GroomMode,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self {
            hair_length: 0.2,
            segments: 16,
            comb: 2.0,
            curl: 0.0,
            thickness_limit: 0.6,
            flow: crate::scene::Flow::Body,
            flow_from: crate::scene::FlowFrom::Auto,
            yaw_deg: 25.0,
            pitch_deg: 15.0,
            distance: None,
            fov_deg: 40.0,
            draw: FurStyle::default(),
            lighting: crate::render::Lighting::default(),
            texture: None,
            show: crate::render::Stage::Lit,
            arrows: crate::render::stage::Arrows::None,
            arrow_scale: 10.0,
            groom_file: None,
            groom_outside: crate::scene::Outside::Bald,
            groom_mode: crate::scene::GroomMode::Blend,
        }
    }
}

/// The vertical fields of view a scene accepts, degrees.
pub const FOV_DEG: crate::span::Span = crate::span::Span::within(1.0, 170.0);

/// Bounding radius of the original demo's sphere ([`crate::scene::ModelSpec::Sphere`]),
/// the half-diagonal of its 4 × 4 × 4 box.
const SPHERE_BOUNDS: f32 = 3.464_101_6;

impl SceneOptions {
    /// The original fur demo's scene on its sphere: master hairs of 12 vertices with
    /// segments of 0.05 along the normals, seen from the side of the poles' axis through
    /// the original's camera (the eye 10 units from the sphere's centre, a 45° vertical
    /// field of view; at its 1280×720 the same pixels). The density gives the whole
    /// sphere as many interpolated hairs as the original's tessellation levels
    /// (⌊350 · area⌋ per triangle) give it distinct points, within 1 %
    /// (`tests/render_levers.rs` counts both). It is lit by the original's model,
    /// Kajiya–Kay, where every other model's default is the Marschner model.
    pub fn original() -> Self {
        Self {
            hair_length: 0.55 / SPHERE_BOUNDS,
            segments: 11,
            comb: 0.0,
            curl: 0.0,
            thickness_limit: 0.0,
            draw: FurStyle {
                // Tuned: the original's 35,129 hairs (docs/testing.md, "Tuned constants").
                density: 0.33 * crate::render::style::DENSITY,
                ..FurStyle::default()
            },
            yaw_deg: 90.0,
            pitch_deg: 15.0,
            distance: Some(10.0 / SPHERE_BOUNDS),
            fov_deg: 45.0,
            // The original's model: its frame rate is measured against this scene's.
            lighting: Lighting {
                model: LightingModel::KajiyaKay,
                ..Lighting::default()
            },
            ..Self::default()
        }
    }

    /// The camera distance that frames `mesh` with its hair: its farthest vertex from the
    /// box centre plus the hair length fills 90 % of the vertical field of view, from
    /// any direction.
    pub fn framing_distance(&self, mesh: &Mesh) -> f32 {
        let (centre, radius) = mesh.bounds();
        let reach = mesh
            .positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0f32, f32::max)
            + self.hair_length * radius;
        reach / ((0.5 * self.fov_deg).to_radians().sin() * 0.9)
    }

    /// Moves the camera of `settings` (made by [`SceneOptions::resolve`] for `mesh`) so
    /// it frames every pose the first `frames` frames of `playback` take: the bounds of
    /// the skinned body over them, plus the hair.
    pub fn frame_poses(
        &self,
        settings: &mut FrameSettings,
        mesh: &Mesh,
        rig: &Rig,
        playback: &Playback,
        frames: u32,
    ) {
        let dt = 1.0 / 60.0;
        let samples = frames.clamp(1, 32);
        let mut positions = Vec::new();
        for k in 0..samples {
            let t = f64::from(frames.max(1) - 1) * dt * f64::from(k) / f64::from(samples);
            let matrices = playback.joint_matrices(rig, t);
            positions.extend(rig.skin(&matrices, &[]).0);
        }
        let envelope = Mesh {
            positions,
            ..mesh.clone()
        };
        let (centre, _) = envelope.bounds();
        let (_, rest_radius) = mesh.bounds();
        settings.camera.target = centre;
        let reach = envelope
            .positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0f32, f32::max)
            + self.hair_length * rest_radius;
        settings.camera.distance = reach / ((0.5 * self.fov_deg).to_radians().sin() * 0.9);
    }

    /// The defaults for a model: the original scene for the built-in sphere, the
    /// general defaults otherwise.
    pub fn for_model(model: &crate::scene::ModelSpec) -> Self {
        match model {
            crate::scene::ModelSpec::Sphere => Self::original(),
            _ => Self::default(),
        }
    }

    /// The groom and frame settings for `mesh`.
    pub fn resolve(&self, mesh: &Mesh) -> Result<(GroomParams, FrameSettings)> {
        for (name, v) in [
            ("hair length", self.hair_length),
            ("camera distance", self.distance.unwrap_or(1.0)),
        ] {
            crate::span::Span::positive().require(name, v)?;
        }
        if self.groom_mode == crate::scene::GroomMode::Draw && self.groom_file.is_none() {
            return Err(Error::Parameter(
                "groom mode `draw` draws the guides of a groom file: give one (--groom FILE, \
                 or `file` under [groom])"
                    .into(),
            ));
        }
        FOV_DEG.require("field of view (degrees)", self.fov_deg)?;
        self.lighting.validate()?;
        let (center, radius) = mesh.bounds();
        let groom = GroomParams {
            segments: self.segments,
            segment_length: self.hair_length * radius / self.segments.max(1) as f32,
            comb_strength: self.comb,
            thickness_limit: self.thickness_limit,
            flow: self.flow,
            flow_from: self.flow_from,
            curl: self.curl,
            source: self.groom_file.as_ref().map(|f| crate::scene::GroomSource {
                path: f.into(),
                outside: self.groom_outside,
                mode: self.groom_mode,
            }),
            ..Default::default()
        };
        let mut settings = FrameSettings {
            camera: Camera {
                target: center,
                yaw_deg: self.yaw_deg,
                pitch_deg: self.pitch_deg,
                distance: match self.distance {
                    Some(d) => d * radius,
                    None => self.framing_distance(mesh),
                },
                fov_y_deg: self.fov_deg,
            },
            lighting: self.lighting.clone(),
            ..Default::default()
        };
        if let Some(c) = self
            .lighting
            .preset
            .colour(self.lighting.fibre.azimuthal_roughness)
        {
            settings.lighting.root_color = c;
            settings.lighting.tip_color = c;
        }
        // Density and lengths are measured on the model; scale them with it.
        self.draw.validate()?;
        settings.style = self.draw.on_model(radius);
        settings.lighting.shadows.spacing *= radius;
        settings.show = self.show;
        settings.arrows = self.arrows;
        settings.arrow_scale = self.arrow_scale;
        groom.validate()?;
        Ok((groom, settings))
    }
}
