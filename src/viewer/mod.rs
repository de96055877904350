//! `fur view`: a window with the live simulation, an orbit camera, a parameter panel
//! and GPU stage timings. Two frames in flight; the swapchain is recreated on resize
//! and rendering pauses while the window is minimised.

mod script;
mod ui;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use glam::{DMat4, DVec3, Vec3};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

pub use script::{Action, Script};

use crate::error::{Error, Result, VkContext};
use crate::gpu::{image_barriers, Device, Surface, Swapchain};
use crate::scene::Mesh;
use crate::session::{FurSession, SceneOptions};
use crate::sim::{Motion, MotionKind, SimParams};

const FRAMES_IN_FLIGHT: usize = 2;

/// What `fur view` was asked to do.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    pub model: crate::scene::ModelSpec,
    pub scene: SceneOptions,
    pub sim: SimParams,
    pub vsync: bool,
    /// Exit after this many frames (for tests and benchmarks).
    pub frames: Option<u64>,
    pub validate: bool,
    pub width: u32,
    pub height: u32,
    pub script: Script,
    /// Where the screenshot key (F12 or P) writes its PNGs.
    pub screenshot_dir: PathBuf,
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
        if let Err(e) = v.finish_all() {
            if app.result.is_ok() {
                app.result = Err(e);
            }
        }
    }
    if let Some(v) = &viewer {
        if !v.frame_times.is_empty() {
            println!(
                "{} frames: median frame time {:.1} ms; last GPU timings: frame {:.2} ms, simulation {:.2} ms; {} hairs drawn in {} segments",
                v.frame_times.len() + 1,
                crate::bench::metrics::median(&v.frame_times),
                v.hud.gpu_frame_ms,
                v.hud.sim_ms,
                v.hud.hairs,
                v.hud.segments
            );
        }
    }
    // Destroying the viewer can report problems too: check after it is gone.
    let instance = viewer.as_ref().map(|v| v.device.instance().clone());
    let device_alive = viewer.as_ref().map(|v| Arc::downgrade(&v.device));
    drop(viewer);
    app.result?;
    if device_alive.is_some_and(|d| d.upgrade().is_some()) {
        return Err(Error::Leak(
            "an object still holds the Vulkan device after the viewer closed".into(),
        ));
    }
    instance.map_or(Ok(()), |i| i.check_validation())
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
            viewer.window.request_redraw();
        }
    }
}

/// Per frame in flight: command buffer, fence, acquire semaphore and what to do once
/// the frame is done.
struct FrameSync {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    image_available: vk::Semaphore,
    submitted: bool,
    simulated: bool,
    screenshot: Option<PathBuf>,
    free_textures: Vec<egui::TextureId>,
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
}

/// Live numbers for the HUD.
#[derive(Clone, Debug, Default)]
pub(crate) struct Hud {
    pub frame_ms: f64,
    /// GPU time of the whole frame, simulation included (timestamps).
    pub gpu_frame_ms: f64,
    pub sim_ms: f64,
    pub hairs: u64,
    pub segments: u64,
    pub points: u64,
    pub masters: usize,
}

// Fields drop in declaration order: UI first, then frame objects, swapchain, scene,
// surface, device, and the window last (the surface refers to it).
struct Viewer {
    egui_renderer: egui_ash_renderer::Renderer<egui_ash_renderer::allocator::GpuAllocator>,
    egui_state: egui_winit::State,
    egui_ctx: egui::Context,
    ui: ui::PanelState,
    frames: Vec<FrameSync>,
    command_pool: vk::CommandPool,
    upload_pool: vk::CommandPool,
    swapchain: Option<Swapchain>,
    session: FurSession,
    surface: Surface,
    device: Arc<Device>,
    mesh: Mesh,
    scene: SceneOptions,
    controls: Controls,
    hud: Hud,
    script: Script,
    frame_limit: Option<u64>,
    frame_index: u64,
    last_frame: Instant,
    /// Seconds of the last frame, and simulation time owed to the clock.
    hud_dt: f64,
    sim_clock: f64,
    /// Wall-clock milliseconds of every frame after the first (for the exit summary).
    frame_times: Vec<f64>,
    vsync: bool,
    needs_resize: bool,
    screenshot_dir: PathBuf,
    screenshots_taken: u32,
    window: Arc<Window>,
}

