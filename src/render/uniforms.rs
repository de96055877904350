//! What the mesh and fur passes are drawn with: the fur's look and level of detail,
//! the lighting, and their std140 uniform block.

use glam::{Mat4, UVec4, Vec3, Vec4};

use crate::error::{Error, Result};
use crate::scene::Camera;

/// How the fur is generated and drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct FurStyle {
    /// Interpolated hairs per square scene unit at full density.
    pub density: f32,
    /// Closer than this the fur is drawn at full density; farther, density falls as 1/d².
    pub lod_distance: f32,
    /// Hair width at the root in scene units (tapers to 20 % at the tip).
    pub hair_width: f32,
    /// Hairs are never drawn thinner than this many pixels.
    pub min_pixel_width: f32,
    /// Random tip offset of each interpolated hair, scene units.
    pub jitter: f32,
    /// Interpolated hairs are shortened by up to this fraction, at random.
    pub length_jitter: f32,
    /// Skip back-facing and off-screen triangles.
    pub cull: bool,
    /// A triangle counts as back-facing when cos(normal, view) < -cull_margin.
    pub cull_margin: f32,
    /// Use this tessellation level everywhere instead of the adaptive one (0 = adaptive).
    pub fixed_level: u32,
}

impl Default for FurStyle {
    fn default() -> Self {
        Self {
            density: 12_000.0,
            lod_distance: 6.0,
            hair_width: 0.004,
            min_pixel_width: 0.75,
            jitter: 0.02,
            length_jitter: 0.25,
            cull: true,
            cull_margin: 0.3,
            fixed_level: 0,
        }
    }
}

impl FurStyle {
    pub fn validate(&self) -> Result<()> {
        let positive = [
            ("density", self.density),
            ("LOD distance", self.lod_distance),
            ("hair width", self.hair_width),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::Parameter(format!(
                    "{name} must be positive and finite, got {v}"
                )));
            }
        }
        for (name, v, hi) in [
            ("minimum pixel width", self.min_pixel_width, 64.0),
            ("jitter", self.jitter, f32::MAX),
            ("length jitter", self.length_jitter, 1.0),
            ("cull margin", self.cull_margin, 1.0),
        ] {
            if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                return Err(Error::Parameter(format!(
                    "{name} must be in [0, {hi}], got {v}"
                )));
            }
        }
        Ok(())
    }
}

/// Light and material.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Direction towards the light (normalised when used).
    pub light_direction: Vec3,
    pub intensity: f32,
    /// Kajiya–Kay diffuse coefficient K_d.
    pub kd: f32,
    /// Kajiya–Kay specular coefficient K_s.
    pub ks: f32,
    /// Specular exponent p.
    pub shininess: f32,
    pub ambient: f32,
    pub root_color: Vec3,
    pub tip_color: Vec3,
    pub skin_color: Vec3,
    /// How much darker hair is at the root than at the tip, 0..1 (cheap self-shadowing).
    pub root_occlusion: f32,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            light_direction: Vec3::new(0.5, 0.8, 0.6),
            intensity: 1.0,
            kd: 0.8,
            ks: 0.35,
            shininess: 40.0,
            ambient: 0.12,
            root_color: Vec3::new(0.16, 0.08, 0.035),
            tip_color: Vec3::new(0.85, 0.6, 0.35),
            skin_color: Vec3::new(0.12, 0.07, 0.05),
            root_occlusion: 0.6,
        }
    }
}

/// Kajiya–Kay on the CPU, exactly as `fur.frag` evaluates it: `t` the unit tangent, `l`
/// the unit direction towards the light, `e` the unit direction from the eye to the
/// point. Returns (diffuse, specular) before colour and intensity.
pub fn kajiya_kay(t: Vec3, l: Vec3, e: Vec3, kd: f32, ks: f32, p: f32) -> (f32, f32) {
    let (tl, te) = (t.dot(l), t.dot(e));
    let sin_tl = (1.0 - tl * tl).max(0.0).sqrt();
    let sin_te = (1.0 - te * te).max(0.0).sqrt();
    (
        kd * sin_tl,
        ks * (tl * te + sin_tl * sin_te).max(0.0).powf(p),
    )
}

/// The `Frame` uniform block of `shaders/common.glsl` (std140).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    pub view_proj: Mat4,
    pub inv_view_proj: Mat4,
    pub model: Mat4,
    pub eye: Vec4,
    pub light: Vec4,
    pub root_color: Vec4,
    pub tip_color: Vec4,
    pub skin_color: Vec4,
    pub shading: Vec4,
    pub lod: Vec4,
    pub hair: Vec4,
    pub viewport: Vec4,
    pub strands: UVec4,
}

pub const FLAG_CULL: u32 = 1;

/// Everything one frame is drawn with.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSettings {
    pub camera: Camera,
    pub style: FurStyle,
    pub lighting: Lighting,
    /// Head transform H (model to world) of the mesh pass.
    pub head: Mat4,
    pub draw_mesh: bool,
    pub draw_fur: bool,
}

impl Default for FrameSettings {
    fn default() -> Self {
        Self {
            camera: Camera::default(),
            style: FurStyle::default(),
            lighting: Lighting::default(),
            head: Mat4::IDENTITY,
            draw_mesh: true,
            draw_fur: true,
        }
    }
}

impl FrameUniforms {
    pub fn new(
        settings: &FrameSettings,
        width: u32,
        height: u32,
        vertices_per_strand: u32,
        strands_per_row: u32,
        max_level: f32,
    ) -> Self {
        let (w, h) = (width as f32, height as f32);
        let view_proj = settings.camera.view_projection(w / h);
        let pixel_at_unit_distance = 2.0 * (settings.camera.fov_y_deg.to_radians() * 0.5).tan() / h;
        let s = &settings.style;
        let l = &settings.lighting;
        Self {
            view_proj,
            inv_view_proj: view_proj.inverse(),
            model: settings.head,
            eye: settings.camera.eye().extend(pixel_at_unit_distance),
            light: l.light_direction.normalize_or(Vec3::Y).extend(l.intensity),
            root_color: l.root_color.extend(l.root_occlusion),
            tip_color: l.tip_color.extend(1.0),
            skin_color: l.skin_color.extend(1.0),
            shading: Vec4::new(l.kd, l.ks, l.shininess, l.ambient),
            lod: Vec4::new(s.density, s.lod_distance, max_level, s.cull_margin),
            hair: Vec4::new(s.hair_width, s.min_pixel_width, s.jitter, s.length_jitter),
            viewport: Vec4::new(w, h, 1.0 / w, 1.0 / h),
            strands: UVec4::new(
                vertices_per_strand,
                strands_per_row,
                s.fixed_level.min(max_level as u32),
                if s.cull { FLAG_CULL } else { 0 },
            ),
        }
    }
}
