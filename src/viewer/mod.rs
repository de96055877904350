//! `fur view`: a window with the live simulation, an orbit camera, a parameter panel
//! and GPU stage timings. Two frames in flight; the swapchain is recreated on resize
//! and rendering pauses while the window is minimised.

mod animation_ui;
mod clock;
mod display;
mod frame;
mod in_flight;
mod input;
mod legend_ui;
mod panel;
mod quality;
mod quality_ui;
mod script;
mod settings_ui;
mod setup;
mod ui;

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec3, Vec3};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::WindowId;

pub use script::{Action, Script};

/// The frame rate `fur view` holds by default (`--target-fps`).
pub const DEFAULT_TARGET_FPS: f64 = 30.0;

use clock::Clock;
use display::Display;
use in_flight::Frames;
use panel::Panel;
use quality::Quality;
use script::Scripted;

use fur_core::scene::Mesh;
use fur_core::scene_file::SceneOptions;
use fur_core::sim::{Motion, MotionKind, SimParams};
use fur_gpu::error::{Error, Result};
use fur_gpu::gpu::Device;
use fur_gpu::session::{FurSession, SessionSetup};

const FRAMES_IN_FLIGHT: usize = 2;

/// What `fur view` was asked to do.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    pub model: fur_core::scene::ModelSpec,
    pub scene: SceneOptions,
    pub sim: SimParams,
    /// The shake the motion toggle switches on (the viewer starts still and shakes
    /// only: another kind of motion in the scene gives the default shake).
    pub motion: fur_core::scene_file::MotionSpec,
    /// The clip a skinned or animated model plays.
    pub animation: fur_core::skinning::AnimationSpec,
    /// Frames per second to hold by lowering the drawing quality (0: off).
    pub target_fps: f64,
    pub vsync: bool,
    /// Exit after this many frames (for tests and benchmarks).
    pub frames: Option<u64>,
    pub validate: bool,
    /// The device to use (`--device`: an index or part of a name); `None`: the default.
    pub device: Option<String>,
    pub width: u32,
    pub height: u32,
    pub script: Script,
    /// Where the screenshot key (F12 or P) writes its PNGs.
    pub screenshot_dir: PathBuf,
    /// Where the panel's state is saved as a scene file (at exit, and by the panel's
    /// button); `fur_scene.toml` for the button when not given.
    pub save_scene: Option<PathBuf>,
}

