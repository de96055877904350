//! One frame: the mesh pass then the fur pass into the offscreen target, with
//! timestamps around each pass and pipeline statistics over the fur pass.

use std::sync::Arc;

use ash::vk;

use super::fur_pass::FurPass;
use super::mesh_pass::MeshPass;
use super::target::{RenderTarget, RgbaImage};
use super::uniforms::{FrameSettings, FrameUniforms};
use crate::error::Result;
use crate::gpu::{
    memory_barrier, Buffer, DescriptorPool, DescriptorSetLayout, Device, FurStatistics,
    PipelineLayout, QueryPool,
};
use crate::scene::Mesh;
use crate::strand_textures::StrandTextures;

/// Points one render descriptor set at its uniforms, position image and ownership masks.
fn write_render_set(
    device: &Device,
    set: vk::DescriptorSet,
    uniforms: &Buffer,
    positions: &crate::gpu::Image,
    ownership: &Buffer,
) {
    let ubo = [vk::DescriptorBufferInfo::default()
        .buffer(uniforms.raw())
        .range(vk::WHOLE_SIZE)];
    let image = [vk::DescriptorImageInfo::default()
        .image_view(positions.view())
        .image_layout(vk::ImageLayout::GENERAL)];
    let owners = [vk::DescriptorBufferInfo::default()
        .buffer(ownership.raw())
        .range(vk::WHOLE_SIZE)];
    let writes = [
        vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .buffer_info(&ubo),
        vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(1)
            .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
            .image_info(&image),
        vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(2)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .buffer_info(&owners),
    ];
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Bindings of descriptor set 0 (see `shaders/common.glsl`).
fn bindings() -> [(vk::DescriptorType, vk::ShaderStageFlags); 3] {
    let hair_stages = vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
        | vk::ShaderStageFlags::GEOMETRY;
    [
        (
            vk::DescriptorType::UNIFORM_BUFFER,
            vk::ShaderStageFlags::ALL_GRAPHICS,
        ),
        (vk::DescriptorType::STORAGE_IMAGE, hair_stages),
        (vk::DescriptorType::STORAGE_BUFFER, hair_stages),
    ]
}

/// Timestamp slots.
const TS_START: u32 = 0;
const TS_MESH: u32 = 1;
const TS_FUR: u32 = 2;

/// What a rendered frame reports.
#[derive(Clone, Debug)]
pub struct FrameReport {
    pub statistics: Option<FurStatistics>,
    /// GPU milliseconds of the mesh pass and the fur pass (timestamps).
    pub mesh_ms: f64,
    pub fur_ms: f64,
}

pub struct Renderer {
    device: Arc<Device>,
    _set_layout: DescriptorSetLayout,
    pipeline_layout: PipelineLayout,
    _pool: DescriptorPool,
    /// Per frame in flight: what the host writes or reads back while other frames run.
    slots: Vec<RenderSlot>,
    _ownership: Buffer,
    indices: Buffer,
    index_count: u32,
    vertices_per_strand: u32,
    strands_per_row: u32,
    mesh_pass: MeshPass,
    fur_pass: FurPass,
    pub target: RenderTarget,
}

/// The resources of one frame in flight.
struct RenderSlot {
    uniforms: Buffer,
    /// One set per possible current position image.
    sets: [vk::DescriptorSet; 2],
    timestamps: Option<QueryPool>,
    statistics: Option<QueryPool>,
}

impl Renderer {
    /// A renderer with `frames_in_flight` sets of per-frame resources (1 headless).
    pub fn new(
        device: &Arc<Device>,
        mesh: &Mesh,
        strands: &StrandTextures,
        extent: vk::Extent2D,
        frames_in_flight: usize,
    ) -> Result<Self> {
        let target = RenderTarget::new(device, extent)?;
        let bindings = bindings();
        let set_layout = DescriptorSetLayout::new(device, "render.set_layout", &bindings)?;
        let pipeline_layout =
            PipelineLayout::new(device, "render.pipeline_layout", &[&set_layout], &[])?;
        let set_count = 2 * frames_in_flight.max(1);
        let pool = DescriptorPool::new(
            device,
            "render.descriptor_pool",
            set_count as u32,
            &bindings,
        )?;
        let ownership = Buffer::with_data(
            device,
            "render.ownership",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &mesh.ownership_masks(),
        )?;
        let indices = Buffer::with_data(
            device,
            "mesh.indices",
            vk::BufferUsageFlags::INDEX_BUFFER,
            &mesh.indices,
        )?;
        let mut slots = Vec::new();
        for slot in 0..frames_in_flight.max(1) {
            let uniforms = Buffer::new(
                device,
                &format!("render.uniforms[{slot}]"),
                std::mem::size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                gpu_allocator::MemoryLocation::CpuToGpu,
            )?;
            let sets = pool.allocate(&set_layout, 2)?;
            for (i, set) in sets.iter().enumerate() {
                write_render_set(device, *set, &uniforms, &strands.positions[i], &ownership);
            }
            let timestamps = if device.info.timestamps {
                Some(QueryPool::timestamps(
                    device,
                    &format!("render.timestamps[{slot}]"),
                    3,
                )?)
            } else {
                None
            };
            let statistics = if device.info.pipeline_statistics {
                Some(QueryPool::fur_statistics(
                    device,
                    &format!("render.fur_statistics[{slot}]"),
                )?)
            } else {
                None
            };
            slots.push(RenderSlot {
                uniforms,
                sets: [sets[0], sets[1]],
                timestamps,
                statistics,
            });
        }
        let vertices_per_strand = strands.layout.vertices_per_strand;
        let mesh_pass = MeshPass::new(device, &pipeline_layout, mesh)?;
        let fur_pass = FurPass::new(device, &pipeline_layout, vertices_per_strand)?;
        Ok(Self {
            device: device.clone(),
            _set_layout: set_layout,
            pipeline_layout,
            _pool: pool,
            slots,
            _ownership: ownership,
            indices,
            index_count: mesh.indices.len() as u32,
            vertices_per_strand,
            strands_per_row: strands.layout.strands_per_row,
            mesh_pass,
            fur_pass,
            target,
        })
    }

    /// Recreates the render target for a new image size.
    pub fn resize(&mut self, extent: vk::Extent2D) -> Result<()> {
        if extent != self.target.extent {
            self.target = RenderTarget::new(&self.device, extent)?;
        }
        Ok(())
    }

    /// Writes the uniforms of frame slot `slot`. Call before recording the frame, once
    /// the slot's previous frame has finished.
    pub fn update(&mut self, slot: usize, settings: &FrameSettings) {
        let max_level = self.device.info.limits.max_tessellation_generation_level as f32;
        let uniforms = FrameUniforms::new(
            settings,
            self.target.extent.width,
            self.target.extent.height,
            self.vertices_per_strand,
            self.strands_per_row,
            max_level,
        );
        self.slots[slot]
            .uniforms
            .write(0, bytemuck::bytes_of(&uniforms));
    }

    /// Records both passes into the target; the resolved image is left in
    /// `COLOR_ATTACHMENT_OPTIMAL` for [`RenderTarget::copy_out`] or a blit. `current`
    /// selects the position image the simulation last wrote; its writes are made visible.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        slot: usize,
        current: usize,
        settings: &FrameSettings,
    ) {
        let d = &*self.device;
        let raw = &d.raw;
        let frame = &self.slots[slot];
        if let Some(q) = &frame.timestamps {
            q.reset();
        }
        if let Some(q) = &frame.statistics {
            q.reset();
        }
        d.begin_label(cmd, "frame");
        // The simulation's last writes must land before the hair stages read them.
        memory_barrier(
            d,
            cmd,
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
            (
                vk::PipelineStageFlags2::VERTEX_SHADER
                    | vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER
                    | vk::PipelineStageFlags2::TESSELLATION_EVALUATION_SHADER
                    | vk::PipelineStageFlags2::GEOMETRY_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_READ,
            ),
        );
        self.target.begin(d, cmd);
        self.timestamp(cmd, slot, TS_START);
        let extent = self.target.extent;
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [0.02, 0.025, 0.035, 1.0],
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
        ];
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(self.target.color.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(self.target.resolve.view())
            .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(clear[0])];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(self.target.depth.view())
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(clear[1]);
        // The statistics query spans the whole rendering scope (the mesh pass adds no
        // tessellation or geometry work). Mesa 22.3's lavapipe crashes when such a query
        // begins inside the scope before its first draw.
        if let Some(q) = &frame.statistics {
            unsafe { raw.cmd_begin_query(cmd, q.raw(), 0, vk::QueryControlFlags::empty()) };
        }
        let rendering = vk::RenderingInfo::default()
            .render_area(extent.into())
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        unsafe {
            raw.cmd_begin_rendering(cmd, &rendering);
            raw.cmd_set_viewport(
                cmd,
                0,
                &[vk::Viewport {
                    x: 0.0,
                    y: 0.0,
                    width: extent.width as f32,
                    height: extent.height as f32,
                    min_depth: 0.0,
                    max_depth: 1.0,
                }],
            );
            raw.cmd_set_scissor(cmd, 0, &[extent.into()]);
            raw.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.pipeline_layout.raw(),
                0,
                &[frame.sets[current]],
                &[],
            );
            raw.cmd_bind_index_buffer(cmd, self.indices.raw(), 0, vk::IndexType::UINT32);
        }
        self.mesh_pass.bind_vertices(d, cmd);
        if settings.draw_mesh {
            d.begin_label(cmd, "mesh pass");
            self.mesh_pass.draw(d, cmd, self.index_count);
            d.end_label(cmd);
        }
        self.timestamp(cmd, slot, TS_MESH);
        if settings.draw_fur {
            d.begin_label(cmd, "fur pass");
            self.fur_pass.draw(d, cmd, self.index_count);
            d.end_label(cmd);
        }
        self.timestamp(cmd, slot, TS_FUR);
        unsafe { raw.cmd_end_rendering(cmd) };
        if let Some(q) = &frame.statistics {
            unsafe { raw.cmd_end_query(cmd, q.raw(), 0) };
        }
        d.end_label(cmd);
    }

    fn timestamp(&self, cmd: vk::CommandBuffer, slot: usize, query: u32) {
        if let Some(q) = &self.slots[slot].timestamps {
            let stage = vk::PipelineStageFlags2::ALL_GRAPHICS;
            unsafe {
                self.device
                    .raw
                    .cmd_write_timestamp2(cmd, stage, q.raw(), query)
            };
        }
    }

    /// Reads the queries of slot `slot`'s last submitted frame (waits for them).
    pub fn report(&self, slot: usize, settings: &FrameSettings) -> Result<FrameReport> {
        let frame = &self.slots[slot];
        let (mesh_ms, fur_ms) = match &frame.timestamps {
            Some(q) => {
                let t = q.timestamps_ms(3)?;
                (t[1] - t[0], t[2] - t[1])
            }
            None => (f64::NAN, f64::NAN),
        };
        let statistics = match (&frame.statistics, settings.draw_fur) {
            (Some(q), true) => Some(q.fur_statistics_result()?),
            _ => None,
        };
        Ok(FrameReport {
            statistics,
            mesh_ms,
            fur_ms,
        })
    }

    /// Renders one frame of the strands' current state and returns the image.
    pub fn render(
        &mut self,
        strands: &StrandTextures,
        settings: &FrameSettings,
    ) -> Result<(RgbaImage, FrameReport)> {
        self.update(0, settings);
        let device = self.device.clone();
        device.submit_once(|cmd| {
            self.record(cmd, 0, strands.current, settings);
            self.target.copy_out(&device, cmd);
            Ok(())
        })?;
        Ok((self.target.pixels(), self.report(0, settings)?))
    }
}
