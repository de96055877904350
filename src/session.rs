//! A running fur scene: mesh, master hairs, strand textures, simulation and renderer,
//! advanced frame by frame. The CLI's `render` and the benchmarks drive it.

use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::gpu::Device;
use crate::render::{FrameReport, FrameSettings, Renderer, RgbaImage};
use crate::scene::{GroomParams, Mesh, Strands};
use crate::sim::{GpuSim, Motion, SimParams};
use crate::strand_textures::StrandTextures;

/// What a frame reports beyond the image.
#[derive(Clone, Debug)]
pub struct FrameTimings {
    pub render: FrameReport,
    /// GPU milliseconds of the frame's simulation substeps (NaN when not simulated).
    pub simulation_ms: f64,
}

pub struct FurSession {
    device: Arc<Device>,
    pub mesh: Mesh,
    pub strands: Strands,
    pub textures: StrandTextures,
    pub sim: GpuSim,
    pub renderer: Renderer,
    pub motion: Motion,
    pub settings: FrameSettings,
}

impl FurSession {
    pub fn new(
        device: &Arc<Device>,
        mesh: Mesh,
        groom: &GroomParams,
        sim_params: SimParams,
        motion: Motion,
        settings: FrameSettings,
        extent: vk::Extent2D,
    ) -> Result<Self> {
        settings.style.validate()?;
        motion.validate()?;
        sim_params.validate()?;
        let strands = Strands::grow(&mesh, groom)?;
        let head = motion.head(0.0).as_mat4();
        let textures = StrandTextures::new(device, &strands, head)?;
        let sim = GpuSim::new(device, &textures, sim_params)?;
        let renderer = Renderer::new(device, &mesh, &textures, extent)?;
        Ok(Self {
            device: device.clone(),
            mesh,
            strands,
            textures,
            sim,
            renderer,
            motion,
            settings,
        })
    }

    /// Renders the current state without simulating.
    pub fn render(&mut self) -> Result<(RgbaImage, FrameReport)> {
        self.renderer.render(&self.textures, &self.settings)
    }

    /// Simulates one frame (all its substeps) and renders it, in one submission.
    pub fn step_and_render(&mut self) -> Result<(RgbaImage, FrameTimings)> {
        let motion = self.motion;
        let constants = self.sim.next_constants(1, |t| motion.head(t));
        self.settings.head = motion.head(self.sim.time).as_mat4();
        self.renderer.update(&self.settings);
        let device = self.device.clone();
        device.submit_once(|cmd| {
            self.sim.record(cmd, &mut self.textures, &constants)?;
            self.renderer
                .record(cmd, self.textures.current, &self.settings);
            Ok(())
        })?;
        let timings = FrameTimings {
            render: self.renderer.report(&self.settings)?,
            simulation_ms: self.sim.last_gpu_ms()?,
        };
        Ok((self.renderer.target.pixels(), timings))
    }
}
