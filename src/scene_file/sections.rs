//! The sections and keys of a scene file (TOML): every key optional.

use serde::{Deserialize, Serialize};

/// A scene file: any part of a [`Scene`](super::Scene).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// `blob`, `sphere`, or an OBJ path relative to the scene file.
    pub model: Option<String>,
    /// `tabby`, or an image path relative to the scene file (over the model's own).
    pub texture: Option<String>,
    pub image: Option<ImageSection>,
    pub camera: Option<CameraSection>,
    pub groom: Option<GroomSection>,
    pub render: Option<RenderSection>,
    pub light: Option<LightSection>,
    pub fibre: Option<FibreSection>,
    pub shadows: Option<ShadowsSection>,
    pub simulation: Option<SimulationSection>,
    pub collision: Option<CollisionSection>,
    pub motion: Option<MotionSection>,
    pub animation: Option<AnimationSection>,
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
    pub thin_hair_aa: Option<bool>,
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
    pub secondary_highlight: Option<bool>,
    /// Degrees, positive toward the tip.
    pub primary_shift: Option<f32>,
    pub secondary_shift: Option<f32>,
    pub secondary_shininess: Option<f32>,
    pub secondary_strength: Option<f32>,
    /// `kajiya-kay` or `marschner`.
    pub lighting_model: Option<String>,
}

/// The hair fibre's physical parameters (Chiang et al. 2016), which the path-traced
/// reference (`fur export-frame`, `tools/reference`) takes with the hair colour.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FibreSection {
    /// β_m, 0.01..1.
    pub longitudinal_roughness: Option<f32>,
    /// β_n, 0.01..1.
    pub azimuthal_roughness: Option<f32>,
    /// The cuticle scales' tilt α in degrees, −10..10.
    pub cuticle_tilt: Option<f32>,
    /// Index of refraction η, 1..3.
    pub ior: Option<f32>,
}

/// Self-shadowing; the spacing in bounding radii (0 = the hair spacing).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShadowsSection {
    pub enabled: Option<bool>,
    pub resolution: Option<u32>,
    pub opacity: Option<f32>,
    pub spacing: Option<f32>,
}

/// Units as [`SimParams`](crate::sim::SimParams): seconds, m/s², degrees.
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
    pub skin_blend: Option<bool>,
}

/// `kind`: still, shake, spin or nod.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSection {
    pub kind: Option<String>,
    pub amplitude: Option<f64>,
    pub rate: Option<f64>,
}

/// A skinned or animated model's clip: `clip` by name (any case; `none` = rest pose),
/// `speed` in clip seconds per second, `start` in seconds, `loop`, `in_place` (root
/// motion removed).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationSection {
    pub clip: Option<String>,
    pub speed: Option<f32>,
    pub start: Option<f32>,
    #[serde(rename = "loop")]
    pub looping: Option<bool>,
    pub in_place: Option<bool>,
}