/// Opens the window and runs until it is closed (or `frames` have been shown).
pub fn run(options: ViewerOptions) -> Result<()> {
    let event_loop = EventLoop::new().map_err(|e| {
        Error::Window(format!(
            "cannot open a window ({e}); is a display available (DISPLAY or WAYLAND_DISPLAY)? \
             For headless output use `fur render`"
        ))
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        options,
        viewer: None,
        result: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Window(format!("the window system failed: {e}")))?;
    let mut viewer = app.viewer.take();
    if let Some(v) = viewer.as_mut() {
        // Frames still in flight may carry a screenshot: finish them all.
        let finished = v.finish_all().and_then(|()| match &v.save_scene {
            Some(path) => v.current_scene().save(path).map_err(Into::into).map(|()| {
                println!("scene saved to {}", path.display());
            }),
            None => Ok(()),
        });
        if let Err(e) = finished {
            if app.result.is_ok() {
                app.result = Err(e);
            }
        }
    }
    if let Some(v) = &viewer {
        if !v.clock.frame_times.is_empty() {
            println!(
                "{} frames: median frame time {:.1} ms; last GPU timings: frame {:.2} ms, simulation {:.2} ms; {} hairs drawn in {} segments; {} simulation steps ({:.4} s simulated)",
                v.clock.frame_times.len() + 1,
                crate::bench::metrics::median(&v.clock.frame_times),
                v.hud.gpu_frame_ms,
                v.hud.sim_ms,
                v.hud.hairs,
                v.hud.segments,
                v.frames_simulated,
                v.session.sim.time,
            );
            if v.quality.budget.is_some() {
                let changes: Vec<String> = v
                    .quality
                    .log
                    .iter()
                    .map(|(frame, rung)| format!("rung {rung} at frame {frame}"))
                    .collect();
                println!(
                    "quality: {}",
                    if changes.is_empty() {
                        "the default drawing throughout".to_string()
                    } else {
                        changes.join(", ")
                    }
                );
                for (r, e) in v.quality.errors.iter().enumerate() {
                    if let Some(e) = e {
                        println!(
                            "measured: rung {r} ({}) ꟻLIP {e:.4} against the default drawing at a still view",
                            v.quality.ladder.rung(r).name
                        );
                    }
                }
            }
        }
    }
    // Destroying the viewer can report problems too: check after it is gone.
    let device = viewer.as_ref().map(|v| v.device.clone());
    drop(viewer);
    app.result?;
    device.map_or(Ok(()), fur_gpu::gpu::shut_down)
}

struct App {
    options: ViewerOptions,
    viewer: Option<Viewer>,
    result: Result<()>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        if self.result.is_ok() {
            self.result = Err(error);
        }
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.viewer.is_some() {
            return;
        }
        match Viewer::new(event_loop, &self.options) {
            Ok(viewer) => self.viewer = Some(viewer),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(viewer) = self.viewer.as_mut() else {
            return;
        };
        let outcome = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::RedrawRequested => match viewer.frame() {
                Ok(true) => Ok(()),
                Ok(false) => {
                    event_loop.exit();
                    Ok(())
                }
                Err(e) => Err(e),
            },
            event => {
                if viewer.input(&event) {
                    event_loop.exit();
                }
                Ok(())
            }
        };
        if let Err(e) = outcome {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(viewer) = &self.viewer {
            viewer.display.window.request_redraw();
        }
    }
}

/// Interaction state.
#[derive(Default)]
struct Controls {
    orbiting: bool,
    panning: bool,
    cursor: Option<(f64, f64)>,
    model_offset: DVec3,
    model_yaw: f64,
    paused: bool,
    single_step: bool,
    light_orbit: bool,
    light_yaw_deg: f32,
    light_pitch_deg: f32,
    screenshot_requested: bool,
    wind_strength: f32,
    wind_on: bool,
    shake_on: bool,
    /// A ladder rung the panel pinned (the budget keeps it).
    quality_pin: Option<usize>,
}

/// Live numbers for the HUD.
#[derive(Clone, Debug, Default)]
pub(crate) struct Hud {
    /// The rungs of the device's quality ladder.
    pub ladder: &'static [fur_core::render::budget::Rung],
    pub frame_ms: f64,
    /// GPU time of the whole frame, simulation included (timestamps).
    pub gpu_frame_ms: f64,
    pub sim_ms: f64,
    pub hairs: u64,
    pub segments: u64,
    /// Triangles the tessellation control stage gave no hairs.
    pub culled: u64,
    pub points: u64,
    pub masters: usize,
    /// The scene has a texture the panel can turn on.
    pub texture_available: bool,
    /// The ladder rung the fur is drawn at.
    pub rung: usize,
    /// That rung's ꟻLIP against the default drawing, once measured at a still view.
    pub rung_error: Option<f64>,
    /// Even the cheapest rung misses the budget.
    pub budget_missed: bool,
    /// The target frame rate (0: no budget).
    pub target_fps: f64,
    /// The device bins (lavapipe): timestamps between stages misattribute.
    pub binning: bool,
    /// What the compute rasteriser counted, when it drew the last frame.
    pub raster: Option<fur_gpu::render::ComputeCounts>,
}

// The viewer in parts, each freeing what it holds itself, in the order its own fields
// give (and every Vulkan object holds the device, so none outlives it): the panel (egui
// and its renderer), the frames in flight (command pool, fences, semaphores), the
// session (the scene on the GPU), the display (swapchain, surface, window). Once the
// device is idle, which `Drop` waits for first, no part's objects are in use through
// another's, so the order of the parts below does not matter.
struct Viewer {
    panel: Panel,
    frames: Frames,
    session: FurSession,
    display: Display,
    device: Arc<Device>,
    /// The frame-time budget.
    quality: Quality,
    /// Scripted input and the frame count.
    scripted: Scripted,
    clock: Clock,
    mesh: Mesh,
    /// The scene's texture (the panel turns it off and on).
    scene_texture: Option<fur_core::scene::TextureSpec>,
    model: fur_core::scene::ModelSpec,
    scene: SceneOptions,
    controls: Controls,
    hud: Hud,
    screenshot_dir: PathBuf,
    save_scene: Option<PathBuf>,
    screenshots_taken: u32,
    /// Simulation frames run (each all its substeps); paused, one per step key.
    frames_simulated: u64,
    /// Whether the viewer has said it draws with the fixed-function rasteriser on a CPU
    /// driver (`Viewer::hold_raster`).
    raster_held: bool,
}

impl Drop for Viewer {
    fn drop(&mut self) {
        // Wait for every frame in flight before the parts free their objects.
        let _ = self.device.wait_idle();
    }
}
