//! A running fur scene: mesh, master hairs, strand textures, simulation and renderer,
//! advanced frame by frame. The CLI's `render` and the benchmarks drive it.

use std::sync::Arc;

use ash::vk;
use glam::DMat4;

use crate::error::Error;
use crate::error::Result;
use crate::gpu::Device;
use crate::render::{FrameReport, Renderer};
use crate::sim::GpuSim;
use crate::strand_textures::StrandTextures;
use fur_core::render::{FrameSettings, RgbaImage, Stage};
use fur_core::scene::{DrawnGroom, GroomParams, HairPatches, Mesh, Rig, Strands};
use fur_core::sim::{Motion, Sdf, SdfReport, SimParams};
use fur_core::skinning::{Playback, SkinnedBody};

mod options;

pub use options::{check_work, MAX_SEGMENTS_PER_FRAME, MAX_STRAND_VERTICES, MAX_TARGET_BYTES};

/// What a frame reports beyond the image.
#[derive(Clone, Debug)]
pub struct FrameTimings {
    pub render: FrameReport,
    /// GPU milliseconds of the frame's simulation substeps (NaN when not simulated).
    pub simulation_ms: f64,
}

/// What a session is built from: the body and the fur grown on it, how the fur moves
/// and is drawn, and the frames it renders.
pub struct SessionSetup<'a> {
    /// The body the fur grows on.
    pub mesh: Mesh,
    /// For a skinned body: its rig (vertex-aligned with `mesh`) and the clip it plays.
    /// The body is then skinned on the device every frame, each master hair follows
    /// its own root pose, and the default comb follows the bones. None: a rigid body.
    pub rig: Option<(Rig, Playback)>,
    /// How the master hairs are grown.
    pub groom: &'a GroomParams,
    /// The strand simulation's parameters.
    pub sim: SimParams,
    /// The scripted motion of the head (the whole model).
    pub motion: Motion,
    /// Camera, lighting and drawing of each frame.
    pub settings: FrameSettings,
    /// The size of the rendered image, in pixels.
    pub extent: vk::Extent2D,
    /// Frames recorded ahead of the device: 1 for headless use, 2 for the viewer.
    pub frames_in_flight: usize,
}

pub struct FurSession {
    device: Arc<Device>,
    pub mesh: Mesh,
    pub strands: Strands,
    pub textures: StrandTextures,
    pub sim: GpuSim,
    /// The body's distance field and what building it found, when collision is on.
    pub body: Option<(Arc<Sdf>, SdfReport)>,
    pub renderer: Renderer,
    pub motion: Motion,
    /// Where the user has put the model (the viewer moves it; identity otherwise).
    pub user: DMat4,
    pub settings: FrameSettings,
    /// What building the scene warned about (e.g. collision switched off).
    pub warnings: Vec<String>,
    /// With a drawn groom (`--groom-mode draw`), the first of the guides' master hairs
    /// (those before are the body's own vertices').
    pub first_guide: Option<usize>,
}

impl FurSession {
    /// Everything building the scene warned about, for model `name`: the body's field
    /// (an open or inconsistently oriented surface), then the rest.
    pub fn all_warnings(&self, name: &str) -> Vec<String> {
        let field = self
            .body
            .as_ref()
            .and_then(|(_, report)| report.warning(name));
        field
            .into_iter()
            .chain(self.warnings.iter().cloned())
            .collect()
    }

