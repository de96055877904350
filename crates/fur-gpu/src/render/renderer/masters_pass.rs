//! The master hairs' views: `--show masters`, the master hairs alone as line strips
//! coloured by master index over the body (the seed's picture of the groom before
//! interpolation), and `--show simulation`, the same lines coloured by how far the
//! simulation moved each vertex from rest (the kernel's probe, see
//! `GpuSim::set_probe`). The same positions the fur pass interpolates (the
//! simulation's current state), drawn without tessellation or geometry stages.

use std::sync::Arc;

use ash::vk;

use super::super::graph::{FrameContext, Pass};
use super::super::pipeline::{
    graphics_pipeline, Blend, ColourAttachment, DepthAttachment, GraphicsDesc,
};
use super::super::target::{sample_flag, COLOR_FORMAT, DEPTH_FORMAT};
use super::registry::{Build, FramePass, Phase, Plan, Registered};
use crate::error::Result;
use crate::frame::{uses, Resource, Use};
use crate::gpu::{Access, Device, Pipeline, PipelineLayout, ShaderModule};
use fur_core::render::Stage;

pub struct MastersPass {
    device: Arc<Device>,
    vertices_per_strand: u32,
    strand_count: u32,
    /// Per sample count of the target and view, built on first use.
    pipelines: Vec<((u32, Stage), Pipeline)>,
    /// The simulation view's arrows, per sample count, built on first use.
    arrows: Vec<(u32, Pipeline)>,
}

/// Lines drawn by a vertex shader alone: the pipeline's name, the shader and its
/// defines, what it draws and how it meets the depth.
struct Lines<'a> {
    name: &'a str,
    vert: &'a str,
    defines: &'a [(&'static str, String)],
    topology: vk::PrimitiveTopology,
    depth: DepthAttachment,
}

impl MastersPass {
    /// The pass's name (its debug label).
    pub const NAME: &'static str = "masters pass";

    /// Builds the pipelines of view `stage` (with `arrows`) for a target of `samples`
    /// per pixel if they do not exist.
    fn build_pipelines(
        &mut self,
        layout: &PipelineLayout,
        samples: u32,
        stage: Stage,
        arrows: bool,
    ) -> Result<()> {
        if arrows && !self.arrows.iter().any(|(s, _)| *s == samples) {
            let pipeline = self.arrows_pipeline(layout, samples)?;
            self.arrows.push((samples, pipeline));
        }
        if self
            .pipelines
            .iter()
            .any(|(key, _)| *key == (samples, stage))
        {
            return Ok(());
        }
        let mut defines = super::super::bindings::render_defines();
        defines.push(("STAGE_VIEW", stage.code().to_string()));
        let lines = Lines {
            name: "masters pass",
            vert: "masters.vert",
            defines: &defines,
            topology: vk::PrimitiveTopology::LINE_STRIP,
            depth: DepthAttachment::nearest(DEPTH_FORMAT),
        };
        let pipeline = self.lines_pipeline(layout, samples, lines)?;
        self.pipelines.push(((samples, stage), pipeline));
        Ok(())
    }

    /// The simulation view's arrows: line segments over the hairs, tested against
    /// their depth, not written.
    fn arrows_pipeline(&self, layout: &PipelineLayout, samples: u32) -> Result<Pipeline> {
        let defines = super::super::bindings::render_defines();
        let lines = Lines {
            name: "simulation arrows",
            vert: "arrows.vert",
            defines: &defines,
            topology: vk::PrimitiveTopology::LINE_LIST,
            depth: DepthAttachment {
                format: DEPTH_FORMAT,
                compare: vk::CompareOp::LESS_OR_EQUAL,
                write: false,
            },
        };
        self.lines_pipeline(layout, samples, lines)
    }

    /// `lines`' pipeline: no vertex buffers, each line in its flat colour
    /// (`masters.frag`), opaque.
    fn lines_pipeline(
        &self,
        layout: &PipelineLayout,
        samples: u32,
        Lines {
            name,
            vert,
            defines,
            topology,
            depth,
        }: Lines<'_>,
    ) -> Result<Pipeline> {
        let vert = ShaderModule::new(&self.device, vert, defines)?;
        let frag = ShaderModule::new(&self.device, "masters.frag", defines)?;
        graphics_pipeline(
            &self.device,
            layout,
            &GraphicsDesc {
                name,
                stages: &[
                    (vk::ShaderStageFlags::VERTEX, &vert),
                    (vk::ShaderStageFlags::FRAGMENT, &frag),
                ],
                topology,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: None,
                samples: sample_flag(samples),
                colour: &[ColourAttachment {
                    format: COLOR_FORMAT,
                    blend: Blend::Opaque,
                }],
                depth: Some(depth),
            },
        )
    }

    /// Whether `frame` draws the simulation view's arrows.
    fn draws_arrows(frame: &FrameContext<'_>) -> bool {
        frame.settings.show == Stage::Simulation && frame.settings.arrows.step().is_some()
    }
}

impl Registered for MastersPass {
    /// The pass for the renderer's master hairs.
    fn build(build: &Build<'_>) -> Self {
        Self {
            device: build.device.clone(),
            vertices_per_strand: build.strands.vertices_per_strand,
            strand_count: build.strands.strand_count,
            pipelines: Vec::new(),
            arrows: Vec::new(),
        }
    }
}

impl FramePass for MastersPass {
    fn phase(&self) -> Phase {
        Phase::Stage
    }

    fn wanted(&self, plan: &Plan<'_>) -> bool {
        plan.settings.show.draws_masters()
    }

    fn prepare(&mut self, plan: &Plan<'_>) -> Result<()> {
        let show = plan.settings.show;
        let arrows = plan.settings.arrows.step().is_some();
        self.build_pipelines(plan.layout, plan.samples, show, arrows)
    }
}

impl Pass for MastersPass {
    fn name(&self) -> &'static str {
        MastersPass::NAME
    }

    /// The stage's end, timed as the fur's.
    fn timestamp(&self, _frame: &FrameContext<'_>) -> Option<u32> {
        Some(super::super::slot::TS_FUR)
    }

    fn uses(&self, frame: &FrameContext<'_>) -> Vec<Use> {
        let mut list = vec![uses(Resource::Positions, Access::HairStagesSampled)];
        if Self::draws_arrows(frame) {
            list.push(uses(Resource::Probe, Access::HairStagesRead));
        }
        list
    }

    /// One line strip per master hair: an instance each, a vertex per strand vertex.
    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let key = (frame.target.samples, frame.settings.show);
        let Some((_, pipeline)) = self.pipelines.iter().find(|(k, _)| *k == key) else {
            return;
        };
        // SAFETY: recording inside the target's scope; the pipeline was built for its
        // sample count and lives as long as the pass.
        unsafe {
            let raw = &frame.device.raw;
            raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw());
            raw.cmd_draw(cmd, self.vertices_per_strand, self.strand_count, 0, 0);
        }
        if !Self::draws_arrows(frame) {
            return;
        }
        let Some((_, arrows)) = self.arrows.iter().find(|(s, _)| *s == key.0) else {
            return;
        };
        // SAFETY: as above; two vertices per strand vertex, an instance per strand.
        unsafe {
            let raw = &frame.device.raw;
            raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, arrows.raw());
            raw.cmd_draw(cmd, 2 * self.vertices_per_strand, self.strand_count, 0, 0);
        }
    }
}
