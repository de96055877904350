//! How the fur is drawn: the levers that trade speed for image quality (`fur bench`
//! measures each), their defaults, and the values each accepts, stated once here (the
//! scene's settings take their ranges from these, `scene_file/keys/drawing.rs`).

use super::drawing::{Primitive, Raster, Shading};
use super::std140::std140_struct;
use crate::error::{Error, Result};
use crate::span::Span;

/// How the fur is generated and drawn. A frame's style ([`super::FrameSettings::style`])
/// is in scene units; a scene's ([`crate::scene_file::SceneOptions::draw`]) is measured
/// on the model, so one set of defaults suits any model: its lengths in bounding radii
/// and its density per square bounding radius, which [`FurStyle::on_model`] scales to
/// a model's size. The two are the same numbers on a model of bounding radius 1.
#[derive(Clone, Debug, PartialEq)]
pub struct FurStyle {
    /// Interpolated hairs per square scene unit at full density ([`DENSITY`] by
    /// default).
    pub density: f32,
    /// Closer than this the fur is drawn at full density; farther, density falls as 1/d².
    pub lod_distance: f32,
    /// Hair width at the root in scene units (tapers to 20 % at the tip).
    pub hair_width: f32,
    /// Hairs are never drawn thinner than this many pixels.
    pub min_pixel_width: f32,
    /// Random tip offset of each interpolated hair, scene units (at most
    /// [`JITTER_SHARE`](super::uniforms::JITTER_SHARE) of the hair's own reach).
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
    /// Thin-hair anti-aliasing: a hair drawn wider than it is (at least
    /// [`FurStyle::min_pixel_width`]) covers its pixels only by its true width (alpha:
    /// blended at one sample per pixel, a dithered sample mask under MSAA), so sub-pixel
    /// hairs neither vanish between samples nor darken the image more than they should.
    /// Off: they are drawn opaque at the minimum width.
    pub thin_hair_aa: bool,
    /// Samples per pixel of the render target (1 = no MSAA); the device decides which
    /// counts exist.
    pub samples: u32,
    /// What draws the strands.
    pub raster: Raster,
    /// With `Raster::Compute`: the fragments each pixel keeps in depth order (1 to
    /// [`MAX_NEAREST`]); the rest are blended in an order-free tail. More is closer to
    /// the true order and costs more (`fur bench --only raster` measures the trade).
    pub nearest: u32,
    /// With `Raster::Compute`: the side of the screen tiles the strands are binned to,
    /// pixels (one of [`TILE_SIZES`]), or 0 for the default ([`DEFAULT_TILE`]).
    pub tile: u32,
}

/// Interpolated hairs per square scene unit at full density, by default (the scene's
/// `density_scale` multiplies it).
pub const DENSITY: f32 = 12_000.0;

/// The tile sides the compute rasteriser draws with, pixels.
pub const TILE_SIZES: [u32; 4] = [2, 4, 8, 16];

/// What [`FurStyle::tile`] accepts: 0 (the device's) or one of [`TILE_SIZES`].
pub const TILE_CHOICES: [u32; TILE_SIZES.len() + 1] = {
    let mut choices = [0; TILE_SIZES.len() + 1];
    let mut i = 0;
    while i < TILE_SIZES.len() {
        choices[i + 1] = TILE_SIZES[i];
        i += 1;
    }
    choices
};

/// The sample counts a render target may have ([`FurStyle::samples`]); the device
/// decides which of them exist.
pub const SAMPLE_COUNTS: [u32; 5] = [1, 2, 4, 8, 16];

/// The most fragments a pixel of the compute rasteriser keeps in depth order.
pub const MAX_NEAREST: u32 = 16;

/// The values each number of a [`FurStyle`] accepts.
pub mod spans {
    use crate::span::Span;