    /// Builds the scene `setup` describes.
    pub fn new(device: &Arc<Device>, setup: SessionSetup<'_>) -> Result<Self> {
        let SessionSetup {
            mesh,
            rig,
            groom,
            sim: sim_params,
            motion,
            settings,
            extent,
            frames_in_flight,
        } = setup;
        settings.style.validate()?;
        motion.validate()?;
        sim_params.validate()?;
        check_work(&mesh, groom, &settings, extent)?;
        let mut warnings = Vec::new();
        // A drawn groom: the guides' roots join the body as vertices of their own, with
        // their master hairs and patches (fur_core::scene::DrawnGroom).
        let (mesh, rig, drawn) = match (groom.drawn_source(), rig) {
            (Some(source), rig) => {
                let (rig, playback) = rig.map_or((None, None), |(r, p)| (Some(r), Some(p)));
                let drawn = DrawnGroom::from_file(mesh, rig, groom, source)?;
                warnings.extend(drawn.warnings());
                let first = drawn.body_vertices;
                let rig = drawn.rig.zip(playback);
                (drawn.mesh, rig, Some((drawn.strands, drawn.patches, first)))
            }
            (None, rig) => (mesh, rig, None),
        };
        let mut groom = groom.clone();
        let skinned = match rig {
            Some((rig, playback)) => {
                rig.validate(mesh.vertex_count())
                    .map_err(|m| Error::parameter(format!("the model's skin: {m}")))?;
                groom.comb_field = Some(fur_core::skinning::fur_flow(&rig));
                Some(crate::sim::SkinnedMotion {
                    body: Arc::new(SkinnedBody::new(&mesh, rig)),
                    playback,
                })
            }
            None => None,
        };
        if sim_params.skin_blend == Some(true) && (skinned.is_none() || !sim_params.collision) {
            warnings.push(format!(
                "the skin's blend changes nothing here: {}",
                if skinned.is_none() {
                    "the model has no skin (a rigid body keeps its field built once)"
                } else {
                    "collision is off"
                }
            ));
        }
        let groom = &groom;
        let (strands, patches, first_guide) = match drawn {
            Some((strands, patches, first)) => (strands, patches, Some(first)),
            None => {
                let (strands, groom_warnings) = Strands::grow_reported(&mesh, groom)?;
                warnings.extend(groom_warnings);
                (strands, HairPatches::default(), None)
            }
        };
        let head = motion.head(0.0).as_mat4();
        let textures = StrandTextures::new(device, &strands, head)?;
        let body = if sim_params.collision {
            let (sdf, report) =
                Sdf::for_hair(&mesh, &sim_params, textures.hair_length, skinned.is_some())?;
            Some((Arc::new(sdf), report))
        } else {
            None
        };
        let mut sim_params = sim_params;
        if let (Some(_), Some((sdf, _)), None) = (&skinned, &body, sim_params.skin_blend) {
            // The default blend stands down where its grid does not fit; asked for, it is
            // refused there, naming the limit.
            let limit = device.info.limits.max_image_dimension3_d;
            let misfit = fur_core::skinning::blend::misfit(sdf, limit);
            if let Some(why) = &misfit {
                warnings.push(format!(
                    "{why}: collision goes without it (hair may sink into skin that bends \
                     between bones); lower --sdf-resolution to keep it"
                ));
            }
            sim_params.skin_blend = Some(misfit.is_none());
        }
        let sim = GpuSim::build(
            device,
            &textures,
            sim_params,
            frames_in_flight,
            body.as_ref().map(|(sdf, _)| &**sdf),
            skinned,
        )?;
        let texture = match &mesh.texture {
            Some(_) if mesh.uvs.is_empty() => {
                return Err(Error::parameter(
                    "the model has no texture coordinates (`vt` on every face), so it cannot \
                     take a texture",
                ))
            }
            Some(spec) => Some(spec.load()?),
            None => None,
        };
        let renderer = Renderer::for_body(
            device,
            &mesh,
            &patches,
            texture.as_ref(),
            &textures,
            crate::render::TargetSpec {
                extent,
                frames_in_flight,
                samples: settings.style.samples,
            },
            sim.skinned.as_ref().map(|s| s.skin.posed.raw()),
        )?;
        Ok(Self {
            device: device.clone(),
            mesh,
            strands,
            textures,
            sim,
            body,
            renderer,
            motion,
            user: DMat4::IDENTITY,
            settings,
            warnings,
            first_guide,
        })
    }

