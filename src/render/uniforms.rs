//! What the mesh and fur passes are drawn with: the fur's look and level of detail,
//! the lighting, and their std140 uniform block.

use glam::{Mat4, UVec4, Vec3, Vec4};

use crate::error::{Error, Result};
use crate::scene::Camera;

/// What the geometry stage emits for each hair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Primitive {
    /// Line strips carrying their coverage as alpha for hairs narrower than
    /// [`FurStyle::ribbon_above_px`] at the root, ribbons for the wider ones.
    Auto,
    /// Line strips for every hair.
    Lines,
    /// Camera-facing ribbons of the true width for every hair.
    #[default]
    Ribbons,
}

impl Primitive {
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Lines => "lines",
            Self::Ribbons => "ribbons",
        }
    }
}

impl std::str::FromStr for Primitive {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "auto" => Ok(Self::Auto),
            "lines" => Ok(Self::Lines),
            "ribbons" => Ok(Self::Ribbons),
            _ => Err(format!("expected auto, lines or ribbons, got `{s}`")),
        }
    }
}

/// Where Kajiya–Kay is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Shading {
    /// Per emitted strand vertex, in the geometry stage (colours interpolated).
    #[default]
    Vertex,
    /// Per fragment.
    Fragment,
}

impl Shading {
    pub fn name(self) -> &'static str {
        match self {
            Self::Vertex => "vertex",
            Self::Fragment => "fragment",
        }
    }
}

impl std::str::FromStr for Shading {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "vertex" => Ok(Self::Vertex),
            "fragment" => Ok(Self::Fragment),
            _ => Err(format!("expected vertex or fragment, got `{s}`")),
        }
    }
}

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
    /// Lines, ribbons, or each where it fits.
    pub primitive: Primitive,
    /// With [`Primitive::Auto`], hairs at least this many pixels wide at the root are
    /// drawn as ribbons.
    pub ribbon_above_px: f32,
    /// Per-vertex or per-fragment lighting.
    pub shading: Shading,
    /// Vertex LOD tolerance in pixels: a strand vertex is skipped when the segment
    /// drawn instead passes within this distance of it, width included (0 = draw every
    /// vertex). The root and the tip are always drawn.
    pub vertex_lod_px: f32,
    /// Widen hairs thinned out by the density LOD by the same factor (coverage kept).
    pub thickness_compensation: bool,
    /// Samples per pixel of the render target (1 = no MSAA); the device decides which
    /// counts exist.
    pub samples: u32,
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
            primitive: Primitive::Ribbons,
            ribbon_above_px: 1.0,
            shading: Shading::Vertex,
            vertex_lod_px: 0.05,
            thickness_compensation: true,
            samples: 4,
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
            ("ribbon threshold (px)", self.ribbon_above_px, 1e6),
            ("vertex LOD tolerance (px)", self.vertex_lod_px, 1e6),
        ] {
            if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                return Err(Error::Parameter(format!(
                    "{name} must be in [0, {hi}], got {v}"
                )));
            }
        }
        if !matches!(self.samples, 1 | 2 | 4 | 8 | 16) {
            return Err(Error::Parameter(format!(
                "samples per pixel must be 1, 2, 4, 8 or 16, got {}",
                self.samples
            )));
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

impl Lighting {
    pub fn validate(&self) -> Result<()> {
        if !self.light_direction.is_finite() || self.light_direction.length() < 1e-6 {
            return Err(Error::Parameter(format!(
                "the light direction must be a finite, non-zero vector, got {}",
                self.light_direction
            )));
        }
        for (name, v, hi) in [
            ("light intensity", self.intensity, 1e3),
            ("Kd", self.kd, 1e3),
            ("Ks", self.ks, 1e3),
            ("ambient", self.ambient, 1e3),
            ("root occlusion", self.root_occlusion, 1.0),
        ] {
            if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                return Err(Error::Parameter(format!(
                    "{name} must be in [0, {hi}], got {v}"
                )));
            }
        }
        if !(self.shininess.is_finite() && (1.0..=1e4).contains(&self.shininess)) {
            return Err(Error::Parameter(format!(
                "the specular exponent must be in [1, 10000], got {}",
                self.shininess
            )));
        }
        for (name, c) in [
            ("root colour", self.root_color),
            ("tip colour", self.tip_color),
            ("skin colour", self.skin_color),
        ] {
            if !c.is_finite() || c.min_element() < 0.0 || c.max_element() > 1e3 {
                return Err(Error::Parameter(format!(
                    "{name} must have components in [0, 1000], got {c}"
                )));
            }
        }
        Ok(())
    }
}

/// Kajiya–Kay on the CPU, exactly as `shaders/shading.glsl` evaluates it: `t` the unit tangent, `l`
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

/// What the fur pass needs to know of the master strands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandShape {
    pub vertices_per_strand: u32,
    pub strands_per_row: u32,
}

/// The `Frame` uniform block of `shaders/common.glsl` (std140).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    pub view_proj: Mat4,
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
    pub draw: Vec4,
    pub strands: UVec4,
}

pub const FLAG_CULL: u32 = 1;
pub const FLAG_THICKNESS_COMPENSATION: u32 = 2;
pub const FLAG_COUNT: u32 = 4;

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
    /// Count the hairs and segments the fur pass draws (an atomic per hair; for tests
    /// and reports, off when timing).
    pub count_hairs: bool,
    /// Pixels of the render target per pixel of the image it stands for along each
    /// axis: > 1 for supersampled references, whose hair widths and pixel-based limits
    /// must be those of the final image.
    pub supersample: u32,
}

impl FrameSettings {
    /// World size at distance 1 of a pixel of the image a target `height` pixels tall
    /// stands for (a supersampled target's pixels are `supersample` times smaller).
    pub fn pixel_at_unit_distance(&self, height: u32) -> f32 {
        self.camera.pixel_at_unit_distance(height) * self.supersample.max(1) as f32
    }
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
            count_hairs: false,
            supersample: 1,
        }
    }
}

impl FrameUniforms {
    pub fn new(
        settings: &FrameSettings,
        (width, height): (u32, u32),
        strands: &StrandShape,
        max_level: f32,
    ) -> Self {
        let (w, h) = (width as f32, height as f32);
        let view_proj = settings.camera.view_projection(w / h);
        let pixel_at_unit_distance = settings.pixel_at_unit_distance(height);
        let s = &settings.style;
        let l = &settings.lighting;
        let mut flags = 0;
        if s.cull {
            flags |= FLAG_CULL;
        }
        if s.thickness_compensation {
            flags |= FLAG_THICKNESS_COMPENSATION;
        }
        if settings.count_hairs {
            flags |= FLAG_COUNT;
        }
        let ribbon_above = match s.primitive {
            Primitive::Auto => s.ribbon_above_px,
            Primitive::Lines => f32::MAX,
            Primitive::Ribbons => 0.0,
        };
        Self {
            view_proj,
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
            draw: Vec4::new(ribbon_above, s.vertex_lod_px, 0.0, 0.0),
            strands: UVec4::new(
                strands.vertices_per_strand,
                strands.strands_per_row,
                s.fixed_level.min(max_level as u32),
                flags,
            ),
        }
    }
}
