//! The shadow pass: the fur seen from the light into a depth map of the nearest hair,
//! which the fur and skin passes then read (see `light_through_fur` in
//! `shaders/shading.glsl`).
//!
//! The light is directional: an orthographic view along it that holds the model's
//! bounding sphere grown by the hair length. The fur is drawn there as lines, depth
//! only, at a fraction of the frame's density ([`fur_core::render::CASTER_DENSITY`]):
//! the map needs the nearest hair, not every hair. The light's view and its uniform
//! block are the core's ([`fur_core::render::LightView`]).

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass, View};
use super::fur_pass::{hair_uses, FurPass, Variant};
use super::mesh_pass::BodyTraits;
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use crate::error::Result;
use crate::frame::Use;

/// The fur seen from the light, depth only, into the slot's shadow map. It owns its
/// pipeline: the fur pipeline's caster form (lines, one sample, no fragment stage).
pub struct ShadowPass {
    casters: FurPass,
}

impl ShadowPass {
    /// The pass's name (its debug label).
    pub const NAME: &'static str = "shadow pass";

}

impl Registered for ShadowPass {
    /// The casters of the renderer's strands, on its body (untextured: depth only).
    fn build(build: &Build<'_>) -> Self {
        let body = BodyTraits {
            textured: false,
            ..build.body
        };
        Self {
            casters: FurPass::new(build.device, build.strands.vertices_per_strand, 1, body),
        }
    }
}

impl FramePass for ShadowPass {
    fn phase(&self) -> Phase {
        Phase::Shadow
    }

    fn wanted(&self, plan: &Plan<'_>) -> bool {
        plan.shadows
    }

    /// Builds its pipeline if it does not exist yet.
    fn prepare(&mut self, plan: &Plan<'_>) -> Result<()> {
        self.casters.prepare(plan.layout, &[Variant::CASTER])
    }
}

impl Pass for ShadowPass {
    fn name(&self) -> &'static str {
        ShadowPass::NAME
    }

    fn attachments(&self) -> Attachments {
        Attachments::ShadowMap
    }

    fn view(&self) -> View {
        View::Light
    }

    fn uses(&self, _frame: &FrameContext<'_>) -> Vec<Use> {
        // The casters count nothing.
        hair_uses(self.casters.skinned(), false)
    }

    /// Draws the fur's caster form (the graph has bound the light's sets). The fur reads
    /// its triangles from a storage buffer: no vertex or index buffers to bind.
    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        self.casters.draw(
            frame.device,
            cmd,
            frame.hair_index_count,
            &[Variant::CASTER],
        );
    }
}
