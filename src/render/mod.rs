//! The render passes: mesh (skin) and fur, into an offscreen target.

mod bindings;
pub mod budget;
mod fur_pass;
mod image;
mod lighting;
pub mod marschner;
mod mesh_pass;
mod pipeline;
mod renderer;
mod shadow_pass;
mod slot;
mod target;
mod texture;
mod uniforms;

pub use image::{flip, RgbaImage};
pub use lighting::{kajiya_kay, Fibre, Highlights, Lighting, LightingModel, Shade, Shadows};
pub use renderer::{
    CapturedHairs, FrameReport, HairCounts, Renderer, BACKGROUND, MAX_CAPTURE_BYTES,
};
pub use shadow_pass::CASTER_DENSITY;
pub use target::{check_samples, RenderTarget};
pub use uniforms::{FrameSettings, FrameUniforms, FurStyle, Primitive, Shading, StrandShape};