    /// The head transform at simulated time `t`: the user's placement of the model
    /// times the scripted motion.
    pub fn head_at(&self, t: f64) -> DMat4 {
        self.user * self.motion.head(t)
    }

    /// Renders the current state without simulating.
    pub fn render(&mut self) -> Result<(RgbaImage, FrameReport)> {
        self.prepare_frame()?;
        self.renderer.render(&self.textures, &self.settings)
    }

    /// What a change of settings needs before a frame's command buffer is begun: the
    /// simulation view's probe (and its arrows) switched on or off in the kernel, which
    /// rebuilds it and waits for the device (only when the view or arrows change).
    pub fn prepare_frame(&mut self) -> Result<()> {
        let probe = (self.settings.show == Stage::Simulation).then(|| self.settings.arrows.step());
        if self.sim.probe() != probe {
            self.device.wait_idle()?;
            self.sim.set_probe(probe, &mut self.textures)?;
            self.renderer.bind_probe(&self.textures);
        }
        Ok(())
    }

    /// Records one rendered frame into `cmd` using frame slot `slot`: `sim_frames`
    /// simulation frames of `dt` each (all their substeps; 0 when paused) and both render
    /// passes. The slot's previous frame must have finished, and
    /// [`FurSession::prepare_frame`] must have run since the settings last changed. The
    /// resolved image is left for the caller to copy or blit.
    pub fn record_frame(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        sim_frames: usize,
    ) -> Result<()> {
        let (user, motion) = (self.user, self.motion);
        let constants = self
            .sim
            .next_constants(sim_frames, |t| user * motion.head(t));
        self.settings.head = self.head_at(self.sim.time).as_mat4();
        self.renderer.update(slot, &self.settings)?;
        self.renderer.begin_frame(cmd, slot);
        // One tracker through the submission: the skinning and the simulation declare
        // their uses, then the frame's passes, and the barriers follow.
        let mut tracker = crate::frame::tracker();
        if !constants.is_empty() {
            self.sim
                .record(cmd, &mut tracker, slot, &mut self.textures, &constants)?;
        }
        self.renderer.record(
            cmd,
            &mut tracker,
            slot,
            self.textures.current,
            &self.settings,
        );
        Ok(())
    }

    /// GPU timings of slot `slot`'s last frame (waits for its queries).
    pub fn timings(&self, slot: usize, simulated: bool) -> Result<FrameTimings> {
        Ok(FrameTimings {
            render: self.renderer.report(slot, &self.settings)?,
            simulation_ms: if simulated {
                self.sim.last_gpu_ms(slot)?
            } else {
                f64::NAN
            },
        })
    }

    /// A skinned body's last posed positions and normals (model space, before the head
    /// transform), read back from the device; None for a rigid body.
    pub fn posed_body(&self) -> Result<Option<(Vec<glam::Vec3>, Vec<glam::Vec3>)>> {
        let Some(skinned) = &self.sim.skinned else {
            return Ok(None);
        };
        let bytes = skinned.skin.posed.read_back()?;
        let words: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        let (positions, normals) = words
            .chunks_exact(2)
            .map(|v| {
                (
                    glam::Vec4::from(v[0]).truncate(),
                    glam::Vec4::from(v[1]).truncate(),
                )
            })
            .unzip();
        Ok(Some((positions, normals)))
    }

    /// Simulates one frame (all its substeps) and renders it, in one submission.
    pub fn step_and_render(&mut self) -> Result<(RgbaImage, FrameTimings)> {
        self.prepare_frame()?;
        let device = self.device.clone();
        device.submit_once(|cmd| {
            self.record_frame(cmd, 0, 1)?;
            self.renderer.target.copy_out(&device, cmd);
            Ok(())
        })?;
        Ok((self.renderer.target.pixels(), self.timings(0, true)?))
    }
}