    /// Density, full-density distance, hair width.
    pub const POSITIVE: Span = Span::positive();
    pub const MIN_PIXEL_WIDTH: Span = Span::within(0.0, 64.0);
    pub const JITTER: Span = Span::non_negative();
    pub const LENGTH_JITTER: Span = Span::within(0.0, 1.0);
    pub const CULL_MARGIN: Span = Span::within(0.0, 1.0);
    /// Pixels: the ribbon threshold and the vertex LOD's tolerance.
    pub const PIXELS: Span = Span::within(0.0, 1e6);
}

/// The compute rasteriser's tile side unless a style sets one, pixels: on a GPU a
/// tile's workgroup of 64 pixels fills two warps, and on a CPU driver, where a pixel
/// finds the entries that reach it by their masks, a larger tile lists each segment in
/// fewer tiles (`fur bench --only raster` measures the other sides).
pub const DEFAULT_TILE: u32 = 8;

impl Default for FurStyle {
    fn default() -> Self {
        Self {
            density: DENSITY,
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
            // Tuned, as is `min_pixel_width` (docs/testing.md, "Tuned constants").
            vertex_lod_px: 0.05,
            thickness_compensation: true,
            thin_hair_aa: true,
            samples: 4,
            raster: Raster::Hardware,
            nearest: 8,
            tile: 0,
        }
    }
}

impl FurStyle {
    /// This style, measured on the model (lengths in bounding radii, density per
    /// square bounding radius), on a model of bounding radius `radius`: in scene units.
    pub fn on_model(&self, radius: f32) -> Self {
        Self {
            density: self.density / (radius * radius),
            lod_distance: self.lod_distance * radius,
            hair_width: self.hair_width * radius,
            jitter: self.jitter * radius,
            ..self.clone()
        }
    }

    /// The inverse of [`FurStyle::on_model`]: this style, in scene units, measured on a
    /// model of bounding radius `radius`.
    pub fn per_radius(&self, radius: f32) -> Self {
        Self {
            density: self.density * radius * radius,
            lod_distance: self.lod_distance / radius,
            hair_width: self.hair_width / radius,
            jitter: self.jitter / radius,
            ..self.clone()
        }
    }

    /// This style at reference quality: 4× MSAA ribbons lit per fragment, every strand
    /// vertex drawn (density, widths, jitter and culling kept).
    pub fn reference_quality(&self) -> Self {
        Self {
            samples: 4,
            primitive: Primitive::Ribbons,
            shading: Shading::Fragment,
            vertex_lod_px: 0.0,
            ..self.clone()
        }
    }

    /// The compute rasteriser's tile side this style draws with, pixels: its own, or
    /// the default ([`DEFAULT_TILE`]).
    pub fn tile_side(&self) -> u32 {
        match self.tile {
            0 => DEFAULT_TILE,
            side => side,
        }
    }

    /// Checks every value against what it accepts ([`spans`], [`TILE_CHOICES`],
    /// [`SAMPLE_COUNTS`], [`MAX_NEAREST`]).
    pub fn validate(&self) -> Result<()> {
        let numbers: [(&str, f32, Span); 9] = [
            ("density", self.density, spans::POSITIVE),
            ("LOD distance", self.lod_distance, spans::POSITIVE),
            ("hair width", self.hair_width, spans::POSITIVE),
            (
                "minimum pixel width",
                self.min_pixel_width,
                spans::MIN_PIXEL_WIDTH,
            ),
            ("jitter", self.jitter, spans::JITTER),
            ("length jitter", self.length_jitter, spans::LENGTH_JITTER),
            ("cull margin", self.cull_margin, spans::CULL_MARGIN),
            ("ribbon threshold (px)", self.ribbon_above_px, spans::PIXELS),
            (
                "vertex LOD tolerance (px)",
                self.vertex_lod_px,
                spans::PIXELS,
            ),
        ];
        for (name, v, span) in numbers {
            span.require(name, v)?;
        }
        if !(1..=MAX_NEAREST).contains(&self.nearest) {
            return Err(Error::Parameter(format!(
                "fragments kept in depth order must be 1 to {MAX_NEAREST}, got {}",
                self.nearest
            )));
        }
        if !TILE_CHOICES.contains(&self.tile) {
            return Err(Error::Parameter(format!(
                "the tile side must be 0 (the device's) or one of {TILE_SIZES:?} pixels, got {}",
                self.tile
            )));
        }
        if !SAMPLE_COUNTS.contains(&self.samples) {
            return Err(Error::Parameter(format!(
                "samples per pixel must be one of {SAMPLE_COUNTS:?}, got {}",
                self.samples
            )));
        }
        Ok(())
    }
}

