//! Image quality against cost: one still frame of a scene, drawn with given settings
//! and compared with a supersampled reference of the same frame. The frame is taken
//! after the hair has settled for a moment under gravity, wind and a shake, so the
//! strands are bent as they are in motion, not straight as groomed.
//!
//! The reference is the frame at `factor`× the width and height, drawn the most exact
//! way the renderer has (ribbons of the true width, 4× MSAA, lighting per fragment,
//! every strand vertex), with every pixel-based limit (minimum hair width, LOD) taken
//! at the final image's pixel size, then box-filtered down in linear light: 16 × 4
//! samples per pixel at the default factor 4.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::metrics::{median, Frames};
use fur_core::render::{FrameSettings, FurStyle, Lighting, RgbaImage};
use fur_core::scene::{Mesh, Strands, Texture};
use fur_core::scene_file::Scene;
use fur_core::sim::Motion;
use fur_gpu::error::Result;
use fur_gpu::gpu::Device;
use fur_gpu::render::{HairCounts, Renderer};
use fur_gpu::session::{FurSession, SessionSetup};
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;

/// Simulated frames before the shot.
const SETTLE_FRAMES: usize = 20;

/// A still frame of a scene, ready to be drawn in different ways.
pub struct Shot {
    device: Arc<Device>,
    pub mesh: Mesh,
    pub settings: FrameSettings,
    pub extent: vk::Extent2D,
    /// The scene's size: style settings given in bounding radii scale with it.
    pub radius: f32,
    textures: StrandTextures,
    /// The scene's colour texture, if it has one.
    texture: Option<Texture>,
}

/// How a [`Shot`] is drawn: the fur's style, the lighting, with or without the texture.
#[derive(Clone)]
pub struct Look {
    pub style: FurStyle,
    pub lighting: Lighting,
    pub textured: bool,
}

/// One drawing of a [`Shot`].
pub struct Drawn {
    pub image: RgbaImage,
    /// Median wall-clock milliseconds of a whole frame (clear, both passes, resolve,
    /// copy to the host) over the measured frames.
    pub frame_ms: f64,
    pub counts: Option<HairCounts>,
}

impl Shot {
    /// The frame of `scene` after its simulation and motion have run for a moment.
    pub fn new(device: &Arc<Device>, scene: &Scene, extent: vk::Extent2D) -> Result<Self> {
        let mesh = scene.model.prepare(scene.options.texture.as_ref())?.0;
        let (groom, mut settings) = scene.options.resolve(&mesh)?;
        let strands = Strands::grow(&mesh, &groom)?;
        let mut textures = StrandTextures::new(device, &strands, settings.head)?;
        let radius = mesh.bounds().1;
        let motion = scene.motion.motion(radius);
        let mut sim = GpuSim::new(device, &textures, scene.sim.clone())?;
        sim.run_frames(&mut textures, SETTLE_FRAMES, |t| motion.head(t))?;
        settings.head = motion.head(sim.time).as_mat4();
        let texture = mesh.texture.as_ref().map(|t| t.load()).transpose()?;
        Ok(Self {
            device: device.clone(),
            radius,
            mesh,
            settings,
            extent,
            textures,
            texture,
        })
    }

    /// The frame of `scene`'s animated body (the critter walking) after `frames`
    /// frames of its clip, simulated with its skinned body: the body as posed then and
    /// the hair as simulated, kept as a still. Its root frames come from the posed
    /// hair, so interpolated hairs orient as on the posed surface.
    pub fn walking(
        device: &Arc<Device>,
        scene: &Scene,
        extent: vk::Extent2D,
        frames: u32,
    ) -> Result<Self> {
        let name = scene.model.name();
        let (mesh, rig, _) = scene.model.prepare_body(scene.options.texture.as_ref())?;
        let Some((rig, playback)) = scene.animation.resolve(rig, &name)? else {
            return Err(fur_gpu::error::Error::parameter(format!(
                "{name} has no clip to play"
            )));
        };
        let (groom, mut settings) = scene.options.resolve(&mesh)?;
        if scene.options.distance.is_none() {
            scene
                .options
                .frame_poses(&mut settings, &mesh, &rig, &playback, frames);
        }
        let radius = mesh.bounds().1;
        let mut session = FurSession::new(
            device,
            SessionSetup {
                mesh: mesh.clone(),
                rig: Some((rig, playback)),
                groom: &groom,
                sim: scene.sim.clone(),
                motion: Motion::still(),
                settings,
                extent,
                frames_in_flight: 1,
            },
        )?;
        for _ in 0..frames {
            fur_core::interrupt::check()?;
            session.step_and_render()?;
        }
        let (positions, normals) = session.posed_body()?.ok_or_else(|| {
            fur_gpu::error::Error::parameter(format!("{name}'s body is not skinned"))
        })?;
        let posed = Mesh {
            positions,
            normals,
            ..mesh
        };
        let settings = session.settings.clone();
        let model = settings.head.inverse();
        let textures = &session.textures;
        let strands = Strands {
            vertices_per_strand: session.strands.vertices_per_strand,
            positions: textures
                .read_positions(textures.current)?
                .into_iter()
                .map(|p| model.transform_point3(p))
                .collect(),
        };
        drop(session);
        let textures = StrandTextures::new(device, &strands, settings.head)?;
        // The simulation's rest pass fills the root frames the drawing reads.
        drop(GpuSim::new(device, &textures, scene.sim.clone())?);
        let texture = posed.texture.as_ref().map(|t| t.load()).transpose()?;
        Ok(Self {
            device: device.clone(),
            radius,
            mesh: posed,
            settings,
            extent,
            textures,
            texture,
        })
    }

