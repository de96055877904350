//! The mesh (skin) pass: the model's triangles, Lambert-shaded.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use super::pipeline::{graphics_pipeline, Blend, GraphicsDesc};
use super::target::sample_flag;
use crate::error::Result;
use crate::gpu::{Buffer, Device, Pipeline, PipelineLayout, ShaderModule};
use crate::scene::Mesh;

/// Interleaved position + normal.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MeshVertex {
    position: Vec3,
    normal: Vec3,
}

pub struct MeshPass {
    pipeline: Pipeline,
    vertices: Buffer,
}

impl MeshPass {
    /// The pass for `mesh` into a target of `samples` per pixel.
    pub fn new(
        device: &Arc<Device>,
        layout: &PipelineLayout,
        mesh: &Mesh,
        samples: u32,
    ) -> Result<Self> {
        let data: Vec<MeshVertex> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .map(|(&position, &normal)| MeshVertex { position, normal })
            .collect();
        let vertices = Buffer::with_data(
            device,
            "mesh.vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &data,
        )?;
        Ok(Self {
            pipeline: Self::pipeline(device, layout, samples)?,
            vertices,
        })
    }

    /// Rebuilds the pipeline for a target of `samples` per pixel.
    pub fn set_samples(
        &mut self,
        device: &Arc<Device>,
        layout: &PipelineLayout,
        samples: u32,
    ) -> Result<()> {
        self.pipeline = Self::pipeline(device, layout, samples)?;
        Ok(())
    }

    fn pipeline(device: &Arc<Device>, layout: &PipelineLayout, samples: u32) -> Result<Pipeline> {
        let vert = ShaderModule::new(device, "mesh.vert", &[])?;
        let frag = ShaderModule::new(device, "mesh.frag", &[])?;
        let stride = std::mem::size_of::<MeshVertex>() as u32;
        graphics_pipeline(
            device,
            layout,
            &GraphicsDesc {
                name: "mesh pass",
                stages: &[
                    (vk::ShaderStageFlags::VERTEX, &vert),
                    (vk::ShaderStageFlags::FRAGMENT, &frag),
                ],
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                vertex_bindings: &[vk::VertexInputBindingDescription {
                    binding: 0,
                    stride,
                    input_rate: vk::VertexInputRate::VERTEX,
                }],
                vertex_attributes: &[
                    vk::VertexInputAttributeDescription {
                        location: 0,
                        binding: 0,
                        format: vk::Format::R32G32B32_SFLOAT,
                        offset: 0,
                    },
                    vk::VertexInputAttributeDescription {
                        location: 1,
                        binding: 0,
                        format: vk::Format::R32G32B32_SFLOAT,
                        offset: 12,
                    },
                ],
                patch_control_points: None,
                samples: sample_flag(samples),
                blend: Blend::Opaque,
                depth_write: true,
            },
        )
    }

    /// Binds the mesh's vertex buffer. The renderer binds it once per frame, even when
    /// only the fur (which reads no vertex attributes) is drawn: Mesa 22.3's lavapipe
    /// crashes on an indexed draw with no vertex buffer ever bound.
    pub fn bind_vertices(&self, device: &Device, cmd: vk::CommandBuffer) {
        unsafe {
            device
                .raw
                .cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw()], &[0])
        };
    }

    /// Records the draw; the caller has bound the descriptor set, index and vertex buffers.
    pub fn draw(&self, device: &Device, cmd: vk::CommandBuffer, index_count: u32) {
        unsafe {
            device
                .raw
                .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw());
            device.raw.cmd_draw_indexed(cmd, index_count, 1, 0, 0, 0);
        }
    }
}
