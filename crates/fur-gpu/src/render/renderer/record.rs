//! Recording a frame: its first timestamp, then the shadow, mesh and fur passes into
//! the target, with timestamps and pipeline statistics around them.

use super::super::graph::{record_frame, Attachments, Event, FrameContext};
use super::*;
use crate::error::Error;
use crate::frame::Resource;
use crate::gpu::{DeviceInfo, Tracker};

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

    /// Records the frame's passes (`Renderer::passes`) into the target, after
    /// [`Renderer::begin_frame`]; the resolved image is left in
    /// `COLOR_ATTACHMENT_OPTIMAL` for [`RenderTarget::copy_out`] or a blit. `current`
    /// selects the position image the simulation last wrote. The barriers between the
    /// passes come from what each declares it uses (`super::super::graph`), after the
    /// uses `tracker` has seen this submission (the skinning's and simulation's).
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        tracker: &mut Tracker<Resource>,
        slot: usize,
        current: usize,
        settings: &FrameSettings,
    ) {
        let d = &*self.device;
        let frame = &self.slots[slot];
        let context = FrameContext {
            device: d,
            layout: &self.pipeline_layout,
            slot: frame,
            current,
            target: &self.target,
            settings,
            index_count: self.index_count,
            hair_index_count: self.hair_index_count,
            indices: self.indices.raw(),
            body_set: self.body_set,
            raster_set: if Self::draws_in_compute(settings) {
                self.compute_raster.set(slot)
            } else {
                vk::DescriptorSet::null()
            },
            raster_counts: self.compute_raster.counts_buffer(slot),
            composited: self.compute_raster.composited(),
        };
        let passes = self.passes(settings, frame.shadows);
        d.begin_label(cmd, "frame");
        record_frame(&context, cmd, tracker, &passes, &mut |event| match event {
            Event::ScopeOpening(Attachments::Target) => {
                self.timestamp(cmd, slot, TS_START);
                // The statistics query spans the whole rendering scope (the mesh pass
                // adds no tessellation or geometry work). Mesa 22.3's lavapipe crashes
                // when such a query begins inside the scope before its first draw.
                if let Some(q) = &frame.statistics {
                    // SAFETY: the pool was reset in `begin_frame`; recording, outside a scope.
                    unsafe {
                        d.raw
                            .cmd_begin_query(cmd, q.raw(), 0, vk::QueryControlFlags::empty())
                    };
                }
            }
            // Each timed pass says which query marks its end (`Pass::timestamp`).
            Event::PassRecorded(_, Some(query)) => self.timestamp(cmd, slot, query),
            Event::ScopeClosed(Attachments::Target) => {
                if let Some(q) = &frame.statistics {
                    // SAFETY: the query was begun before this scope, in this command buffer.
                    unsafe { d.raw.cmd_end_query(cmd, q.raw(), 0) };
                }
            }
            _ => {}
        });
        d.end_label(cmd);
    }

    fn timestamp(&self, cmd: vk::CommandBuffer, slot: usize, query: u32) {
        if let Some(q) = &self.slots[slot].timestamps {
            // Written once every command before it has finished (BOTTOM_OF_PIPE in the
            // first scope is every stage): the passes' ends, not a stage of them.
            let stage = vk::PipelineStageFlags2::BOTTOM_OF_PIPE;
            // SAFETY: the command buffer is recording; the pool holds TIMESTAMPS queries, reset in
            // `begin_frame`, and `query` is one of them.
            unsafe {
                self.device
                    .raw
                    .cmd_write_timestamp2(cmd, stage, q.raw(), query)
            };
        }
    }

    /// Whether a frame of `settings` draws its strands with the compute passes.
    pub(super) fn draws_in_compute(settings: &FrameSettings) -> bool {
        (settings.style.raster == Raster::Compute || settings.show.needs_compute())
            && settings.show.draws_fur()
    }

    /// Refuses a frame of `settings` that a device of `info` cannot draw: strands in
    /// compute where its geometry stage cannot write them out.
    pub(super) fn check_device(info: &DeviceInfo, settings: &FrameSettings) -> Result<()> {
        if Self::draws_in_compute(settings) && !info.vertex_pipeline_stores {
            return Err(Error::parameter(format!(
                "the compute rasteriser (the default, --raster compute, and the tiles view) \
                 needs a device whose geometry stage can write storage buffers \
                 (vertexPipelineStoresAndAtomics), which {} lacks; draw with --raster \
                 hardware (raster = \"hardware\" in the scene file) and another view",
                info.name
            )));
        }
        Ok(())
    }

    /// Renders one frame of the strands' current state and returns the image.
    pub fn render(
        &mut self,
        strands: &StrandTextures,
        settings: &FrameSettings,
    ) -> Result<(RgbaImage, FrameReport)> {
        let device = self.device.clone();
        // Again when the compute rasteriser's pools were too small for the frame: they
        // grow to what it asked for, and it is drawn again whole. Up to three times:
        // the tile entries a frame asks for are known only once all its hairs fit.
        let mut tries = 0;
        loop {
            tries += 1;
            self.update(0, settings)?;
            device.submit_once(|cmd| {
                self.begin_frame(cmd, 0);
                self.record(
                    cmd,
                    &mut crate::frame::tracker(),
                    0,
                    strands.current,
                    settings,
                );
                self.target.copy_out(&device, cmd);
                Ok(())
            })?;
            let report = self.report(0, settings)?;
            let lost = report
                .raster
                .is_some_and(|r| r.hairs_lost > 0 || r.entries_lost > 0);
            if !lost || tries == 3 {
                return Ok((self.target.pixels(), report));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fur_core::render::budget::Ladder;
    use fur_core::render::Raster;

    fn info(device_type: vk::PhysicalDeviceType, stores: bool) -> DeviceInfo {
        DeviceInfo {
            name: "a test device".into(),
            driver: String::new(),
            device_type,
            limits: vk::PhysicalDeviceLimits::default(),
            timestamp_period: 1.0,
            timestamps: true,
            pipeline_statistics: false,
            vertex_pipeline_stores: stores,
            subgroup_size: 8,
        }
    }

    /// A device whose geometry stage cannot write storage buffers is refused strands
    /// in compute (the default), by name and naming the feature and the way out (it
    /// draws them with the fixed-function rasteriser); it is never offered the compute
    /// ladders, nor is a CPU driver, and a GPU that can is, the one that suits the
    /// scene's rasteriser. Seen failing with `prefers_compute_strands` ignoring the
    /// feature.
    #[test]
    fn a_device_that_cannot_write_strands_is_refused_compute_by_name() {
        let gpu = vk::PhysicalDeviceType::DISCRETE_GPU;
        let compute = FrameSettings {
            style: fur_core::render::FurStyle {
                raster: Raster::Compute,
                ..Default::default()
            },
            ..Default::default()
        };
        let error = Renderer::check_device(&info(gpu, false), &compute).unwrap_err();
        assert!(error.is_parameter());
        let message = error.to_string();
        assert!(
            message.contains("vertexPipelineStoresAndAtomics")
                && message.contains("a test device")
                && message.contains("--raster hardware"),
            "{message}"
        );
        assert!(Renderer::check_device(&info(gpu, true), &compute).is_ok());
        let default_error = Renderer::check_device(&info(gpu, false), &FrameSettings::default());
        assert!(default_error.is_err(), "the default draws in compute");
        let hardware = FrameSettings {
            style: fur_core::render::FurStyle {
                raster: Raster::Hardware,
                ..Default::default()
            },
            ..Default::default()
        };
        assert!(Renderer::check_device(&info(gpu, false), &hardware).is_ok());
        assert!(info(gpu, true).prefers_compute_strands());
        assert!(!info(gpu, false).prefers_compute_strands());
        assert!(!info(vk::PhysicalDeviceType::CPU, true).prefers_compute_strands());
        for scene in [Raster::Hardware, Raster::Compute] {
            assert_eq!(info(gpu, false).ladder(scene), Ladder::FIXED);
            let cpu = info(vk::PhysicalDeviceType::CPU, true);
            assert_eq!(cpu.ladder(scene), Ladder::FIXED);
        }
        assert_eq!(info(gpu, true).ladder(Raster::Hardware), Ladder::COMPUTE);
        assert_eq!(info(gpu, true).ladder(Raster::Compute), Ladder::IN_COMPUTE);
    }

    /// On a CPU driver the passes that meet at barriers take a tile a subgroup (one
    /// SIMD vector), held to the tile's pixels; on a GPU an invocation a pixel. Seen
    /// failing with the GPU's workgroup on a CPU driver, and with the subgroup taken on
    /// a GPU.
    #[test]
    fn a_cpu_driver_works_a_tile_with_one_subgroup() {
        use super::super::compute_raster::tile_group;
        let cpu = info(vk::PhysicalDeviceType::CPU, true);
        let gpu = info(vk::PhysicalDeviceType::DISCRETE_GPU, true);
        assert_eq!(tile_group(&cpu, 8), 8);
        assert_eq!(tile_group(&cpu, 16), 8);
        assert_eq!(tile_group(&cpu, 2), 4);
        let wide = DeviceInfo {
            subgroup_size: 32,
            ..cpu.clone()
        };
        assert_eq!(tile_group(&wide, 4), 16);
        assert_eq!(tile_group(&gpu, 8), 64);
        assert_eq!(tile_group(&gpu, 16), 256);
    }
}
