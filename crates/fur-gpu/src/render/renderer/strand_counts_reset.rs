//! Zeroing the compute rasteriser's counts before the fur pass's geometry stage writes
//! strands into its pools, in frames that draw their strands in compute: the counts
//! are also the pools' cursors and the binning's indirect dispatch
//! ([`super::compute_raster::ComputeCounts::start`]).

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass};
use super::compute_raster::ComputeCounts;
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use super::Renderer;
use crate::frame::{uses, Resource, Use};
use crate::gpu::Access;

pub struct StrandCountsReset;

impl Registered for StrandCountsReset {
    fn build(_build: &Build<'_>) -> Self {
        StrandCountsReset
    }
}

impl FramePass for StrandCountsReset {
    fn phase(&self) -> Phase {
        Phase::Reset
    }

    fn wanted(&self, plan: &Plan<'_>) -> bool {
        Renderer::draws_in_compute(plan.settings)
    }
}

impl Pass for StrandCountsReset {
    fn name(&self) -> &'static str {
        "strand counts reset"
    }

    fn attachments(&self) -> Attachments {
        Attachments::None
    }

    fn uses(&self, _frame: &FrameContext<'_>) -> Vec<Use> {
        vec![uses(Resource::Strands, Access::TransferWrite)]
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let start = ComputeCounts::start();
        // SAFETY: recording outside a rendering scope; the counts belong to the slot,
        // whose previous frame has finished.
        unsafe {
            frame
                .device
                .raw
                .cmd_update_buffer(cmd, frame.raster_counts, 0, bytemuck::bytes_of(&start))
        };
    }
}
