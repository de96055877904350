//! Zeroing the hair counters' header before the fur pass counts into it, in frames
//! that count their hairs (`FrameSettings::count_hairs`).

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass};
use super::super::slot::COUNTERS_BYTES;
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use crate::frame::{uses, Resource, Use};
use crate::gpu::Access;

/// Zeroes the hair counters' header. The previous frame's counts have been read (its
/// fence waited on); a capture behind the header is written whole by the frame.
pub struct CounterReset;

impl Registered for CounterReset {
    fn build(_build: &Build<'_>) -> Self {
        CounterReset
    }
}

impl FramePass for CounterReset {
    fn phase(&self) -> Phase {
        Phase::Reset
    }

    /// Frames that count the hairs the fur pass draws (the masters views draw none).
    fn wanted(&self, plan: &Plan<'_>) -> bool {
        plan.settings.count_hairs && !plan.settings.show.draws_masters()
    }
}

impl Pass for CounterReset {
    fn name(&self) -> &'static str {
        "counter reset"
    }

    fn attachments(&self) -> Attachments {
        Attachments::None
    }

    fn uses(&self, _frame: &FrameContext<'_>) -> Vec<Use> {
        vec![uses(Resource::Counters, Access::TransferWrite)]
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        // SAFETY: recording outside a rendering scope; the counters belong to the slot,
        // whose previous frame has finished.
        unsafe {
            frame
                .device
                .raw
                .cmd_fill_buffer(cmd, frame.slot.counters.raw(), 0, COUNTERS_BYTES, 0)
        };
    }
}
