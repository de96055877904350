//! The registered passes: a pass that builds, prepares and places itself. The renderer
//! holds them in one list, made by the `register!` line in `renderer.rs`; each frame it
//! asks every one whether the frame needs it ([`FramePass::wanted`]), prepares those
//! that do and lists them in their phase ([`Phase`]), so a new pass is its module, its
//! shaders and one line of registration.

use std::sync::Arc;

use super::super::graph::Pass;
use super::mesh_pass::BodyTraits;
use crate::error::Result;
use crate::gpu::{Device, PipelineLayout};
use crate::strand_textures::StrandLayout;
use fur_core::render::uniforms::FrameSettings;

/// Where a pass goes in the frame, in the order the phases run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Transfer work before anything draws (counter resets).
    Reset,
    /// The light's view (the shadow map).
    Shadow,
    /// The body, into the target.
    Body,
    /// The stage the frame shows, over the body: the fur or one of the stage views.
    Stage,
}

impl Phase {
    /// Every phase, in the order a frame runs them.
    pub const ALL: [Phase; 4] = [Phase::Reset, Phase::Shadow, Phase::Body, Phase::Stage];
}

/// What a pass is built from, once per renderer.
pub struct Build<'a> {
    pub device: &'a Arc<Device>,
    /// The body's texture and skin.
    pub body: BodyTraits,
    /// The master strands' texture layout.
    pub strands: &'a StrandLayout,
}

/// What a frame is, as the passes decide whether they are in it and prepare for it.
pub struct Plan<'a> {
    /// The frame's settings.
    pub settings: &'a FrameSettings,
    /// Whether the frame draws the shadow map.
    pub shadows: bool,
    /// The render pipelines' layout.
    pub layout: &'a PipelineLayout,
    /// The target's samples per pixel.
    pub samples: u32,
}

/// A pass as the frame's list holds it.
pub trait AsPass {
    fn as_pass(&self) -> &dyn Pass;
}

impl<T: Pass> AsPass for T {
    fn as_pass(&self) -> &dyn Pass {
        self
    }
}

/// A pass the renderer builds, prepares and places by its registration alone.
pub trait FramePass: Pass + AsPass {
    /// Where it goes in the frame.
    fn phase(&self) -> Phase;
    /// Whether the frame `plan` needs it: a frame holds only the passes it needs.
    fn wanted(&self, plan: &Plan<'_>) -> bool;
    /// Builds what recording it needs (its pipelines), once the frame wants it.
    fn prepare(&mut self, _plan: &Plan<'_>) -> Result<()> {
        Ok(())
    }
}

/// How the registration builds a pass.
pub trait Registered: FramePass + Sized + 'static {
    fn build(build: &Build<'_>) -> Self;
}

/// Declares each pass's module and registers its type, in the order given (within a
/// phase, registered passes are listed in this order, before the renderer's own).
macro_rules! register {
    ($($module:ident :: $pass:ident),* $(,)?) => {
        $(mod $module;)*

        /// Every registered pass, built for one renderer.
        fn registered(build: &registry::Build<'_>) -> Vec<Box<dyn registry::FramePass>> {
            use registry::Registered;
            vec![$(Box::new($module::$pass::build(build))),*]
        }
    };
}
pub(super) use register;