/// The flags of [`DrawingBlock::flags`].
pub const FLAG_CULL: u32 = 1;
pub const FLAG_THICKNESS_COMPENSATION: u32 = 2;
pub const FLAG_COUNT: u32 = 4;
pub const FLAG_THIN_HAIR_AA: u32 = 16;

std140_struct! {
    /// How dense, wide and detailed the fur pass draws (`Drawing` in GLSL): the style as
    /// the shaders read it, each value written once, by [`FurStyle::drawing`].
    pub struct DrawingBlock("Drawing") {
        /// Hairs per unit area at full density.
        pub density: f32,
        /// Closer than this the fur is drawn at full density.
        pub lod_distance: f32,
        /// The device's largest tessellation level.
        pub max_level: f32,
        /// A triangle is back-facing when cos(normal, view) < −cull_margin.
        pub cull_margin: f32,
        /// Hair width at the root, scene units.
        pub hair_width: f32,
        pub min_pixel_width: f32,
        /// Random tip offset of each interpolated hair, scene units.
        pub jitter: f32,
        pub length_jitter: f32,
        /// Hairs at least this many pixels wide at the root are drawn as ribbons.
        pub ribbon_above_px: f32,
        /// Vertex LOD tolerance, pixels (0: every vertex).
        pub vertex_lod_px: f32,
        /// The texels of the fur's texture (0: none), for its level of detail.
        pub texels: f32,
        /// How many times their length the simulation view's arrows are drawn.
        pub arrow_scale: f32,
        /// The tessellation level everywhere (0: adaptive).
        pub fixed_level: u32,
        /// [`FLAG_CULL`], [`FLAG_THICKNESS_COMPENSATION`], [`FLAG_COUNT`], [`FLAG_THIN_HAIR_AA`].
        pub flags: u32,
        pub _pad: [u32; 2],
    }
}

/// What the drawing block takes besides the style.
#[derive(Clone, Copy, Debug)]
pub struct DrawingInputs {
    /// The device's largest tessellation level.
    pub max_level: f32,
    /// The texels of the fur's texture (0: none).
    pub texels: f32,
    /// How many times their length the simulation view's arrows are drawn.
    pub arrow_scale: f32,
    /// Whether the fur pass counts the hairs it draws ([`FLAG_COUNT`]).
    pub count_hairs: bool,
}

impl FurStyle {
    /// This style as the shaders read it (`frame.drawing`).
    pub fn drawing(&self, inputs: DrawingInputs) -> DrawingBlock {
        let mut flags = 0;
        for (on, flag) in [
            (self.cull, FLAG_CULL),
            (self.thickness_compensation, FLAG_THICKNESS_COMPENSATION),
            (inputs.count_hairs, FLAG_COUNT),
            (self.thin_hair_aa, FLAG_THIN_HAIR_AA),
        ] {
            if on {
                flags |= flag;
            }
        }
        let ribbon_above_px = match self.primitive {
            Primitive::Auto => self.ribbon_above_px,
            Primitive::Lines => f32::MAX,
            Primitive::Ribbons => 0.0,
        };
        DrawingBlock {
            density: self.density,
            lod_distance: self.lod_distance,
            max_level: inputs.max_level,
            cull_margin: self.cull_margin,
            hair_width: self.hair_width,
            min_pixel_width: self.min_pixel_width,
            jitter: self.jitter,
            length_jitter: self.length_jitter,
            ribbon_above_px,
            vertex_lod_px: self.vertex_lod_px,
            texels: inputs.texels,
            arrow_scale: inputs.arrow_scale,
            fixed_level: self.fixed_level.min(inputs.max_level as u32),
            flags,
            _pad: [0; 2],
        }
    }
}
