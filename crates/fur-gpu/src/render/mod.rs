//! The render passes: mesh (skin) and fur, into an offscreen target; the drawing's
//! settings, lighting models and images are the core's ([`fur_core::render`]).

mod bindings;
mod graph;
mod pipeline;
mod renderer;
mod slot;
mod target;
mod texture;

#[cfg(test)]
pub(crate) use bindings::render_defines;
pub use renderer::compute_raster::ComputeCounts;
pub use renderer::{
    CapturedHairs, FrameReport, HairCounts, RasterCapture, Renderer, BACKGROUND, MAX_CAPTURE_BYTES,
    STEP_NAMES,
};
pub use target::{check_samples, RenderTarget, TargetSpec};
