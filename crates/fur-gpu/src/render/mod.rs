//! The render passes: mesh (skin) and fur, into an offscreen target; the drawing's
//! settings, lighting models and images are the core's ([`fur_core::render`]).

pub use fur_core::render::*;

mod bindings;
mod fur_pass;
mod graph;
mod masters_pass;
mod mesh_pass;
mod pipeline;
mod renderer;
mod shadow_pass;
mod slot;
mod target;
mod texture;

#[cfg(test)]
pub(crate) use bindings::render_defines;
pub use renderer::{
    CapturedHairs, FrameReport, HairCounts, Renderer, BACKGROUND, MAX_CAPTURE_BYTES,
};
pub use shadow_pass::CASTER_DENSITY;
pub use target::{check_samples, RenderTarget};
