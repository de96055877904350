//! The mesh (skin) pass: the model's triangles, Lambert-shaded, textured when the model
//! has a texture (then drawn corner by corner, so UV seams stay exact), shadowed by
//! the fur when the frame draws shadows.

use std::sync::Arc;

use ash::vk;
use glam::{Vec2, Vec3};

use super::super::graph::{FrameContext, Pass};
use super::super::pipeline::{
    graphics_pipeline, Blend, ColourAttachment, DepthAttachment, GraphicsDesc,
};
use super::super::target::{sample_flag, COLOR_FORMAT, DEPTH_FORMAT};
use crate::error::Result;
use crate::frame::{uses, Resource, Use};
use crate::gpu::{Access, Buffer, Device, Pipeline, PipelineLayout, ShaderModule};
use fur_core::render::Stage;
use fur_core::scene::Mesh;

/// Interleaved position, normal and texture coordinates.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct MeshVertex {
    position: Vec3,
    normal: Vec3,
    uv: Vec2,
}

/// How the mesh pass draws the body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshLook {
    /// Lambert plus ambient.
    Plain,
    /// Lambert plus ambient, shaded by the fur's shadow.
    Shadowed,
    /// Grey stripes for the density view: the density pass draws over every triangle
    /// that gets hairs, so what shows is the culled ones.
    Hatched,
}

impl MeshLook {
    const COUNT: usize = 3;

    /// The look of a frame showing `stage`, with or without `shadows`.
    pub fn of(stage: Stage, shadows: bool) -> Self {
        match (stage, shadows) {
            (Stage::Density, _) => Self::Hatched,
            (_, true) => Self::Shadowed,
            (_, false) => Self::Plain,
        }
    }
}

type Pipelines = [Option<Pipeline>; MeshLook::COUNT];

/// What the body brings to the passes that draw it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BodyTraits {
    /// A texture, read through the corner UVs.
    pub textured: bool,
    /// A skin: the posed positions and normals come from the skinning pass.
    pub skinned: bool,
}

pub struct MeshPass {
    /// One per look, built on first use.
    pipelines: Pipelines,
    /// The pipelines of the sample count in use before the last change, with it.
    spare: Option<(u32, Pipelines)>,
    vertices: Buffer,
    samples: u32,
    /// Textured: one vertex per triangle corner, drawn unindexed.
    textured: bool,
    /// Skinned: positions and normals come from the skinning pass (binding 7).
    skinned: bool,
}

impl MeshPass {
    /// The pass's name (its debug label; the frame's timestamps follow it).
    pub const NAME: &'static str = "mesh pass";

    /// The pass for `mesh` into a target of `samples` per pixel; `textured` draws the
    /// model's texture through its corner UVs, `skinned` the posed body of the skinning
    /// pass instead of the mesh's rest pose.
    pub fn new(
        device: &Arc<Device>,
        mesh: &Mesh,
        samples: u32,
        BodyTraits { textured, skinned }: BodyTraits,
    ) -> Result<Self> {
        let vertex = |i: u32, uv: Vec2| MeshVertex {
            position: mesh.positions[i as usize],
            normal: mesh.normals[i as usize],
            uv,
        };
        let data: Vec<MeshVertex> = if textured {
            mesh.indices
                .iter()
                .zip(&mesh.uvs)
                .map(|(&i, &uv)| vertex(i, uv))
                .collect()
        } else {
            (0..mesh.vertex_count() as u32)
                .map(|i| vertex(i, Vec2::ZERO))
                .collect()
        };
        let vertices = Buffer::with_data(
            device,
            "mesh.vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &data,
        )?;
        Ok(Self {
            pipelines: Default::default(),
            spare: None,
            vertices,
            samples,
            textured,
            skinned,
        })
    }

    /// Pipelines for a target of `samples` per pixel: the spare ones of the last change
    /// when they were for `samples`, else built when first needed.
    pub fn set_samples(&mut self, samples: u32) {
        if samples == self.samples {
            return;
        }
        let pipelines = match self.spare.take() {
            Some((s, pipelines)) if s == samples => pipelines,
            _ => Default::default(),
        };
        let old = std::mem::replace(&mut self.pipelines, pipelines);
        self.spare = Some((self.samples, old));
        self.samples = samples;
    }

    /// Builds the pipeline for frames drawing the body with `look` if it does not exist.
    pub fn prepare(
        &mut self,
        device: &Arc<Device>,
        layout: &PipelineLayout,
        look: MeshLook,
    ) -> Result<()> {
        let slot = &mut self.pipelines[look as usize];
        if slot.is_none() {
            *slot = Some(Self::pipeline(
                device,
                layout,
                self.samples,
                BodyTraits {
                    textured: self.textured,
                    skinned: self.skinned,
                },
                look,
            )?);
        }
        Ok(())
    }

