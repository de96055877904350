//! The fur pass: mesh triangles as 3-point patches through
//! vertex → tessellation control → tessellation evaluation (point mode) → geometry →
//! fragment. See the shaders `fur.*` for what each stage does.

use std::sync::Arc;

use ash::vk;

use super::pipeline::{graphics_pipeline, GraphicsDesc};
use crate::error::Result;
use crate::gpu::{Device, Pipeline, PipelineLayout, ShaderModule};

pub struct FurPass {
    pipeline: Pipeline,
}

impl FurPass {
    /// Builds the pipeline for strands of `vertices_per_strand` vertices (the geometry
    /// shader's output size is fixed at compile time).
    pub fn new(
        device: &Arc<Device>,
        layout: &PipelineLayout,
        vertices_per_strand: u32,
    ) -> Result<Self> {
        let defines = [("STRAND_VERTICES", vertices_per_strand.to_string())];
        let vert = ShaderModule::new(device, "fur.vert", &[])?;
        let tesc = ShaderModule::new(device, "fur.tesc", &[])?;
        let tese = ShaderModule::new(device, "fur.tese", &[])?;
        let geom = ShaderModule::new(device, "fur.geom", &defines)?;
        let frag = ShaderModule::new(device, "fur.frag", &[])?;
        let pipeline = graphics_pipeline(
            device,
            layout,
            &GraphicsDesc {
                name: "fur pass",
                stages: &[
                    (vk::ShaderStageFlags::VERTEX, &vert),
                    (vk::ShaderStageFlags::TESSELLATION_CONTROL, &tesc),
                    (vk::ShaderStageFlags::TESSELLATION_EVALUATION, &tese),
                    (vk::ShaderStageFlags::GEOMETRY, &geom),
                    (vk::ShaderStageFlags::FRAGMENT, &frag),
                ],
                topology: vk::PrimitiveTopology::PATCH_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: Some(3),
            },
        )?;
        Ok(Self { pipeline })
    }

    /// Records the draw; the caller has bound the descriptor set and index buffer.
    pub fn draw(&self, device: &Device, cmd: vk::CommandBuffer, index_count: u32) {
        unsafe {
            device
                .raw
                .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw());
            device.raw.cmd_draw_indexed(cmd, index_count, 1, 0, 0, 0);
        }
    }
}
