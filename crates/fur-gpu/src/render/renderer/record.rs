//! Recording a frame: its first timestamp, then the shadow, mesh and fur passes into
//! the target, with timestamps and pipeline statistics around them.

use super::super::slot::COUNTERS_BYTES;
use super::*;

impl Renderer {
    /// Starts frame slot `slot`'s queries: records the frame's first timestamp. Call
    /// first in the frame's command buffer, before its simulation.
    pub fn begin_frame(&self, cmd: vk::CommandBuffer, slot: usize) {
        let frame = &self.slots[slot];
        if let Some(q) = &frame.timestamps {
            q.reset();
        }
        if let Some(q) = &frame.statistics {
            q.reset();
        }
        self.timestamp(cmd, slot, TS_FRAME);
    }

    /// Records both passes into the target, after [`Renderer::begin_frame`]; the
    /// resolved image is left in `COLOR_ATTACHMENT_OPTIMAL` for
    /// [`RenderTarget::copy_out`] or a blit. `current` selects the position image the
    /// simulation last wrote; its writes are made visible.
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
        d.begin_label(cmd, "frame");
        if settings.count_hairs {
            // The previous frame's counts have been read (its fence waited on).
            // The header only: a capture behind it is written whole by the frame.
            unsafe { raw.cmd_fill_buffer(cmd, frame.counters.raw(), 0, COUNTERS_BYTES, 0) };
            memory_barrier(
                d,
                cmd,
                (
                    vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags2::GEOMETRY_SHADER,
                    vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
                ),
            );
        }
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
        if frame.shadows {
            let map = &frame.shadow;
            unsafe {
                raw.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.pipeline_layout.raw(),
                    0,
                    &[frame.light_sets[current]],
                    &[],
                );
            }
            // The fur pass reads its triangles from a storage buffer: no vertex or index
            // buffers to bind.
            shadow_pass::record(d, cmd, map, &self.fur_pass, self.index_count);
        }
        self.target.begin(d, cmd);
        self.timestamp(cmd, slot, TS_START);
        let extent = self.target.extent;
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: BACKGROUND.extend(1.0).to_array(),
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
        ];
        let color = [self.target.color_attachment(clear[0])];
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
        begin_rendering(d, cmd, &rendering, extent);
        unsafe {
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
            self.mesh_pass.draw(d, cmd, self.index_count, frame.shadows);
            d.end_label(cmd);
        }
        self.timestamp(cmd, slot, TS_MESH);
        if settings.draw_fur {
            d.begin_label(cmd, "fur pass");
            self.fur_pass
                .draw(d, cmd, self.index_count, &frame.variants);
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
            // Written once every command before it has finished (BOTTOM_OF_PIPE in the
            // first scope is every stage): the passes' ends, not a stage of them.
            let stage = vk::PipelineStageFlags2::BOTTOM_OF_PIPE;
            unsafe {
                self.device
                    .raw
                    .cmd_write_timestamp2(cmd, stage, q.raw(), query)
            };
        }
    }
}
