//! The render passes: mesh (skin) and fur, into an offscreen 4× MSAA target.

mod fur_pass;
mod mesh_pass;
mod pipeline;
mod renderer;
mod target;
mod uniforms;

pub use renderer::{FrameReport, Renderer};
pub use target::{RenderTarget, RgbaImage};
pub use uniforms::{kajiya_kay, FrameSettings, FrameUniforms, FurStyle, Lighting};
