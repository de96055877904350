//! The shadow pass: the fur seen from the light into a depth map of the nearest hair,
//! which the fur and skin passes then read (see `light_through_fur` in
//! `shaders/shading.glsl`).
//!
//! The light is directional: an orthographic view along it that holds the model's
//! bounding sphere grown by the hair length. The fur is drawn there as lines, depth
//! only, at a fraction of the frame's density ([`CASTER_DENSITY`]): the map needs the
//! nearest hair, not every hair.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3};

use super::super::graph::{Attachments, FrameContext, Pass, Use, View};
use super::super::uniforms::{FrameSettings, FrameUniforms, FLAG_COUNT};
use super::fur_pass::{hair_uses, FurPass, Variant};
use crate::error::Result;
use crate::gpu::{Device, PipelineLayout};

/// The fraction of the frame's hair density drawn into the shadow map.
pub const CASTER_DENSITY: f32 = 0.5;

/// Where the light looks from and what its map's depth means.
#[derive(Clone, Copy, Debug)]
pub struct LightView {
    pub view_proj: Mat4,
    /// A point far along the light (for the fur pass's culling and level of detail).
    pub eye: Vec3,
    /// Scene units from the map's near to its far plane.
    pub depth_range: f32,
    /// Scene units one texel spans.
    pub texel: f32,
}

impl LightView {
    /// The view along `settings`' light that holds a sphere of `radius` around
    /// `centre` (world space) in a map of `resolution` texels.
    pub fn new(settings: &FrameSettings, centre: Vec3, radius: f32, resolution: u32) -> Self {
        let l = settings.lighting.light_direction.normalize_or(Vec3::Y);
        let up = if l.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let eye = centre + l * (2.0 * radius);
        let view = Mat4::look_at_rh(eye, centre, up);
        // Glam's orthographic projection maps depth to Vulkan's [0, 1].
        let proj = Mat4::orthographic_rh(-radius, radius, -radius, radius, radius, 3.0 * radius);
        Self {
            view_proj: proj * view,
            eye,
            depth_range: 2.0 * radius,
            texel: 2.0 * radius / resolution as f32,
        }
    }

    /// The uniforms of the light's view of the fur: its matrix, lines only, no counting,
    /// [`CASTER_DENSITY`] of the hairs, full density at any distance.
    pub fn caster_uniforms(&self, frame: &FrameUniforms) -> FrameUniforms {
        let mut u = *frame;
        u.view_proj = self.view_proj;
        // The eye is the map's depth range from the centre: a texel there is `texel` wide.
        u.eye = self.eye.extend(self.texel / self.depth_range);
        u.lod.x *= CASTER_DENSITY;
        u.lod.y = f32::MAX;
        u.draw.x = f32::MAX;
        u.strands.w &= !FLAG_COUNT;
        u
    }

    /// Points the frame's uniforms at this view's map: its matrix, the hair layers per
    /// unit of map depth, and a depth bias of half a layer and a texel's slope.
    pub fn apply(&self, frame: &mut FrameUniforms) {
        let spacing = 1.0 / frame.shadow.y;
        frame.light_view_proj = self.view_proj;
        frame.shadow.y = self.depth_range / spacing;
        frame.shadow.z = (0.5 * spacing + self.texel) / self.depth_range;
    }
}

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
            casters: FurPass::new(device, vertices_per_strand, 1, (false, skinned)),
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
