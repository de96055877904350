//! What the mesh and fur passes are drawn with: the fur's look and level of detail,
//! the lighting, and the defines every render shader shares with Rust (the uniform
//! block they become is `frame_block.rs`).

use glam::Mat4;

pub use super::drawing::{Primitive, Raster, Shading};
use super::lighting::Lighting;
pub use super::stage::Stage;
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
    /// Random tip offset of each interpolated hair, scene units (at most
    /// [`JITTER_SHARE`] of the hair's own reach).
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
    /// pixels (one of [`TILE_SIZES`]), or 0 for the device's ([`default_tile`]).
    pub tile: u32,
}

/// The tile sides the compute rasteriser draws with, pixels.
pub const TILE_SIZES: [u32; 4] = [2, 4, 8, 16];

/// The compute rasteriser's tile side on a device, pixels: 4 on a CPU driver, where a
/// pixel's walk of its tile's list is the cost and a smaller tile lists fewer segments
/// per pixel, and 8 on a GPU, whose workgroup of a tile's pixels fills two warps
/// (`fur bench --only raster` measures the other sides).
pub fn default_tile(cpu_driver: bool) -> u32 {
    if cpu_driver {
        4
    } else {
        8
    }
}

/// The most fragments a pixel of the compute rasteriser keeps in depth order.
pub const MAX_NEAREST: u32 = 16;

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
    /// The compute rasteriser's tile side this style draws with on a CPU driver
    /// (`cpu_driver`) or a GPU, pixels: its own, or the device's ([`default_tile`]).
    pub fn tile_on(&self, cpu_driver: bool) -> u32 {
        match self.tile {
            0 => default_tile(cpu_driver),
            side => side,
        }
    }

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
        if !(1..=MAX_NEAREST).contains(&self.nearest) {
            return Err(Error::Parameter(format!(
                "fragments kept in depth order must be 1 to {MAX_NEAREST}, got {}",
                self.nearest
            )));
        }
        if self.tile != 0 && !TILE_SIZES.contains(&self.tile) {
            return Err(Error::Parameter(format!(
                "the tile side must be 0 (the device's) or one of {TILE_SIZES:?} pixels, got {}",
                self.tile
            )));
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

/// What the fur pass needs to know of the master strands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandShape {
    pub vertices_per_strand: u32,
    pub strands_per_row: u32,
    /// A master hair whose tip is closer than this to its root is a bald stub (a
    /// groom's bald region, [`crate::scene::BALD_FRACTION`]); a triangle whose three
    /// masters are all stubs draws nothing. Scene units; 0: none is.
    pub stub_length: f32,
    /// The coat's mean height above the skin, scene units
    /// ([`crate::scene::Strands::coat_height`]): under the Marschner model without a
    /// shadow map, the skin beneath is lit through that many hair layers.
    pub coat_height: f32,
}

/// The stub length of [`StrandShape`] as a fraction of the longest master hair: twice
/// a bald vertex's stub ([`crate::scene::BALD_FRACTION`] of the guides' median
/// length), so every stub is below it while hairs a thousandth of the longest and more
/// are drawn.
pub const STUB_LIMIT: f32 = 2.0 * crate::scene::BALD_FRACTION;

pub use super::frame_block::{
    FLAG_COUNT, FLAG_CULL, FLAG_NO_COAT, FLAG_NO_MULTIPLE, FLAG_NO_R, FLAG_NO_TRT, FLAG_NO_TT,
    FLAG_SECONDARY_HIGHLIGHT, FLAG_THICKNESS_COMPENSATION, FLAG_THIN_HAIR_AA,
};

/// An interpolated hair's random tip offset ([`FurStyle::jitter`]) is at most this
/// fraction of the hair's own reach from root to tip (`fur.geom`), so the short hair of
/// a thin part is not scattered into a tuft.
pub const JITTER_SHARE: f32 = 0.25;

/// What the render shaders share with Rust, given to every one of them as `#define`s
/// so no constant is typed twice: the drawing's and the lighting's flags, the most hair
/// layers counted in front of a point (`MAX_LAYERS`), and the compute rasteriser's
/// depth bins and opacity to stop at.
pub fn shader_defines() -> Vec<(&'static str, String)> {
    [
        ("FLAG_CULL", FLAG_CULL),
        ("FLAG_THICKNESS_COMPENSATION", FLAG_THICKNESS_COMPENSATION),
        ("FLAG_COUNT", FLAG_COUNT),
        ("FLAG_SECONDARY_HIGHLIGHT", FLAG_SECONDARY_HIGHLIGHT),
        ("FLAG_THIN_HAIR_AA", FLAG_THIN_HAIR_AA),
        ("FLAG_NO_R", FLAG_NO_R),
        ("FLAG_NO_TT", FLAG_NO_TT),
        ("FLAG_NO_TRT", FLAG_NO_TRT),
        ("FLAG_NO_MULTIPLE", FLAG_NO_MULTIPLE),
        ("FLAG_NO_COAT", FLAG_NO_COAT),
    ]
    .into_iter()
    .map(|(name, bit)| (name, format!("{bit}u")))
    .chain([
        ("MAX_LAYERS", format!("{:?}", super::marschner::MAX_LAYERS)),
        (
            "DS_ANGLE_NODES",
            super::dual_scattering::ANGLE_NODES.to_string(),
        ),
        (
            "DS_COLOUR_NODES",
            super::dual_scattering::COLOUR_NODES.to_string(),
        ),
        (
            "DS_NODE_VEC4S",
            super::dual_scattering::NODE_VEC4S.to_string(),
        ),
        (
            "DEPTH_BINS",
            super::strand_raster::order::DEPTH_BINS.to_string(),
        ),
        (
            "OPAQUE_TRANSMIT",
            format!("{:?}", super::strand_raster::order::OPAQUE_TRANSMIT),
        ),
        ("JITTER_SHARE", format!("{:?}", JITTER_SHARE)),
        (
            "DS_DENSITY_FORWARD",
            format!("{:?}", super::dual_scattering::DENSITY_FORWARD),
        ),
        (
            "DS_DENSITY_BACKWARD",
            format!("{:?}", super::dual_scattering::DENSITY_BACKWARD),
        ),
    ])
    .chain(super::stage::stage_defines())
    .collect()
}

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
    /// The stage the image shows.
    pub show: Stage,
    /// In the simulation view, the step whose corrections are drawn as arrows, and how
    /// many times their length they are drawn.
    pub arrows: super::stage::Arrows,
    pub arrow_scale: f32,
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
            show: Stage::Lit,
            arrows: super::stage::Arrows::None,
            arrow_scale: 10.0,
            count_hairs: false,
            supersample: 1,
        }
    }
}
