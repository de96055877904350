//! The shadow pass: the fur seen from the light into a depth map of the nearest hair,
//! which the fur and skin passes then read (see `light_through_fur` in
//! `shaders/shading.glsl`).
//!
//! The light is directional: an orthographic view along it that holds the model's
//! bounding sphere grown by the hair length. The fur is drawn there as lines, depth
//! only, at a fraction of the frame's density ([`fur_core::render::CASTER_DENSITY`]):
//! the map needs the nearest hair, not every hair. The light's view and its uniform
//! block are the core's ([`fur_core::render::LightView`]).

use std::sync::Arc;

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass, View};
use super::fur_pass::{hair_uses, FurPass, Variant};
use super::mesh_pass::BodyTraits;
use crate::error::Result;
use crate::frame::Use;
use crate::gpu::{Device, PipelineLayout};

/// The fur seen from the light, depth only, into the slot's shadow map. It owns its
/// pipeline: the fur pipeline's caster form (lines, one sample, no fragment stage).
pub struct ShadowPass {
    casters: FurPass,
}

impl ShadowPass {
    /// The pass's name (its debug label).
    pub const NAME: &'static str = "shadow pass";

    /// The pass for strands of `vertices_per_strand` vertices on a body that is
    /// `skinned` or not.
    pub fn new(device: &Arc<Device>, vertices_per_strand: u32, skinned: bool) -> Self {
        Self {
            casters: FurPass::new(
                device,
                vertices_per_strand,
                1,
                BodyTraits {
                    textured: false,
                    skinned,
                },
            ),
        }
    }

    /// Builds its pipeline if it does not exist yet.
    pub fn prepare(&mut self, layout: &PipelineLayout) -> Result<()> {
        self.casters.prepare(layout, &[Variant::CASTER])
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
