//! The shadow pass: the fur seen from the light into a depth map of the nearest hair,
//! which the fur and skin passes then read (see `light_through_fur` in
//! `shaders/shading.glsl`).
//!
//! The light is directional: an orthographic view along it that holds the model's
//! bounding sphere grown by the hair length. The fur is drawn there as lines, depth
//! only, at a fraction of the frame's density ([`CASTER_DENSITY`]): the map needs the
//! nearest hair, not every hair.

use ash::vk;
use glam::{Mat4, Vec3};

use super::fur_pass::{FurPass, Variant};
use super::pipeline::begin_rendering;
use super::texture::ShadowMap;
use super::uniforms::{FrameSettings, FrameUniforms, FLAG_COUNT};
use crate::gpu::{image_barriers, Device};

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

/// Records the shadow pass into `map`: the fur's caster form drawn with the descriptor
/// set of the light's uniforms (bound by the caller), then the
/// map made readable by the fur and skin passes.
pub fn record(
    device: &Device,
    cmd: vk::CommandBuffer,
    map: &ShadowMap,
    fur_pass: &FurPass,
    index_count: u32,
) {
    // The previous frame's reads of this map are done before it is cleared.
    image_barriers(
        device,
        cmd,
        &[map.image.barrier(
            (
                vk::PipelineStageFlags2::GEOMETRY_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
            (
                vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        )],
    );
    let extent = vk::Extent2D {
        width: map.resolution,
        height: map.resolution,
    };
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(map.image.view())
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let rendering = vk::RenderingInfo::default()
        .render_area(extent.into())
        .layer_count(1)
        .depth_attachment(&depth);
    let raw = &device.raw;
    device.begin_label(cmd, "shadow pass");
    begin_rendering(device, cmd, &rendering, extent);
    fur_pass.draw(device, cmd, index_count, &[Variant::CASTER]);
    unsafe { raw.cmd_end_rendering(cmd) };
    device.end_label(cmd);
    image_barriers(
        device,
        cmd,
        &[map.image.barrier(
            (
                vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            (
                vk::PipelineStageFlags2::GEOMETRY_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )],
    );
}