    fn pipeline(
        device: &Arc<Device>,
        layout: &PipelineLayout,
        samples: u32,
        BodyTraits { textured, skinned }: BodyTraits,
        look: MeshLook,
    ) -> Result<Pipeline> {
        let flag = |on: bool| u32::from(on).to_string();
        // The hatched body of the density view has no colour: it reads no texture (a
        // UV the fragment stage never reads is an output the validation layer reports).
        let textured = textured && look != MeshLook::Hatched;
        let stage = if look == MeshLook::Hatched {
            Stage::Density
        } else {
            Stage::Lit
        };
        let mut defines = vec![
            ("TEXTURED", flag(textured)),
            ("SHADOWS", flag(look == MeshLook::Shadowed)),
            ("BODY_SKINNED", flag(skinned)),
            ("STAGE_VIEW", stage.code().to_string()),
        ];
        defines.extend(super::super::bindings::render_defines());
        let vert = ShaderModule::new(device, "mesh.vert", &defines)?;
        let frag = ShaderModule::new(device, "mesh.frag", &defines)?;
        let stride = std::mem::size_of::<MeshVertex>() as u32;
        let attributes = [
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
            vk::VertexInputAttributeDescription {
                location: 2,
                binding: 0,
                format: vk::Format::R32G32_SFLOAT,
                offset: 24,
            },
        ];

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
                // A skinned body reads its posed vertices from a buffer: only the UVs
                // come from the vertex buffer.
                vertex_attributes: match (skinned, textured) {
                    (false, true) => &attributes[..],
                    (false, false) => &attributes[..2],
                    (true, true) => &attributes[2..],
                    (true, false) => &[],
                },
                patch_control_points: None,
                samples: sample_flag(samples),
                colour: &[ColourAttachment {
                    format: COLOR_FORMAT,
                    blend: Blend::Opaque,
                }],
                depth: Some(DepthAttachment::nearest(DEPTH_FORMAT)),
            },
        )
    }

    /// Binds the mesh's vertex buffer. The renderer binds it once per frame, even when
    /// only the fur (which reads no vertex attributes) is drawn: Mesa 22.3's lavapipe
    /// crashes on an indexed draw with no vertex buffer ever bound.
    fn bind_vertices(&self, device: &Device, cmd: vk::CommandBuffer) {
        // SAFETY: the command buffer is recording; the vertex buffer lives as long as the pass.
        unsafe {
            device
                .raw
                .cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw()], &[0])
        };
    }

    /// Records the draw (prepared before for `look`) once the set, index and vertex
    /// buffers are bound.
    fn draw(&self, device: &Device, cmd: vk::CommandBuffer, index_count: u32, look: MeshLook) {
        let Some(pipeline) = &self.pipelines[look as usize] else {
            return;
        };
        // SAFETY: recording inside the target's scope with the sets, index and vertex buffers
        // bound; the pipeline lives as long as the pass.
        unsafe {
            device
                .raw
                .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw());
            if self.textured {
                device.raw.cmd_draw(cmd, index_count, 1, 0, 0);
            } else {
                device.raw.cmd_draw_indexed(cmd, index_count, 1, 0, 0, 0);
            }
        }
    }
}

impl Pass for MeshPass {
    fn name(&self) -> &'static str {
        MeshPass::NAME
    }

    fn timestamp(&self, _frame: &FrameContext<'_>) -> Option<u32> {
        Some(super::super::slot::TS_MESH)
    }

    fn uses(&self, frame: &FrameContext<'_>) -> Vec<Use> {
        let mut list = Vec::new();
        if self.skinned {
            list.push(uses(Resource::Posed, Access::HairStagesRead));
        }
        if frame.slot.shadows {
            list.push(uses(Resource::ShadowMap, Access::ShadingSampled));
        }
        list
    }

    /// Binds the indices and the vertices (the graph has bound the sets), and draws the
    /// skin when the frame asks for it. It opens the target's scope either way (the fur pass
    /// follows in it).
    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let device = frame.device;
        // SAFETY: recording inside the target's scope; the index buffer belongs to the
        // renderer, which outlives the frame.
        unsafe {
            device
                .raw
                .cmd_bind_index_buffer(cmd, frame.indices, 0, vk::IndexType::UINT32);
        }
        self.bind_vertices(device, cmd);
        if frame.settings.draw_mesh {
            let look = MeshLook::of(frame.settings.show, frame.slot.shadows);
            self.draw(device, cmd, frame.index_count, look);
        }
    }
}
