//! A running fur scene: mesh, master hairs, strand textures, simulation and renderer,
//! advanced frame by frame. The CLI's `render` and the benchmarks drive it.

use std::sync::Arc;

use ash::vk;

use crate::error::Error;
use crate::error::Result;
use crate::gpu::Device;
use crate::render::{FrameReport, FrameSettings, Renderer, RgbaImage};
use crate::scene::{Camera, GroomParams, Mesh, Strands};
use crate::sim::{GpuSim, Motion, SimParams};
use crate::strand_textures::StrandTextures;

/// A scene described relative to the model's size, so one set of defaults suits any
/// model: lengths are fractions of the bounding radius.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptions {
    /// Hair length as a fraction of the bounding radius.
    pub hair_length: f32,
    pub segments: u32,
    pub comb: f32,
    pub curl: f32,
    /// Multiplies the default interpolated-hair density.
    pub density_scale: f32,
    pub yaw_deg: f32,
    pub pitch_deg: f32,
    /// Camera distance in bounding radii.
    pub distance: f32,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self {
            hair_length: 0.2,
            segments: 16,
            comb: 0.9,
            curl: 0.0,
            density_scale: 1.0,
            yaw_deg: 25.0,
            pitch_deg: 15.0,
            distance: 2.6,
        }
    }
}

impl SceneOptions {
    /// The groom and frame settings for `mesh`.
    pub fn resolve(&self, mesh: &Mesh) -> Result<(GroomParams, FrameSettings)> {
        for (name, v) in [
            ("hair length", self.hair_length),
            ("camera distance", self.distance),
            ("density scale", self.density_scale),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::Parameter(format!(
                    "{name} must be a positive number, got {v}"
                )));
            }
        }
        let (center, radius) = mesh.bounds();
        let groom = GroomParams {
            segments: self.segments,
            segment_length: self.hair_length * radius / self.segments.max(1) as f32,
            comb_strength: self.comb,
            curl: self.curl,
            ..Default::default()
        };
        let mut settings = FrameSettings {
            camera: Camera {
                target: center,
                yaw_deg: self.yaw_deg,
                pitch_deg: self.pitch_deg,
                distance: self.distance * radius,
                ..Default::default()
            },
            ..Default::default()
        };
        // Density and widths are per scene unit; scale them with the model.
        let style = &mut settings.style;
        style.density *= self.density_scale / (radius * radius);
        style.hair_width *= radius;
        style.jitter *= radius;
        style.lod_distance *= radius;
        style.validate()?;
        groom.validate()?;
        Ok((groom, settings))
    }
}

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
