//! The compute rasteriser's steps as passes of the frame: what each declares it uses
//! (the graph derives the barriers) and records.

use ash::vk;

use super::super::graph::{Attachments, FrameContext, Pass};
use super::compute_raster::scatter_groups;
use super::strand_counts_reset::CountWords;
use crate::frame::{uses, Resource, Use};
use crate::gpu::{whole_image_copy, Access};

/// The name of the fur's last pass when its strands are drawn in compute.
pub const LAST_NAME: &str = "strand target hand-back";

/// The compute steps that do work after the geometry stage, in the order they run:
/// each is timed from the previous one's end (`FrameReport::raster_steps_ms`).
pub const STEP_NAMES: [&str; 9] = [
    "strand lighting",
    "strand tiles",
    "strand bin count",
    "strand bin scan",
    "strand bin scatter",
    "strand bin sort",
    "strand fine raster",
    "strand composite",
    "strand composite copy",
];

/// The lighting pass (`strand_shade.comp`): the lit frame's strands under the Marschner
/// model, lit in compute (`shaders/fur.geom` says why), through the shadow map with
/// `shadows`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StrandLighting {
    pub shadows: bool,
}

impl StrandLighting {
    /// The lighting pass's defines.
    pub(super) fn defines(self) -> [(&'static str, String); 3] {
        let flag = |on: bool| u32::from(on).to_string();
        [
            ("SHADOWS", flag(self.shadows)),
            ("TEXTURED", flag(false)),
            ("STAGE_VIEW", "0".to_string()),
        ]
    }
}

/// The workgroups a CPU driver lights the strands in (`strand_shade.comp`, whose
/// invocations each take every so-many-th vertex): lavapipe pays for each workgroup it
/// starts, and the lighting pass's large program started thousands (one per 64
/// segments) for about 6 % of the blob's Marschner frame at 320×180. Enough for 64
/// cores.
const CPU_LIGHTING_GROUPS: u32 = 64;

/// The most vertices one invocation of the lighting pass lights on a CPU driver: its
/// loop stays under lavapipe's limit on a loop's turns (65,535).
const CPU_LIGHTING_TURNS: u64 = 32_768;

/// The workgroups the lighting pass runs as, for pools of `vertices` vertices: on a CPU
/// driver (`cpu`) a few, [`CPU_LIGHTING_GROUPS`] or as many more as keep each
/// invocation's loop within [`CPU_LIGHTING_TURNS`]; elsewhere as many as the segments
/// ask (None: the indirect dispatch the geometry stage leaves).
pub(super) fn lighting_groups(cpu: bool, vertices: u64) -> Option<u32> {
    let per_group = u64::from(crate::gpu::shader::GROUP_SIZE) * CPU_LIGHTING_TURNS;
    let needed = u32::try_from(vertices.div_ceil(per_group)).unwrap_or(u32::MAX);
    cpu.then_some(needed.clamp(CPU_LIGHTING_GROUPS, 65_535))
}

/// One step of the compute passes, as the frame's pass list holds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Step {
    /// The strand vertices lit under the Marschner model (otherwise the geometry
    /// stage colours them, and the step does no work).
    Shade,
    Tiles,
    Count,
    Scan,
    Scatter,
    Sort,
    Fine,
    Composite,
    Copy,
    HandBack,
}

/// A step and what it records with.
pub(in super::super) struct StepPass {
    pub(super) step: Step,
    pub(super) pipeline: vk::Pipeline,
    /// The tile grid, for the passes dispatched per tile.
    pub(super) grid: (u32, u32),
    /// The composited image and the target's extent, for the copy.
    pub(super) composited: vk::Image,
    pub(super) extent: vk::Extent2D,
    /// Recorded without its work (its barriers stay): for measuring what a step costs
    /// by leaving it out (`Renderer::leave_out_raster_steps`).
    pub(super) left_out: bool,
    /// The lighting pass's workgroups where they are not the indirect count
    /// ([`lighting_groups`]).
    pub(super) lighting_groups: Option<u32>,
}

