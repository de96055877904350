//! The render passes: mesh (skin) and fur, into an offscreen target.

mod bindings;
mod fur_pass;
mod image;
mod mesh_pass;
mod pipeline;
mod renderer;
mod target;
mod uniforms;

pub use image::RgbaImage;
pub use renderer::{FrameReport, HairCounts, Renderer};
pub use target::{check_samples, RenderTarget};
pub use uniforms::{
    kajiya_kay, FrameSettings, FrameUniforms, FurStyle, Lighting, Primitive, Shading, StrandShape,
};
