//! The density view (`--show density`): the body's triangles through the fur pass's
//! own vertex and tessellation control stages (the same levels, the same culling),
//! tessellated into triangles instead of points (`density.tese`), each emitted by the
//! geometry stage in the colour of its inner level and outlined (`density.geom`,
//! `density.frag`). The mesh pass draws the body beneath, hatched: what shows of it
//! is the triangles the control stage culled.

use std::sync::Arc;

use ash::vk;

use super::super::graph::{FrameContext, Pass};
use super::super::pipeline::{
    graphics_pipeline, Blend, ColourAttachment, DepthAttachment, GraphicsDesc,
};
use super::super::target::{sample_flag, COLOR_FORMAT, DEPTH_FORMAT};
use super::fur_pass::hair_uses;
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use crate::error::Result;
use crate::frame::Use;
use crate::gpu::{Device, Pipeline, PipelineLayout, ShaderModule};
use fur_core::render::Stage;

pub struct DensityPass {
    device: Arc<Device>,
    /// Whether the body is skinned (its rest triangles set the levels).
    skinned: bool,
    /// Whether the control stage counts the triangles it culls.
    counts: bool,
    /// Per sample count of the target, built on first use.
    pipelines: Vec<(u32, Pipeline)>,
}

impl DensityPass {
    /// The pass's name (its debug label).
    pub const NAME: &'static str = "density pass";

    /// Builds the pipeline for a target of `samples` per pixel if it does not exist.
    fn build_pipeline(&mut self, layout: &PipelineLayout, samples: u32) -> Result<()> {
        if self.pipelines.iter().any(|(s, _)| *s == samples) {
            return Ok(());
        }
        let flag = |on: bool| u32::from(on).to_string();
        let shared = super::super::bindings::render_defines();
        let mut defines = vec![
            ("COUNT_HAIRS", flag(self.counts)),
            ("BODY_SKINNED", flag(self.skinned)),
            ("TEXTURED", flag(false)),
        ];
        defines.extend(shared.iter().cloned());
        let device = &self.device;
        let vert = ShaderModule::new(device, "fur.vert", &shared)?;
        let tesc = ShaderModule::new(device, "fur.tesc", &defines)?;
        let tese = ShaderModule::new(device, "density.tese", &shared)?;
        let geom = ShaderModule::new(device, "density.geom", &shared)?;
        let frag = ShaderModule::new(device, "density.frag", &shared)?;
        let pipeline = graphics_pipeline(
            device,
            layout,
            &GraphicsDesc {
                name: "density pass",
                stages: &[
                    (vk::ShaderStageFlags::VERTEX, &vert),
                    (vk::ShaderStageFlags::TESSELLATION_CONTROL, &tesc),
                    (vk::ShaderStageFlags::TESSELLATION_EVALUATION, &tese),
                    (vk::ShaderStageFlags::GEOMETRY, &geom),
                    (vk::ShaderStageFlags::FRAGMENT, &frag),
                ],
                topology: vk::PrimitiveTopology::PATCH_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: Some(3),
                samples: sample_flag(samples),
                colour: &[ColourAttachment {
                    format: COLOR_FORMAT,
                    blend: Blend::Opaque,
                }],
                depth: Some(DepthAttachment::nearest(DEPTH_FORMAT)),
            },
        )?;
        self.pipelines.push((samples, pipeline));
        Ok(())
    }
}

impl Registered for DensityPass {
    fn build(build: &Build<'_>) -> Self {
        Self {
            device: build.device.clone(),
            skinned: build.body.skinned,
            counts: build.device.info.vertex_pipeline_stores,
            pipelines: Vec::new(),
        }
    }
}

impl FramePass for DensityPass {
    fn phase(&self) -> Phase {
        Phase::Stage
    }

    fn wanted(&self, plan: &Plan<'_>) -> bool {
        plan.settings.show == Stage::Density
    }

    fn prepare(&mut self, plan: &Plan<'_>) -> Result<()> {
        self.build_pipeline(plan.layout, plan.samples)
    }
}

impl Pass for DensityPass {
    fn name(&self) -> &'static str {
        DensityPass::NAME
    }

    /// The stage's end, timed as the fur's.
    fn timestamp(&self, _frame: &FrameContext<'_>) -> Option<u32> {
        Some(super::super::slot::TS_FUR)
    }

    fn uses(&self, frame: &FrameContext<'_>) -> Vec<Use> {
        hair_uses(self.skinned, frame.settings.count_hairs)
    }

    /// One patch per body triangle, as the fur pass draws them.
    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let samples = frame.target.samples;
        let Some((_, pipeline)) = self.pipelines.iter().find(|(s, _)| *s == samples) else {
            return;
        };
        // SAFETY: recording inside the target's scope with the sets bound; the pipeline
        // was built for its sample count and lives as long as the pass.
        unsafe {
            let raw = &frame.device.raw;
            raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw());
            raw.cmd_draw(cmd, frame.index_count, 1, 0, 0);
        }
    }
}