    /// The scene's colour texture, if it has one.
    pub fn texture(&self) -> Option<&Texture> {
        self.texture.as_ref()
    }

    /// The scene's own look with `style`.
    pub fn look(&self, style: &FurStyle) -> Look {
        Look {
            style: style.clone(),
            lighting: self.settings.lighting.clone(),
            textured: self.texture.is_some(),
        }
    }

    /// The frame's style with the drawing choices of `draw` (distances in radii).
    pub fn style(&self, draw: &FurStyle) -> FurStyle {
        FurStyle {
            samples: draw.samples,
            raster: draw.raster,
            nearest: draw.nearest,
            primitive: draw.primitive,
            ribbon_above_px: draw.ribbon_above_px,
            shading: draw.shading,
            vertex_lod_px: draw.vertex_lod_px,
            lod_distance: draw.lod_distance * self.radius,
            thickness_compensation: draw.thickness_compensation,
            ..self.settings.style.clone()
        }
    }

    /// Draws the frame with `style` `warm + measured` times; times the measured ones.
    pub fn draw(&self, style: &FurStyle, frames: Frames) -> Result<Drawn> {
        self.draw_look(&self.look(style), frames)
    }

    /// Draws the frame with `look` `warm + measured` times; times the measured ones.
    pub fn draw_look(&self, look: &Look, Frames { warm, measured }: Frames) -> Result<Drawn> {
        let frames = Frames {
            warm,
            measured: measured.max(1),
        };
        self.draw_at(look, self.extent, 1, frames, true)
    }

    fn draw_at(
        &self,
        look: &Look,
        extent: vk::Extent2D,
        supersample: u32,
        Frames { warm, measured }: Frames,
        count: bool,
    ) -> Result<Drawn> {
        let mut renderer = self.renderer(look, extent)?;
        let mut settings = FrameSettings {
            style: look.style.clone(),
            lighting: look.lighting.clone(),
            supersample,
            ..self.settings.clone()
        };
        let mut ms = Vec::new();
        let mut image = None;
        for frame in 0..warm + measured {
            fur_core::interrupt::check()?;
            let start = Instant::now();
            image = Some(renderer.render(&self.textures, &settings)?.0);
            if frame >= warm {
                ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let mut counts = None;
        if count {
            // One more frame, counted (the atomics would perturb the timing).
            settings.count_hairs = true;
            let (counted, report) = renderer.render(&self.textures, &settings)?;
            image = Some(counted);
            counts = report.counts;
        }
        Ok(Drawn {
            image: image.unwrap_or_else(|| renderer.target.pixels()),
            frame_ms: median(&ms),
            counts,
        })
    }

    /// A renderer of this frame into `extent` for `look` (its texture, if it takes it,
    /// and sample count).
    fn renderer(&self, look: &Look, extent: vk::Extent2D) -> Result<Renderer> {
        let texture = self.texture.as_ref().filter(|_| look.textured);
        Renderer::textured(
            &self.device,
            &self.mesh,
            texture,
            &self.textures,
            extent,
            1,
            look.style.samples,
        )
    }

    /// The frame drawn with `look`, with every hair it draws captured (for the
    /// path-traced truth), and the settings it was drawn with.
    pub fn capture(
        &self,
        look: &Look,
    ) -> Result<(RgbaImage, fur_gpu::render::CapturedHairs, FrameSettings)> {
        let mut renderer = self.renderer(look, self.extent)?;
        let settings = FrameSettings {
            style: look.style.clone(),
            lighting: look.lighting.clone(),
            ..self.settings.clone()
        };
        let (image, hairs) = renderer.capture(&self.textures, &settings)?;
        Ok((image, hairs, settings))
    }

    /// The supersampled reference of this frame (see the module documentation).
    pub fn reference(&self, factor: u32) -> Result<RgbaImage> {
        self.reference_of(&self.look(&self.settings.style), factor)
    }

    /// The supersampled reference of the frame with `look`'s lighting and texture;
    /// hairs cover their sub-pixels by their true width (thin-hair AA).
    pub fn reference_of(&self, look: &Look, factor: u32) -> Result<RgbaImage> {
        let style = FurStyle {
            thin_hair_aa: true,
            ..self.style(&FurStyle {
                lod_distance: self.settings.style.lod_distance / self.radius,
                thickness_compensation: self.settings.style.thickness_compensation,
                ..FurStyle::default().reference_quality()
            })
        };
        let extent = vk::Extent2D {
            width: self.extent.width * factor,
            height: self.extent.height * factor,
        };
        let look = Look {
            style,
            ..look.clone()
        };
        let big = self.draw_at(&look, extent, factor, Frames::STILL, false)?;
        Ok(big.image.downsample(factor)?)
    }
}
