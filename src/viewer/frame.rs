//! The viewer's frame loop: the swapchain, one frame's simulation and drawing, what a
//! finished frame reports (timings, screenshots), and the panel's changes applied
//! between frames.

use std::time::Duration;

use ash::vk;
use glam::DVec3;

use super::input::controls_view;
use super::script::Action;
use super::{ui, Frames, Viewer, FRAMES_IN_FLIGHT};
use fur_gpu::error::{Result, VkContext};
use fur_gpu::session::{FurSession, SessionSetup};

impl Viewer {
    /// Rebuilds the swapchain at the window's size and the render target to match;
    /// false (nothing done) while the window has no drawable area.
    pub(super) fn recreate_swapchain(&mut self) -> Result<bool> {
        let Some(extent) = self.display.recreate_swapchain(&self.device)? else {
            return Ok(false);
        };
        self.session.renderer.resize(extent)?;
        Ok(true)
    }

    /// Renders one frame. Returns false when the viewer should close.
    pub(super) fn frame(&mut self) -> Result<bool> {
        if fur_core::interrupt::requested() {
            return Ok(false);
        }
        let actions: Vec<Action> = self.scripted.due();
        for action in &actions {
            self.apply(action);
        }
        if self.scripted.finished() {
            return Ok(false);
        }
        let frame_index = self.scripted.begin_frame();
        let dt = self.clock.tick();
        self.hud.frame_ms = if self.hud.frame_ms == 0.0 {
            dt * 1e3
        } else {
            self.hud.frame_ms * 0.9 + dt * 1e3 * 0.1
        };
        self.steer_quality(dt);
        self.measure_rung_error()?;
        if frame_index > 1 {
            self.clock.frame_times.push(dt * 1e3);
        }

        let extent = self.display.drawable();
        if extent.width == 0 || extent.height == 0 {
            // Minimised: nothing to draw into. Keep counting frames so --frames ends.
            std::thread::sleep(Duration::from_millis(10));
            return Ok(true);
        }
        let current = self.display.swapchain().map(|s| s.extent);
        if (self.display.needs_resize || current != Some(extent)) && !self.recreate_swapchain()? {
            return Ok(true);
        }

        let slot = Frames::slot_of(frame_index);
        self.device.wait_fence(self.frames.slots[slot].fence.raw)?;
        self.finish_slot(slot)?;

        let swapchain = self
            .display
            .swapchain()
            .expect("swapchain exists while drawing");
        let Some(image_index) = swapchain.acquire(self.frames.slots[slot].image_available.raw)?
        else {
            self.display.needs_resize = true;
            return Ok(true);
        };

        // UI, then the parameter changes it asked for (some need an idle device).
        let raw_input = self.panel.state.take_egui_input(&self.display.window);
        let mut changes = ui::Changes::default();
        let mut scene = self.current_scene();
        let egui_ctx = self.panel.ctx.clone();
        let mut output = egui_ctx.run_ui(raw_input, |root| {
            let mut view = controls_view(&mut self.controls);
            changes = self.panel.ui.show(
                root.ctx(),
                &mut scene,
                &mut self.session,
                &self.hud,
                &mut view,
            );
        });
        self.panel.state.handle_platform_output(
            &self.display.window,
            std::mem::take(&mut output.platform_output),
        );
        // Settings the script changes, as the panel would have.
        for action in &actions {
            // Checked when the script was read.
            let Action::Set(name, value) = action else {
                continue;
            };
            if let Some(setting) = crate::setting_args::find_setting(name) {
                setting.set(&mut scene, value.clone());
                changes.note(setting.effect, &scene);
            }
        }
        self.apply_changes(changes)?;
        self.hold_raster();
        self.update_scene();
        if self.session.settings.style.samples != self.session.renderer.target.samples {
            // The target and every pipeline are rebuilt: nothing may be in flight.
            self.device.wait_idle()?;
        }

        let free_textures = self
            .panel
            .set_textures(std::mem::take(&mut output.textures_delta))?;
        // Freed after this frame has finished (see finish_slot).
        self.frames.slots[slot].free_textures = free_textures;
        let primitives = self
            .panel
            .ctx
            .tessellate(output.shapes, output.pixels_per_point);

        // Fixed simulation steps, decoupled from the frame rate: as many 1/60 s steps as
        // wall-clock time has accumulated (at most 4 per frame, so a slow device slows
        // the simulation down rather than spiralling); one when single-stepping.
        let dt = f64::from(self.session.sim.params().dt);
        let sim_frames = if self.controls.paused {
            self.clock.pause();
            usize::from(std::mem::take(&mut self.controls.single_step))
        } else if self.scripted.counted() {
            // Counted runs (tests, benchmarks) step exactly once per frame.
            1
        } else {
            self.clock.steps_owed(dt)
        };
        let simulate = sim_frames > 0;
        self.frames_simulated += sim_frames as u64;
        let screenshot = if std::mem::take(&mut self.controls.screenshot_requested) {
            self.screenshots_taken += 1;
            Some(
                self.screenshot_dir
                    .join(format!("fur_screenshot_{:03}.png", self.screenshots_taken)),
            )
        } else {
            self.panel.ui.pending_screenshot.take()
        };

        // A change of stage view may rebuild the simulation kernel (waits for the device).
        self.session.prepare_frame()?;
        let d = self.device.clone();
        let raw = &d.raw;
        let frame = &mut self.frames.slots[slot];
        let cmd = frame.cmd;
        // SAFETY: the slot's fence was waited above, so its last submission has
        // finished: the fence may be reset and `cmd` (from the frames' pool, which
        // allows resetting single buffers) is no longer pending; nothing else records
        // into it.
        unsafe {
            raw.reset_fences(&[frame.fence.raw]).vk("vkResetFences")?;
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
            .display
            .swapchain()
            .expect("swapchain exists while drawing");
        let image = swapchain.images[image_index as usize];
        swapchain.before_blit(cmd, image_index);
        target.blit_to(&d, cmd, image);
        swapchain.before_panel(cmd, image_index);
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
        // SAFETY: `cmd` is recording, outside a rendering; the view is of the acquired
        // swapchain image, just moved to COLOR_ATTACHMENT_OPTIMAL, and `rendering`
        // covers the swapchain's extent; dynamic rendering is enabled.
        unsafe { raw.cmd_begin_rendering(cmd, &rendering) };
        self.panel
            .draw(cmd, swapchain.extent, output.pixels_per_point, &primitives)?;
        // SAFETY: `cmd` is inside the rendering begun above (the panel only records
        // draws into it).
        unsafe { raw.cmd_end_rendering(cmd) };
        d.end_label(cmd);
        swapchain.before_present(cmd, image_index);
        // SAFETY: `cmd` is recording (begun above) and every rendering and label opened
        // in it was closed.
        unsafe { raw.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;

        let frame = &mut self.frames.slots[slot];
        let wait = [vk::SemaphoreSubmitInfo::default()
            .semaphore(frame.image_available.raw)
            .stage_mask(vk::PipelineStageFlags2::BLIT)];
        let signal = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.render_finished[image_index as usize].raw)
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signal);
        // SAFETY: `cmd` is executable and the fence was reset above and is unused; the
        // acquire semaphore is signalled by this slot's acquire, and the
        // render-finished semaphore is per image, so the image's previous present has
        // consumed its last signal (see `Swapchain::render_finished`); everything
        // submitted stays alive until the fence is waited.
        unsafe { raw.queue_submit2(d.queue, &[submit], frame.fence.raw) }.vk("vkQueueSubmit2")?;
        frame.submitted = true;
        if !swapchain.present(image_index)? {
            self.display.needs_resize = true;
        }
        Ok(true)
    }

