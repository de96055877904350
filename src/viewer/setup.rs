//! Opening the viewer: the display (the window, the device and its surface, the
//! swapchain), the session with the scene, the frames in flight and the panel.

use super::*;

impl Viewer {
    pub(super) fn new(event_loop: &ActiveEventLoop, options: &ViewerOptions) -> Result<Self> {
        let (device, display) = Display::open(event_loop, options)?;
        let swapchain = display
            .swapchain()
            .expect("a display opens with a swapchain");
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
        let shake = match options.motion.kind {
            MotionKind::Shake => options.motion,
            _ => fur_core::scene_file::MotionSpec::default(),
        };
        let motion = Motion {
            kind: MotionKind::Still,
            ..shake.motion(mesh.bounds().1)
        };
        let session = FurSession::new(
            &device,
            SessionSetup {
                mesh: mesh.clone(),
                rig,
                groom: &groom,
                sim: options.sim.clone(),
                motion,
                settings,
                extent: swapchain.extent,
                frames_in_flight: FRAMES_IN_FLIGHT,
            },
        )?;
        for warning in session.all_warnings(&options.model.name()) {
            eprintln!("warning: {warning}");
        }
        let frames = Frames::new(&device)?;
        let panel = Panel::new(&device, &display.window, swapchain.format)?;
        let light = session.settings.lighting.light_direction.normalize();
        let controls = Controls {
            light_yaw_deg: light.x.atan2(light.z).to_degrees(),
            light_pitch_deg: light.y.asin().to_degrees(),
            wind_strength: options.sim.wind.length().max(6.0),
            wind_on: options.sim.wind != Vec3::ZERO,
            ..Default::default()
        };
        let masters = session.strands.count();
        let ladder = device.info.ladder(session.settings.style.raster);
        let quality = Quality::new(options.target_fps, &session.settings.style, ladder);
        let binning = device.info.name.contains("llvmpipe");
        let scene_texture = mesh.texture.clone();
        let texture_available = scene_texture.is_some();
        Ok(Self {
            panel,
            frames,
            session,
            display,
            device,
            scene_texture,
            mesh,
            model: options.model.clone(),
            scene: options.scene.clone(),
            controls,
            hud: Hud {
                ladder: ladder.rungs,
                masters,
                texture_available,
                target_fps: options.target_fps,
                binning,
                ..Default::default()
            },
            quality,
            scripted: Scripted::new(options.script.clone(), options.frames),
            clock: Clock::new(),
            screenshot_dir: options.screenshot_dir.clone(),
            save_scene: options.save_scene.clone(),
            screenshots_taken: 0,
            frames_simulated: 0,
            raster_held: false,
        })
    }
}
