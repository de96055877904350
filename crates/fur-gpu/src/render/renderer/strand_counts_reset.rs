//! What the compute rasteriser counts in a frame ([`ComputeCounts`]), and zeroing the
//! counts before the fur pass's geometry stage writes strands into its pools, in
//! frames that draw their strands in compute: the counts are also the pools' cursors
//! and the binning's indirect dispatch ([`ComputeCounts::start`]).

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass};
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use super::Renderer;
use crate::frame::{uses, Resource, Use};
use crate::gpu::Access;

/// What the compute passes counted in a frame (`ComputeCounts` in
/// `shaders/strand_raster.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ComputeCounts {
    pub vertices: u32,
    pub segments: u32,
    pub(super) bin_groups: [u32; 3],
    /// Hairs that found the vertex or segment pool full: not drawn.
    pub hairs_lost: u32,
    /// Hairs with a vertex behind the eye: not drawn.
    pub hairs_clipped: u32,
    /// (segment, tile) entries listed.
    pub entries: u32,
    /// Entries that found the entry pool full: those segments are missing from those tiles.
    pub entries_lost: u32,
    /// Fragments blended in a pixel's tail rather than in depth order.
    pub tail_fragments: u32,
    /// Pixels that stopped, opaque, before their tile's list ended.
    pub pixels_stopped: u32,
    /// Fragments the pixels took (every segment's share of a pixel in front of the
    /// body: kept in order, merged with its strand's or blended in a tail).
    pub fragments: u32,
}

impl ComputeCounts {
    /// The counts a frame starts from: nothing, and an indirect dispatch of no groups.
    pub(super) fn start() -> Self {
        Self {
            bin_groups: [0, 1, 1],
            ..Self::default()
        }
    }
}

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