    /// Waits for every frame in flight and finishes it (screenshots included).
    pub(super) fn finish_all(&mut self) -> Result<()> {
        self.device.wait_idle()?;
        for slot in 0..self.frames.slots.len() {
            self.finish_slot(slot)?;
        }
        Ok(())
    }

    /// After slot `slot`'s previous frame finished: HUD timings, screenshot, UI frees.
    pub(super) fn finish_slot(&mut self, slot: usize) -> Result<()> {
        let frame = &mut self.frames.slots[slot];
        if !frame.submitted {
            return Ok(());
        }
        frame.submitted = false;
        let textures = std::mem::take(&mut frame.free_textures);
        let screenshot = frame.screenshot.take();
        let simulated = frame.simulated;
        self.panel.free(textures)?;
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
            self.hud.culled = c.triangles_culled;
        }
        self.hud.raster = timings.render.raster;
        if let Some(path) = screenshot {
            self.session.renderer.target.pixels().write_png(&path)?;
            log::info!("screenshot written to {}", path.display());
            println!("screenshot: {}", path.display());
        }
        Ok(())
    }

    /// Rebuilds or re-parameterises the scene as the panel asked.
    pub(super) fn apply_changes(&mut self, changes: ui::Changes) -> Result<()> {
        if let Some(scene) = changes.groom {
            let (groom, mut settings) = scene.resolve(&self.mesh)?;
            let old = &self.session.settings;
            settings.camera = old.camera;
            settings.draw_mesh = old.draw_mesh;
            settings.draw_fur = old.draw_fur;
            self.rebuild_session(&groom, settings)?;
            self.scene = scene;
        } else if let Some(scene) = changes.frame {
            // The lighting and the drawing as the scene's settings give them (scaled by
            // the model); the camera and the light's direction stay as the mouse and
            // the light controls left them.
            let (_, settings) = scene.resolve(&self.mesh)?;
            let direction = self.session.settings.lighting.light_direction;
            self.session.settings.lighting = settings.lighting;
            self.session.settings.lighting.light_direction = direction;
            self.session.settings.style = settings.style;
            self.session.settings.show = settings.show;
            self.session.settings.arrows = settings.arrows;
            self.session.settings.arrow_scale = settings.arrow_scale;
            self.scene = scene;
        }
        if let Some(on) = changes.texture {
            self.mesh.texture = if on { self.scene_texture.clone() } else { None };
            let (groom, _) = self.scene.resolve(&self.mesh)?;
            let settings = self.session.settings.clone();
            self.rebuild_session(&groom, settings)?;
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
        if std::mem::take(&mut self.panel.ui.save_requested) {
            let path = self
                .save_scene
                .clone()
                .unwrap_or_else(|| self.screenshot_dir.join("fur_scene.toml"));
            self.current_scene().save(&path)?;
            println!("scene saved to {}", path.display());
        }
        if std::mem::take(&mut self.panel.ui.reset_requested) {
            let (groom, _) = self.scene.resolve(&self.mesh)?;
            self.rebuild_session(&groom, self.session.settings.clone())?;
            self.controls.model_offset = DVec3::ZERO;
            self.controls.model_yaw = 0.0;
        }
        Ok(())
    }

    /// Regrows the hairs and restarts the simulation (keeping its parameters and the
    /// motion), once every frame in flight has finished.
    pub(super) fn rebuild_session(
        &mut self,
        groom: &fur_core::scene::GroomParams,
        settings: fur_core::render::FrameSettings,
    ) -> Result<()> {
        self.device.wait_idle()?;
        let extent = self.session.renderer.target.extent;
        let sim = self.session.sim.params().clone();
        let rig = self.session.sim.skinned.as_ref().map(|s| {
            let mut playback = s.playback.clone();
            // The new session starts at time 0: keep the clip where it is.
            playback.start = playback.clip_time(&s.body.rig, self.session.sim.time);
            // The body's own rig: a drawn groom's session adds its guides' roots.
            (s.body.rig.body_only(self.mesh.vertex_count()), playback)
        });
        self.session = FurSession::new(
            &self.device,
            SessionSetup {
                mesh: self.mesh.clone(),
                rig,
                groom,
                sim,
                motion: self.session.motion,
                settings,
                extent,
                frames_in_flight: FRAMES_IN_FLIGHT,
            },
        )?;
        self.hud.masters = self.session.strands.count();
        // The new session's query pools hold nothing yet.
        for frame in &mut self.frames.slots {
            frame.submitted = false;
        }
        Ok(())
    }
}
