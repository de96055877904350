//! What the mesh and fur passes are drawn with: the fur's look and level of detail,
//! the lighting, and the defines every render shader shares with Rust (the uniform
//! block they become is `frame_block.rs`).

use glam::Mat4;

pub use super::drawing::{Primitive, Raster, Shading};
use super::lighting::Lighting;
pub use super::stage::Stage;
pub use super::style::{FurStyle, DEFAULT_TILE, MAX_NEAREST, TILE_SIZES};
use crate::scene::Camera;

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

/// An interpolated hair's random tip offset ([`FurStyle::jitter`]) is at most this
/// fraction of the hair's own reach from root to tip (`fur.geom`), so the short hair of
/// a thin part is not scattered into a tuft.
pub const JITTER_SHARE: f32 = 0.25;

/// What the render shaders share with Rust, given to every one of them as `#define`s
/// so no constant is typed twice: the drawing's and the lighting's flags, the most hair
/// layers counted in front of a point (`MAX_LAYERS`), and the compute rasteriser's
/// depth bins and opacity to stop at.
pub fn shader_defines() -> Vec<(&'static str, String)> {
    super::style::DRAWING_FLAGS
        .into_iter()
        .chain(super::frame_block::LIGHTING_FLAGS)
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
            ("ROW_RUN", super::strand_raster::order::ROW_RUN.to_string()),
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
