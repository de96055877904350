//! What the compute rasteriser counts in a frame ([`ComputeCounts`]), and zeroing the
//! counts before the fur pass's geometry stage writes strands into its pools, in
//! frames that draw their strands in compute: the counts are also the pools' cursors
//! and the binning's indirect dispatch ([`CountWords::start`]).

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass};
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use super::Renderer;
use crate::frame::{uses, Resource, Use};
use crate::gpu::Access;

/// What the compute passes counted in a frame. The fragment counts are 64-bit: a
/// frame of 16384×16384 pixels with a few dozen fragments each takes more than 2³²,
/// which the passes carry into a high word (`RasterCounts` in
/// `shaders/strand_raster.glsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ComputeCounts {
    pub vertices: u32,
    pub segments: u32,
    /// Hairs that found the vertex or segment pool full: not drawn.
    pub hairs_lost: u32,
    /// Hairs with a vertex behind the eye: not drawn.
    pub hairs_clipped: u32,
    /// (segment, tile) entries listed.
    pub entries: u32,
    /// Entries that found the entry pool full: those segments are missing from those tiles.
    pub entries_lost: u32,
    /// Fragments blended in a pixel's tail rather than in depth order.
    pub tail_fragments: u64,
    /// Pixels that stopped, opaque, before their tile's list ended.
    pub pixels_stopped: u32,
    /// Fragments the pixels took (every segment's share of a pixel in front of the
    /// body: kept in order, merged with its strand's or blended in a tail).
    pub fragments: u64,
}

/// The counts as the passes write them (`RasterCounts` in `shaders/strand_raster.glsl`):
/// also the pools' cursors and the binning's indirect dispatch. A fragment count's low
/// word wraps past 2³² and each add that wrapped it adds one to its high word.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct CountWords {
    vertices: u32,
    segments: u32,
    pub(super) bin_groups: [u32; 3],
    hairs_lost: u32,
    hairs_clipped: u32,
    entries: u32,
    entries_lost: u32,
    tail_fragments: u32,
    pixels_stopped: u32,
    fragments: u32,
    tail_fragments_high: u32,
    fragments_high: u32,
    /// The sort and fine passes' indirect dispatch over the tiles that list something.
    pub(super) listed_groups: [u32; 3],
    listed_tiles: u32,
}

impl ComputeCounts {
    /// The bytes of a frame slot's counts buffer, as the passes lay it out.
    pub const BUFFER_BYTES: u64 = std::mem::size_of::<CountWords>() as u64;
}

impl CountWords {
    /// The counts a frame starts from: nothing, and indirect dispatches of no groups.
    pub(super) fn start() -> Self {
        Self {
            bin_groups: [0, 1, 1],
            listed_groups: [0, 1, 1],
            ..Self::default()
        }
    }
}

impl From<CountWords> for ComputeCounts {
    fn from(w: CountWords) -> Self {
        let wide = |low: u32, high: u32| u64::from(high) << 32 | u64::from(low);
        Self {
            vertices: w.vertices,
            segments: w.segments,
            hairs_lost: w.hairs_lost,
            hairs_clipped: w.hairs_clipped,
            entries: w.entries,
            entries_lost: w.entries_lost,
            tail_fragments: wide(w.tail_fragments, w.tail_fragments_high),
            pixels_stopped: w.pixels_stopped,
            fragments: wide(w.fragments, w.fragments_high),
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
        let start = CountWords::start();
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The high words carry: a wide count is its high word times 2³² plus its low word,
    /// each count from its own words (a swapped or dropped high word fails).
    #[test]
    fn a_fragment_count_joins_its_high_word() {
        let words = CountWords {
            fragments: 7,
            fragments_high: 3,
            tail_fragments: u32::MAX,
            tail_fragments_high: 1,
            ..CountWords::start()
        };
        let counts = ComputeCounts::from(words);
        assert_eq!(counts.fragments, 3 * (1u64 << 32) + 7);
        assert_eq!(counts.tail_fragments, (1u64 << 32) + u64::from(u32::MAX));
    }
}