impl Step {
    /// Every step, in the order a frame runs them.
    pub(super) const ALL: [Step; 10] = [
        Step::Shade,
        Step::Tiles,
        Step::Count,
        Step::Scan,
        Step::Scatter,
        Step::Sort,
        Step::Fine,
        Step::Composite,
        Step::Copy,
        Step::HandBack,
    ];

    /// Its place in [`STEP_NAMES`]: the steps that do work after the geometry stage.
    pub(super) fn timed(self) -> Option<usize> {
        match self {
            Step::HandBack => None,
            Step::Shade => Some(0),
            Step::Tiles => Some(1),
            Step::Count => Some(2),
            Step::Scan => Some(3),
            Step::Scatter => Some(4),
            Step::Sort => Some(5),
            Step::Fine => Some(6),
            Step::Composite => Some(7),
            Step::Copy => Some(8),
        }
    }
}

impl Pass for StepPass {
    fn name(&self) -> &'static str {
        match self.step.timed() {
            Some(i) => STEP_NAMES[i],
            None => LAST_NAME,
        }
    }

    fn attachments(&self) -> Attachments {
        Attachments::None
    }

    /// After each step that does work, its own query (`TS_STRANDS` + 1 + its place in
    /// [`STEP_NAMES`]); after the hand-back, the fur's end.
    fn timestamp(&self, _frame: &FrameContext<'_>) -> Option<u32> {
        use super::super::slot::{TS_FUR, TS_STRANDS};
        match (self.step, self.step.timed()) {
            (_, Some(i)) => Some(TS_STRANDS + 1 + i as u32),
            (Step::HandBack, None) => Some(TS_FUR),
            (_, None) => None,
        }
    }

    fn uses(&self, frame: &FrameContext<'_>) -> Vec<Use> {
        use Access as A;
        use Resource as R;
        match self.step {
            // Nothing to light: the geometry stage coloured the strands.
            Step::Shade if self.pipeline == vk::Pipeline::null() => Vec::new(),
            Step::Shade => {
                let mut list = vec![uses(R::Strands, A::ComputeWrite)];
                // Its dispatch is the count the geometry stage left, unless fixed.
                if self.lighting_groups.is_none() {
                    list.push(uses(R::Strands, A::IndirectRead));
                }
                if frame.slot.shadows {
                    list.push(uses(R::ShadowMap, A::ComputeSampled));
                }
                list
            }
            Step::Tiles => vec![
                uses(R::Depth, A::ComputeSampled),
                uses(R::TileBins, A::ComputeWrite),
            ],
            Step::Count | Step::Scatter => vec![
                uses(R::Strands, A::ComputeRead),
                uses(R::Strands, A::IndirectRead),
                uses(R::TileBins, A::ComputeWrite),
            ],
            Step::Scan => vec![
                uses(R::Strands, A::ComputeWrite),
                uses(R::TileBins, A::ComputeWrite),
            ],
            // Dispatched over the tiles that list something, as the scan counted them.
            Step::Sort => vec![
                uses(R::Strands, A::ComputeWrite),
                uses(R::Strands, A::IndirectRead),
                uses(R::TileBins, A::ComputeWrite),
            ],
            Step::Fine => vec![
                uses(R::Strands, A::ComputeWrite),
                uses(R::Strands, A::IndirectRead),
                uses(R::TileBins, A::ComputeRead),
                uses(R::Depth, A::ComputeSampled),
                uses(R::HairLayer, A::ComputeWrite),
            ],
            Step::Composite => vec![
                uses(R::HairLayer, A::ComputeRead),
                uses(R::TileBins, A::ComputeRead),
                uses(R::Resolve, A::ComputeSampled),
                uses(R::Composited, A::ComputeWrite),
            ],
            Step::Copy => vec![
                uses(R::Composited, A::TransferRead),
                uses(R::Resolve, A::TransferWrite),
            ],
            // The target goes back to being an attachment, as the frame leaves it.
            Step::HandBack => vec![uses(R::Resolve, A::ColorAttachment)],
        }
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let raw = &frame.device.raw;
        let unlit = self.step == Step::Shade && self.pipeline == vk::Pipeline::null();
        if self.left_out || unlit {
            return;
        }
        match self.step {
            Step::HandBack => return,
            Step::Copy => {
                let layers = whole_image_copy(self.extent, 0).image_subresource;
                let region = vk::ImageCopy::default()
                    .src_subresource(layers)
                    .dst_subresource(layers)
                    .extent(vk::Extent3D {
                        width: self.extent.width,
                        height: self.extent.height,
                        depth: 1,
                    });
                // SAFETY: recording outside a scope; the graph left the composited image
                // a transfer source and the target's a transfer destination; both are
                // the target's size and of one texel size (RGBA8).
                unsafe {
                    raw.cmd_copy_image(
                        cmd,
                        self.composited,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        frame.target.resolve.raw(),
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &[region],
                    )
                };
                return;
            }
            _ => {}
        }
        frame.bind_compute_sets(cmd);
        // SAFETY: recording outside a rendering scope, the sets bound; the pipeline and
        // the counts buffer (the indirect arguments at `bin_groups` and `listed_groups`)
        // outlive the frame.
        unsafe {
            raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            let scatter = scatter_groups(&frame.device.info);
            match (self.step, scatter, self.lighting_groups) {
                (Step::Tiles | Step::Composite, _, _) => {
                    raw.cmd_dispatch(cmd, self.grid.0, self.grid.1, 1)
                }
                (Step::Sort | Step::Fine, _, _) => raw.cmd_dispatch_indirect(
                    cmd,
                    frame.raster_counts,
                    std::mem::offset_of!(CountWords, listed_groups) as u64,
                ),
                (Step::Scan, _, _) => raw.cmd_dispatch(cmd, 1, 1, 1),
                (Step::Shade, _, Some(groups)) => raw.cmd_dispatch(cmd, groups, 1, 1),
                (Step::Scatter, Some(groups), _) => raw.cmd_dispatch(cmd, groups, 1, 1),
                _ => raw.cmd_dispatch_indirect(
                    cmd,
                    frame.raster_counts,
                    std::mem::offset_of!(CountWords, bin_groups) as u64,
                ),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A CPU driver lights the strands in a few workgroups, more only where an
    /// invocation's loop would otherwise pass lavapipe's limit; another device as the
    /// segments ask. Seen failing with the groups left at the floor for any pool.
    #[test]
    fn a_cpu_driver_lights_in_few_workgroups_each_within_the_loop_limit() {
        assert_eq!(lighting_groups(false, 1 << 20), None);
        assert_eq!(lighting_groups(true, 1 << 20), Some(CPU_LIGHTING_GROUPS));
        let group = u64::from(crate::gpu::shader::GROUP_SIZE);
        for vertices in [0, 1 << 20, 33 << 20, 1 << 30, 1 << 34] {
            let groups = u64::from(lighting_groups(true, vertices).unwrap());
            let turns = vertices.div_ceil(groups * group);
            assert!(turns <= CPU_LIGHTING_TURNS, "{vertices}: {turns} turns");
        }
    }

    /// The steps that do work are timed in order, one query each, and named by
    /// [`STEP_NAMES`] in that order. Seen failing with a step left out of `timed`.
    #[test]
    fn every_timed_step_has_its_own_name_and_query() {
        let timed: Vec<usize> = Step::ALL.iter().filter_map(|s| s.timed()).collect();
        assert_eq!(timed, (0..STEP_NAMES.len()).collect::<Vec<_>>());
    }
}
