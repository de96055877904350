//! Opening the viewer: the window, the device and its surface, the session with the
//! scene, the swapchain, and the frames in flight.

use super::*;

impl Viewer {
    pub(super) fn new(event_loop: &ActiveEventLoop, options: &ViewerOptions) -> Result<Self> {
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
        let (device, surface) =
            crate::gpu::windowed(options.validate, options.device.as_deref(), &*window)?;
        let (mesh, rig, warnings) = options.model.prepare_body(options.scene.texture.as_ref())?;
        for warning in warnings {
            eprintln!("warning: {warning}");
        }
        let rig = options.animation.resolve(rig, &options.model.name())?;
        let (groom, mut settings) = options.scene.resolve(&mesh)?;
        if let (Some((rig, playback)), None) = (&rig, options.scene.distance) {
            // Frame a second of the clip, not only the rest pose.
            options
                .scene
                .frame_poses(&mut settings, &mesh, rig, playback, 60);
        }
        // The HUD shows the hairs and segments drawn (two atomics per hair).
        settings.count_hairs = true;
        let size = window.inner_size();
        let extent = vk::Extent2D {
            width: size.width.max(1),
            height: size.height.max(1),
        };
        let swapchain = Swapchain::new(&device, &surface, extent, options.vsync, None)?;
        let shake = match options.motion.kind {
            MotionKind::Shake => options.motion,
            _ => crate::scene_file::MotionSpec::default(),
        };
        let motion = Motion {
            kind: MotionKind::Still,
            ..shake.motion(mesh.bounds().1)
        };
        let session = FurSession::with_rig(
            &device,
            (mesh.clone(), rig),
            &groom,
            options.sim.clone(),
            motion,
            settings,
            swapchain.extent,
            FRAMES_IN_FLIGHT,
        )?;
        for warning in session.all_warnings(&options.model.name()) {
            eprintln!("warning: {warning}");
        }
        let command_pool = CommandPool::new(&device, "frames")?;
        let upload_pool = CommandPool::new(&device, "ui uploads")?;
        let mut frames = Vec::new();
        for (i, cmd) in command_pool
            .allocate(FRAMES_IN_FLIGHT as u32)?
            .into_iter()
            .enumerate()
        {
            frames.push(FrameSync {
                cmd,
                fence: Fence::new(&device, true, &format!("frame_done[{i}]"))?,
                image_available: Semaphore::new(&device, &format!("image_available[{i}]"))?,
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
        let quality = Quality {
            budget: (options.target_fps > 0.0)
                .then(|| crate::render::budget::Budget::new(1000.0 / options.target_fps)),
            base: session.settings.style.clone(),
            applied: session.settings.style.clone(),
            input_seen: false,
            log: Vec::new(),
            still_s: 0.0,
            moving_rung: 0,
            errors: vec![None; crate::render::budget::LADDER.len()],
        };
        let binning = device.info.name.contains("llvmpipe");
        let scene_texture = mesh.texture.clone();
        let texture_available = scene_texture.is_some();
        Ok(Self {
            egui_renderer,
            egui_state,
            egui_ctx,
            ui: ui::PanelState::new(),
            frames,
            command_pool,
            upload_pool,
            swapchain: Some(swapchain),
            session,
            surface,
            device,
            scene_texture,
            mesh,
            model: options.model.clone(),
            scene: options.scene.clone(),
            controls,
            hud: Hud {
                masters,
                texture_available,
                target_fps: options.target_fps,
                binning,
                ..Default::default()
            },
            quality,
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
            save_scene: options.save_scene.clone(),
            screenshots_taken: 0,
            window,
        })
    }
}
