//! How the fur is drawn: the levers that trade speed for image quality (`fur bench`
//! measures each), their defaults, and the values each accepts, stated once here (the
//! scene's settings take their ranges from these, `scene_file/keys/drawing.rs`).

use super::drawing::{Primitive, Raster, Shading};
use super::std140::std140_struct;
use crate::error::{Error, Result};
use crate::setting::{accessor, Accessor, Flag, Kind, Panel, Setting};
use crate::span::Span;

mod forms;

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
    /// [`MAX_NEAREST`]); the rest are blended behind them as they come, nearly front to
    /// back. More is closer to the true order and costs more (`fur bench --only
    /// raster` measures the trade).
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
            raster: Raster::Compute,
            nearest: 8,
            tile: 0,
        }
    }
}

/// A setting of the drawing style (`[render]` in a scene file).
pub type StyleSetting = Setting<Accessor<FurStyle>>;

/// The style's setting of field `$field`, its other parts placeholders that each
/// definition below overrides.
macro_rules! field {
    ($field:ident) => {
        Setting::reaching(accessor!(FurStyle: $field))
    };
}

/// Every setting of the style, in the order `fur settings` and the docs list them:
/// its key in a scene file's `[render]` section, its flag, its range (from [`spans`]
/// and the lists above), its help and its panel control.
pub const SETTINGS: &[StyleSetting] = &[
    Setting {
        key: "samples",
        flag: Flag::Long("samples"),
        label: "samples per pixel",
        help: "Samples per pixel: 1 (no MSAA; lines then blend their coverage) or an MSAA \
               count the device supports (lavapipe: 1 and 4)",
        kind: Kind::OneOf(&SAMPLE_COUNTS),
        panel: Panel::Plain,
        ..field!(samples)
    },
    Setting {
        key: "raster",
        flag: Flag::Long("raster"),
        label: "strand rasteriser",
        help: "What draws the strands the geometry stage makes: `compute` (compute passes: \
               strands binned to screen tiles, exact coverage, the nearest fragments of each \
               pixel blended front to back; each strand is lit per vertex, by the geometry \
               stage or, under the Marschner model, by a compute pass, so `samples` sets \
               only the body's MSAA, and `primitive` and `shading` do not apply) or \
               `hardware` (the fixed-function rasteriser: lines or ribbons, at `samples` \
               per pixel)",
        kind: Kind::Choice(&["hardware", "compute"]),
        panel: Panel::Plain,
        ..field!(raster)
    },
    Setting {
        key: "nearest",
        flag: Flag::Long("nearest"),
        label: "fragments in order",
        help: "With `raster = \"compute\"`: the fragments each pixel keeps in depth order \
               and blends front to back; the rest are blended behind them as they come, \
               nearly front to back. More is closer to the true order, and costs more",
        kind: Kind::integer(1, MAX_NEAREST),
        panel: Panel::Plain,
        ..field!(nearest)
    },
    Setting {
        key: "tile",
        flag: Flag::Long("tile"),
        label: "tile side (px)",
        help: "With `raster = \"compute\"`: the side of the screen tiles strands are binned \
               to, pixels; 0 takes the default side. A pixel \
               walks its tile's list: a smaller tile lists fewer segments a pixel, and \
               lists each segment in more tiles",
        kind: Kind::OneOf(&TILE_CHOICES),
        panel: Panel::Plain,
        ..field!(tile)
    },
    Setting {
        key: "primitive",
        flag: Flag::Long("primitive"),
        label: "hair primitive",
        help: "What each hair is drawn as: `lines` (coverage in alpha), `ribbons` (true \
               width), or `auto`: ribbons for hairs at least --ribbon-above pixels wide at \
               the root, lines for the rest",
        kind: Kind::Choice(&["ribbons", "lines", "auto"]),
        panel: Panel::Plain,
        ..field!(primitive)
    },
    Setting {
        key: "ribbon_above",
        flag: Flag::Long("ribbon-above"),
        label: "ribbon threshold",
        help: "Root width from which `auto` draws ribbons",
        units: "px",
        kind: Kind::span(spans::PIXELS),
        panel: Panel::slider(0.0, 8.0),
        ..field!(ribbon_above_px)
    },
    Setting {
        key: "shading",
        flag: Flag::Long("shading"),
        label: "shading rate",
        help: "Where the lighting runs: `vertex` (per strand vertex, geometry stage) or \
               `fragment`",
        kind: Kind::Choice(&["vertex", "fragment"]),
        panel: Panel::Plain,
        ..field!(shading)
    },
    Setting {
        key: "vertex_lod",
        flag: Flag::Long("vertex-lod"),
        label: "vertex LOD tolerance",
        help: "Vertex LOD tolerance: a strand vertex is skipped when the segment drawn \
               instead passes within this distance of it, width included; 0 draws every \
               vertex",
        units: "px",
        kind: Kind::span(spans::PIXELS),
        panel: Panel::log_slider(0.0, 2.0),
        ..field!(vertex_lod_px)
    },
    Setting {
        key: "lod_distance",
        flag: Flag::Long("lod-distance"),
        label: "full-density distance",
        help: "Full-density distance: farther away the density falls with the square of \
               the distance",
        units: "bounding radii",
        kind: Kind::span(spans::POSITIVE),
        panel: Panel::log_slider(0.1, 100.0),
        ..field!(lod_distance)
    },
    Setting {
        key: "thickness_compensation",
        flag: Flag::Long("thickness-compensation"),
        label: "thickness compensation",
        help: "Widen hairs the density LOD thins out, so coverage is kept",
        kind: Kind::Bool,
        panel: Panel::Plain,
        ..field!(thickness_compensation)
    },
    Setting {
        key: "hair_width",
        flag: Flag::Long("hair-width"),
        label: "hair width",
        help: "Hair width at the root",
        units: "bounding radii",
        kind: Kind::span(spans::POSITIVE),
        panel: Panel::log_slider(1e-4, 0.05),
        ..field!(hair_width)
    },
    Setting {
        key: "min_pixel_width",
        flag: Flag::Long("min-pixel-width"),
        label: "minimum hair width",
        help: "Hairs are drawn at least this wide; thinner ones cover by their true width \
               (thin-hair AA)",
        units: "px",
        kind: Kind::span(spans::MIN_PIXEL_WIDTH),
        panel: Panel::slider(0.0, 4.0),
        ..field!(min_pixel_width)
    },
    Setting {
        key: "jitter",
        flag: Flag::Long("jitter"),
        label: "jitter",
        help: "Random tip offset of each interpolated hair",
        units: "bounding radii",
        kind: Kind::span(spans::JITTER),
        panel: Panel::slider(0.0, 0.2),
        ..field!(jitter)
    },
    Setting {
        key: "length_jitter",
        flag: Flag::Long("length-jitter"),
        label: "length jitter",
        help: "Random shortening of each interpolated hair, as a fraction of its length",
        kind: Kind::span(spans::LENGTH_JITTER),
        panel: Panel::slider(0.0, 1.0),
        ..field!(length_jitter)
    },
    Setting {
        key: "cull",
        flag: Flag::Long("cull"),
        label: "culling",
        help: "Skip triangles facing away or off screen before tessellating them",
        kind: Kind::Bool,
        panel: Panel::Plain,
        ..field!(cull)
    },
    Setting {
        key: "cull_margin",
        flag: Flag::Long("cull-margin"),
        label: "cull margin",
        help: "How far a triangle may face away before its hairs are culled: culled when \
               cos(normal, view) < −margin; hairs on triangles just past the silhouette \
               still show, so 0 loses them and 1 culls by the screen's bounds only",
        kind: Kind::span(spans::CULL_MARGIN),
        panel: Panel::slider(0.0, 1.0),
        ..field!(cull_margin)
    },
    Setting {
        key: "thin_hair_aa",
        flag: Flag::Long("thin-hair-aa"),
        label: "thin-hair anti-aliasing",
        help: "Hairs thinner than the minimum width cover their pixels by their true width \
               (a dithered sample mask under MSAA, blending at 1 sample)",
        kind: Kind::Bool,
        panel: Panel::Plain,
        ..field!(thin_hair_aa)
    },
];

impl FurStyle {
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

/// The drawing block's flags by the names the shaders know them by (defined for every
/// render shader, `super::uniforms::shader_defines`).
pub const DRAWING_FLAGS: [(&str, u32); 4] = [
    ("FLAG_CULL", FLAG_CULL),
    ("FLAG_THICKNESS_COMPENSATION", FLAG_THICKNESS_COMPENSATION),
    ("FLAG_COUNT", FLAG_COUNT),
    ("FLAG_THIN_HAIR_AA", FLAG_THIN_HAIR_AA),
];

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
