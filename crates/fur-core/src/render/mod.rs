//! What a frame is drawn with, without the device: the drawing's settings and the
//! uniform block they become, the lighting models and their CPU twins, images and
//! their error, and the quality ladder (the passes that draw are the GPU layer's
//! `render` module).

pub mod budget;
pub mod direction_spread;
mod drawing;
pub mod dual_scattering;
pub mod frame_block;
pub mod hair_oracle;
mod image;
mod lighting;
pub mod marschner;
pub mod presets;
pub mod stage;
pub mod std140;
pub mod strand_raster;
pub mod style;
pub mod uniforms;

pub use frame_block::{FrameInputs, FrameUniforms, LightView, CASTER_DENSITY};
pub use image::{flip, RgbaImage};
pub use lighting::spans as lighting_spans;
pub use lighting::{
    kajiya_kay, Fibre, Highlights, Lighting, LightingModel, Shade, Shadows, DIRECTION_SPREAD,
};
pub use presets::FurPreset;
pub use uniforms::{
    FrameSettings, FurStyle, Primitive, Raster, Shading, Stage, StrandShape, DEFAULT_TILE,
    MAX_NEAREST, STUB_LIMIT, TILE_SIZES,
};