impl Viewer {
    fn new(event_loop: &ActiveEventLoop, options: &ViewerOptions) -> Result<Self> {
        let attributes = Window::default_attributes()
            .with_title("fur")
            .with_inner_size(PhysicalSize::new(
                options.width.max(1),
                options.height.max(1),
            ));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Window(format!("cannot create a window: {e}")))?,
        );
        let (device, surface) = crate::gpu::windowed(options.validate, &*window)?;
        let (mesh, warnings) = options.model.prepare()?;
        for warning in warnings {
            eprintln!("warning: {warning}");
        }
        let (groom, mut settings) = options.scene.resolve(&mesh)?;
        // The HUD shows the hairs and segments drawn (two atomics per hair).
        settings.count_hairs = true;
        let size = window.inner_size();
        let extent = vk::Extent2D {
            width: size.width.max(1),
            height: size.height.max(1),
        };
        let swapchain = Swapchain::new(&device, &surface, extent, options.vsync, None)?;
        let radius = f64::from(mesh.bounds().1);
        let motion = Motion {
            kind: MotionKind::Still,
            amplitude: 0.25 * radius,
            rate: 1.0,
        };
        let session = FurSession::new(
            &device,
            mesh.clone(),
            &groom,
            options.sim.clone(),
            motion,
            settings,
            swapchain.extent,
            FRAMES_IN_FLIGHT,
        )?;
        if let Some(warning) = session
            .body
            .as_ref()
            .and_then(|(_, report)| report.warning(&options.model.name()))
        {
            eprintln!("warning: {warning}");
        }
        let raw = &device.raw;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let command_pool =
            unsafe { raw.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        let upload_pool =
            unsafe { raw.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        let alloc_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(FRAMES_IN_FLIGHT as u32);
        let cmds =
            unsafe { raw.allocate_command_buffers(&alloc_info) }.vk("vkAllocateCommandBuffers")?;
        let mut frames = Vec::new();
        for (i, cmd) in cmds.into_iter().enumerate() {
            let fence = unsafe {
                raw.create_fence(
                    &vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED),
                    None,
                )
            }
            .vk("vkCreateFence")?;
            let image_available =
                unsafe { raw.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                    .vk("vkCreateSemaphore")?;
            device.set_name(image_available, &format!("image_available[{i}]"));
            frames.push(FrameSync {
                cmd,
                fence,
                image_available,
                submitted: false,
                simulated: false,
                screenshot: None,
                free_textures: Vec::new(),
            });
        }
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &*window,
            Some(window.scale_factor() as f32),
            None,
            Some(device.info.limits.max_image_dimension2_d as usize),
        );
        let srgb = matches!(
            swapchain.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
        );
        let egui_renderer = egui_ash_renderer::Renderer::with_gpu_allocator(
            device.shared_allocator(),
            device.raw.clone(),
            egui_ash_renderer::RenderMode::DynamicRendering(egui_ash_renderer::DynamicRendering {
                color_attachment_format: swapchain.format,
                depth_attachment_format: None,
                stencil_attachment_format: None,
            }),
            egui_ash_renderer::Options {
                in_flight_frames: FRAMES_IN_FLIGHT,
                srgb_framebuffer: srgb,
                ..Default::default()
            },
        )
        .map_err(|e| Error::Window(format!("cannot create the UI renderer: {e}")))?;
        let light = session.settings.lighting.light_direction.normalize();
        let controls = Controls {
            light_yaw_deg: light.x.atan2(light.z).to_degrees(),
            light_pitch_deg: light.y.asin().to_degrees(),
            wind_strength: options.sim.wind.length().max(6.0),
            wind_on: options.sim.wind != Vec3::ZERO,
            ..Default::default()
        };
        let masters = session.strands.count();
        Ok(Self {
            egui_renderer,
            egui_state,
            egui_ctx,
            ui: ui::PanelState::new(&options.scene, &session),
            frames,
            command_pool,
            upload_pool,
            swapchain: Some(swapchain),
            session,
            surface,
            device,
            mesh,
            scene: options.scene.clone(),
            controls,
            hud: Hud {
                masters,
                ..Default::default()
            },
            script: options.script.clone(),
            frame_limit: options.frames,
            frame_index: 0,
            last_frame: Instant::now(),
            hud_dt: 0.0,
            sim_clock: 0.0,
            frame_times: Vec::new(),
            vsync: options.vsync,
            needs_resize: false,
            screenshot_dir: options.screenshot_dir.clone(),
            screenshots_taken: 0,
            window,
        })
    }

    /// Handles input; returns true when the viewer should close.
    fn input(&mut self, event: &WindowEvent) -> bool {
        let response = self.egui_state.on_window_event(&self.window, event);
        match event {
            WindowEvent::Resized(_) => self.needs_resize = true,
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = *state == ElementState::Pressed && !response.consumed;
                match button {
                    MouseButton::Left => self.controls.orbiting = pressed,
                    MouseButton::Right | MouseButton::Middle => self.controls.panning = pressed,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let Some(last) = self.controls.cursor {
                    let (dx, dy) = ((now.0 - last.0) as f32, (now.1 - last.1) as f32);
                    let camera = &mut self.session.settings.camera;
                    if self.controls.orbiting {
                        camera.yaw_deg -= dx * 0.4;
                        camera.pitch_deg = (camera.pitch_deg + dy * 0.4).clamp(-89.0, 89.0);
                    } else if self.controls.panning {
                        let view = camera.view();
                        let right = view.row(0).truncate();
                        let up = view.row(1).truncate();
                        let scale = camera.distance * 0.0015;
                        camera.target += (-right * dx + up * dy) * scale;
                    }
                }
                self.controls.cursor = Some(now);
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.session.settings.camera.distance *= 0.9f32.powf(lines);
            }
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed && !response.consumed =>
            {
                let step = f64::from(self.mesh.bounds().1) * 0.05;
                match &event.logical_key {
                    Key::Named(NamedKey::Escape) => return true,
                    Key::Named(NamedKey::Space) => self.controls.paused = !self.controls.paused,
                    Key::Named(NamedKey::F12) => self.controls.screenshot_requested = true,
                    Key::Named(NamedKey::ArrowLeft) => self.controls.model_offset.x -= step,
                    Key::Named(NamedKey::ArrowRight) => self.controls.model_offset.x += step,
                    Key::Named(NamedKey::ArrowUp) => self.controls.model_offset.y += step,
                    Key::Named(NamedKey::ArrowDown) => self.controls.model_offset.y -= step,
                    Key::Character(c) => match c.as_str() {
                        "a" => self.controls.model_offset.x -= step,
                        "d" => self.controls.model_offset.x += step,
                        "w" => self.controls.model_offset.z -= step,
                        "s" => self.controls.model_offset.z += step,
                        "q" => self.controls.model_yaw += 0.15,
                        "e" => self.controls.model_yaw -= 0.15,
                        "n" | "." => self.controls.single_step = true,
                        "r" => self.ui.reset_requested = true,
                        "f" => self.controls.wind_on = !self.controls.wind_on,
                        "+" | "=" => self.controls.wind_strength *= 1.25,
                        "-" => self.controls.wind_strength /= 1.25,
                        "l" => self.controls.light_orbit = !self.controls.light_orbit,
                        "m" => self.controls.shake_on = !self.controls.shake_on,
                        "p" => self.controls.screenshot_requested = true,
                        _ => {}
                    },
                    _ => {}
                }
            }
            _ => {}
        }
        false
    }

    fn apply(&mut self, action: &Action) {
        let c = &mut self.controls;
        match action {
            Action::Resize(w, h) => {
                let _ = self.window.request_inner_size(PhysicalSize::new(*w, *h));
                self.needs_resize = true;
            }
            Action::Orbit(yaw, pitch) => {
                let camera = &mut self.session.settings.camera;
                camera.yaw_deg += yaw;
                camera.pitch_deg = (camera.pitch_deg + pitch).clamp(-89.0, 89.0);
            }
            Action::Zoom(f) => self.session.settings.camera.distance *= f,
            Action::Move(x, y, z) => c.model_offset += DVec3::new(*x, *y, *z),
            Action::Wind(on) => c.wind_on = *on,
            Action::Shake(on) => c.shake_on = *on,
            Action::Pause(on) => c.paused = *on,
            Action::Minimize(on) => self.window.set_minimized(*on),
            Action::Screenshot(path) => {
                self.ui.pending_screenshot = Some(path.clone());
            }
        }
    }

    /// The window's drawable size; zero while minimised.
    fn drawable(&self) -> vk::Extent2D {
        let size = self.window.inner_size();
        if self.window.is_minimized() == Some(true) {
            return vk::Extent2D::default();
        }
        vk::Extent2D {
            width: size.width,
            height: size.height,
        }
    }

    fn recreate_swapchain(&mut self) -> Result<bool> {
        let extent = self.drawable();
        if extent.width == 0 || extent.height == 0 {
            return Ok(false);
        }
        self.device.wait_idle()?;
        let old = self.swapchain.take();
        let swapchain = Swapchain::new(
            &self.device,
            &self.surface,
            extent,
            self.vsync,
            old.as_ref(),
        )?;
        drop(old);
        self.session.renderer.resize(swapchain.extent)?;
        self.swapchain = Some(swapchain);
        self.needs_resize = false;
        Ok(true)
    }

    /// Renders one frame. Returns false when the viewer should close.
    fn frame(&mut self) -> Result<bool> {
        if crate::interrupt::requested() {
            return Ok(false);
        }
        let actions: Vec<Action> = self.script.due(self.frame_index).cloned().collect();
        for action in &actions {
            self.apply(action);
        }
        if let Some(limit) = self.frame_limit {
            if self.frame_index >= limit {
                return Ok(false);
            }
        }
        self.frame_index += 1;
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f64();
        self.last_frame = now;
        self.hud.frame_ms = if self.hud.frame_ms == 0.0 {
            dt * 1e3
        } else {
            self.hud.frame_ms * 0.9 + dt * 1e3 * 0.1
        };
        self.hud_dt = dt;
        if self.frame_index > 1 {
            self.frame_times.push(dt * 1e3);
        }

        let extent = self.drawable();
        if extent.width == 0 || extent.height == 0 {
            // Minimised: nothing to draw into. Keep counting frames so --frames ends.
            std::thread::sleep(Duration::from_millis(10));
            return Ok(true);
        }
        let current = self.swapchain.as_ref().map(|s| s.extent);
        if (self.needs_resize || current != Some(extent)) && !self.recreate_swapchain()? {
            return Ok(true);
        }

        let slot = (self.frame_index % FRAMES_IN_FLIGHT as u64) as usize;
        self.device.wait_fence(self.frames[slot].fence)?;
        self.finish_slot(slot)?;

        let swapchain = self
            .swapchain
            .as_ref()
            .expect("swapchain exists while drawing");
        let Some(image_index) = swapchain.acquire(self.frames[slot].image_available)? else {
            self.needs_resize = true;
            return Ok(true);
        };

        // UI, then the parameter changes it asked for (some need an idle device).
        let raw_input = self.egui_state.take_egui_input(&self.window);
        let mut changes = ui::Changes::default();
        let egui_ctx = self.egui_ctx.clone();
        let mut output = egui_ctx.run_ui(raw_input, |root| {
            let mut view = controls_view(&mut self.controls);
            changes = self
                .ui
                .show(root.ctx(), &mut self.session, &self.hud, &mut view);
        });
        self.egui_state
            .handle_platform_output(&self.window, std::mem::take(&mut output.platform_output));
        self.apply_changes(changes)?;
        self.update_scene();
        if self.session.settings.style.samples != self.session.renderer.target.samples {
            // The target and every pipeline are rebuilt: nothing may be in flight.
            self.device.wait_idle()?;
        }

        let frame = &mut self.frames[slot];
        let mut textures = std::mem::take(&mut output.textures_delta);
        for (id, deltas) in textures.set.drain() {
            for delta in &deltas {
                self.egui_renderer
                    .set_texture(self.device.queue, self.upload_pool, id, delta)
                    .map_err(|e| Error::Window(format!("UI texture upload failed: {e}")))?;
            }
        }
        // Freed after this frame has finished (see finish_slot).
        frame.free_textures = textures.free.drain().collect();
        let primitives = self
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);

        // Fixed simulation steps, decoupled from the frame rate: as many 1/60 s steps as
        // wall-clock time has accumulated (at most 4 per frame, so a slow device slows
        // the simulation down rather than spiralling); one when single-stepping.
        let dt = f64::from(self.session.sim.params().dt);
        let sim_frames = if self.controls.paused {
            self.sim_clock = 0.0;
            usize::from(std::mem::take(&mut self.controls.single_step))
        } else if self.frame_limit.is_some() {
            // Counted runs (tests, benchmarks) step exactly once per frame.
            1
        } else {
            self.sim_clock = (self.sim_clock + self.hud_dt).min(4.0 * dt);
            let n = (self.sim_clock / dt).floor() as usize;
            self.sim_clock -= n as f64 * dt;
            n
        };
        let simulate = sim_frames > 0;
        let screenshot = if std::mem::take(&mut self.controls.screenshot_requested) {
            self.screenshots_taken += 1;
            Some(
                self.screenshot_dir
                    .join(format!("fur_screenshot_{:03}.png", self.screenshots_taken)),
            )
        } else {
            self.ui.pending_screenshot.take()
        };

        let d = self.device.clone();
        let raw = &d.raw;
        let frame = &mut self.frames[slot];
        let cmd = frame.cmd;
        unsafe {
            raw.reset_fences(&[frame.fence]).vk("vkResetFences")?;
            raw.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            raw.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .vk("vkBeginCommandBuffer")?;
        }
        frame.simulated = simulate;
        frame.screenshot = screenshot.clone();
        self.session.record_frame(cmd, slot, sim_frames)?;
        let target = &self.session.renderer.target;
        target.finish(&d, cmd);
        if screenshot.is_some() {
            target.copy_to_readback(&d, cmd);
        }
        let swapchain = self
            .swapchain
            .as_ref()
            .expect("swapchain exists while drawing");
        let image = swapchain.images[image_index as usize];
        let barrier = |src, dst, old, new| {
            crate::gpu::image_barrier(image, vk::ImageAspectFlags::COLOR, src, dst, old, new)
        };
        let blit = (
            vk::PipelineStageFlags2::BLIT,
            vk::AccessFlags2::TRANSFER_WRITE,
        );
        let attachment = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ,
        );
        // The acquire semaphore is waited at ALL_COMMANDS, so this barrier chains to it.
        image_barriers(
            &d,
            cmd,
            &[barrier(
                (
                    vk::PipelineStageFlags2::ALL_COMMANDS,
                    vk::AccessFlags2::NONE,
                ),
                blit,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            )],
        );
        target.blit_to(&d, cmd, image);
        image_barriers(
            &d,
            cmd,
            &[barrier(
                blit,
                attachment,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            )],
        );
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(swapchain.views[image_index as usize])
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let rendering = vk::RenderingInfo::default()
            .render_area(swapchain.extent.into())
            .layer_count(1)
            .color_attachments(&color);
        d.begin_label(cmd, "ui");
        unsafe { raw.cmd_begin_rendering(cmd, &rendering) };
        self.egui_renderer
            .cmd_draw(cmd, swapchain.extent, output.pixels_per_point, &primitives)
            .map_err(|e| Error::Window(format!("UI drawing failed: {e}")))?;
        unsafe { raw.cmd_end_rendering(cmd) };
        d.end_label(cmd);
        image_barriers(
            &d,
            cmd,
            &[barrier(
                (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
                (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::PRESENT_SRC_KHR,
            )],
        );
        unsafe { raw.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;

        let frame = &mut self.frames[slot];
        let wait = [vk::SemaphoreSubmitInfo::default()
            .semaphore(frame.image_available)
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let signal = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.render_finished[image_index as usize])
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signal);
        unsafe { raw.queue_submit2(d.queue, &[submit], frame.fence) }.vk("vkQueueSubmit2")?;
        frame.submitted = true;
        if !swapchain.present(image_index)? {
            self.needs_resize = true;
        }
        Ok(true)
    }

    /// Waits for every frame in flight and finishes it (screenshots included).
    fn finish_all(&mut self) -> Result<()> {
        self.device.wait_idle()?;
        for slot in 0..self.frames.len() {
            self.finish_slot(slot)?;
        }
        Ok(())
    }

    /// After slot `slot`'s previous frame finished: HUD timings, screenshot, UI frees.
    fn finish_slot(&mut self, slot: usize) -> Result<()> {
        let frame = &mut self.frames[slot];
        if !frame.submitted {
            return Ok(());
        }
        frame.submitted = false;
        let textures = std::mem::take(&mut frame.free_textures);
        let screenshot = frame.screenshot.take();
        let simulated = frame.simulated;
        for id in textures {
            self.egui_renderer
                .free_texture(id)
                .map_err(|e| Error::Window(format!("UI texture free failed: {e}")))?;
        }
        let timings = self.session.timings(slot, simulated)?;
        if simulated {
            self.hud.sim_ms = timings.simulation_ms;
        }
        self.hud.gpu_frame_ms = timings.render.frame_ms;
        if let Some(s) = timings.render.statistics {
            self.hud.points = s.tess_eval_invocations;
        }
        if let Some(c) = timings.render.counts {
            self.hud.hairs = c.hairs;
            self.hud.segments = c.segments;
        }
        if let Some(path) = screenshot {
            self.session.renderer.target.pixels().write_png(&path)?;
            log::info!("screenshot written to {}", path.display());
            println!("screenshot: {}", path.display());
        }
        Ok(())
    }

    /// Rebuilds or re-parameterises the scene as the panel asked.
    fn apply_changes(&mut self, changes: ui::Changes) -> Result<()> {
        if let Some(scene) = changes.groom {
            let (groom, mut settings) = scene.resolve(&self.mesh)?;
            let old = &self.session.settings;
            settings.camera = old.camera;
            settings.lighting = old.lighting.clone();
            // The groom sets the model-scaled density and widths; every drawing choice
            // made in the panel stays.
            let scaled = settings.style;
            settings.style = crate::render::FurStyle {
                density: scaled.density,
                hair_width: scaled.hair_width,
                jitter: scaled.jitter,
                ..old.style.clone()
            };
            self.rebuild_session(&groom, settings)?;
            self.scene = scene;
        }
        if let Some(params) = changes.sim {
            self.device.wait_idle()?;
            if params.collision && self.session.body.is_none() {
                // Collision was off when the scene was built: build the body's field.
                let (groom, _) = self.scene.resolve(&self.mesh)?;
                let settings = self.session.settings.clone();
                self.session
                    .sim
                    .set_params(params, &self.session.textures)?;
                self.rebuild_session(&groom, settings)?;
            } else {
                self.session
                    .sim
                    .set_params(params, &self.session.textures)?;
            }
        }
        if std::mem::take(&mut self.ui.reset_requested) {
            let (groom, _) = self.scene.resolve(&self.mesh)?;
            self.rebuild_session(&groom, self.session.settings.clone())?;
            self.controls.model_offset = DVec3::ZERO;
            self.controls.model_yaw = 0.0;
        }
        Ok(())
    }

    /// Regrows the hairs and restarts the simulation (keeping its parameters and the
    /// motion), once every frame in flight has finished.
    fn rebuild_session(
        &mut self,
        groom: &crate::scene::GroomParams,
        settings: crate::render::FrameSettings,
    ) -> Result<()> {
        self.device.wait_idle()?;
        let extent = self.session.renderer.target.extent;
        let sim = self.session.sim.params().clone();
        self.session = FurSession::new(
            &self.device,
            self.mesh.clone(),
            groom,
            sim,
            self.session.motion,
            settings,
            extent,
            FRAMES_IN_FLIGHT,
        )?;
        self.hud.masters = self.session.strands.count();
        // The new session's query pools hold nothing yet.
        for frame in &mut self.frames {
            frame.submitted = false;
        }
        Ok(())
    }

    /// Per-frame scene updates from the controls: model placement, motion, wind, light.
    fn update_scene(&mut self) {
        let c = &mut self.controls;
        self.session.user =
            DMat4::from_translation(c.model_offset) * DMat4::from_rotation_y(c.model_yaw);
        self.session.motion.kind = if c.shake_on {
            MotionKind::Shake
        } else {
            MotionKind::Still
        };
        if c.light_orbit {
            c.light_yaw_deg = (c.light_yaw_deg + 1.0) % 360.0;
        }
        let (yaw, pitch) = (c.light_yaw_deg.to_radians(), c.light_pitch_deg.to_radians());
        self.session.settings.lighting.light_direction = Vec3::new(
            yaw.sin() * pitch.cos(),
            pitch.sin(),
            yaw.cos() * pitch.cos(),
        );
        let wind = if c.wind_on {
            let dir = self
                .session
                .sim
                .params()
                .wind
                .try_normalize()
                .unwrap_or(Vec3::new(0.95, 0.0, 0.3).normalize());
            dir * c.wind_strength
        } else {
            Vec3::ZERO
        };
        if wind != self.session.sim.params().wind {
            let params = SimParams {
                wind,
                ..self.session.sim.params().clone()
            };
            // Switching wind on or off adds or removes a pipeline: wait for the frames
            // in flight first. A strength change only rewrites per-step constants.
            if (wind == Vec3::ZERO) != (self.session.sim.params().wind == Vec3::ZERO) {
                let _ = self.device.wait_idle();
            }
            if let Err(e) = self.session.sim.set_params(params, &self.session.textures) {
                log::warn!("wind change rejected: {e}");
            }
        }
    }
}

/// The controls the panel edits alongside the keyboard.
fn controls_view(c: &mut Controls) -> ui::ControlsView<'_> {
    ui::ControlsView {
        paused: &mut c.paused,
        single_step: &mut c.single_step,
        wind_on: &mut c.wind_on,
        wind_strength: &mut c.wind_strength,
        shake_on: &mut c.shake_on,
        light_orbit: &mut c.light_orbit,
        light_yaw_deg: &mut c.light_yaw_deg,
        light_pitch_deg: &mut c.light_pitch_deg,
        screenshot: &mut c.screenshot_requested,
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        // Wait for every frame in flight before anything is destroyed.
        let _ = self.device.wait_idle();
        let raw = &self.device.raw;
        unsafe {
            for frame in &self.frames {
                raw.destroy_fence(frame.fence, None);
                raw.destroy_semaphore(frame.image_available, None);
            }
            raw.destroy_command_pool(self.command_pool, None);
            raw.destroy_command_pool(self.upload_pool, None);
        }
    }
}
