//! The viewer's input: keys, mouse and scripted actions, and the scene they drive
//! (model placement, motion, wind, light).

use glam::{DMat4, DVec3, Vec3};
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{Key, NamedKey};

use super::script::Action;
use super::{ui, Controls, Viewer};
use fur_core::scene_file::{MotionSpec, Scene};
use fur_core::sim::{MotionKind, SimParams};

impl Viewer {
    /// The scene on screen now, as a scene file would hold it: the groom, the camera,
    /// lighting and drawing as the panel and the mouse left them, the simulation, the
    /// motion and the window's size. (A panned camera target is not kept: scenes aim
    /// at the model's centre.)
    pub(super) fn current_scene(&self) -> Scene {
        let settings = &self.session.settings;
        let radius = self.mesh.bounds().1;
        // The drawing the scene asks for, not the ladder's rung in use.
        let style = &self.quality.base;
        let camera = &settings.camera;
        let mut options = self.scene.clone();
        options.yaw_deg = camera.yaw_deg;
        options.pitch_deg = camera.pitch_deg;
        options.distance = Some(camera.distance / radius);
        options.fov_deg = camera.fov_y_deg;
        options.lighting = settings.lighting.clone();
        options.lighting.shadows.spacing /= radius;
        options.texture = self.session.mesh.texture.clone();
        options.draw = style.per_radius(radius);
        let motion = self.session.motion;
        let extent = self.session.renderer.target.extent;
        Scene {
            model: self.model.clone(),
            options,
            sim: self.session.sim.params().clone(),
            animation: super::animation_ui::spec(&self.session),
            motion: MotionSpec {
                kind: if self.controls.shake_on {
                    MotionKind::Shake
                } else {
                    motion.kind
                },
                amplitude: match motion.kind {
                    MotionKind::Shake => motion.amplitude / f64::from(radius),
                    _ => motion.amplitude,
                },
                rate: motion.rate,
            },
            width: extent.width,
            height: extent.height,
        }
    }

    /// Handles input; returns true when the viewer should close.
    pub(super) fn input(&mut self, event: &WindowEvent) -> bool {
        let response = self
            .panel
            .state
            .on_window_event(&self.display.window, event);
        // What counts as input for the frame-time budget: anything a person does.
        if matches!(
            event,
            WindowEvent::MouseInput { .. }
                | WindowEvent::MouseWheel { .. }
                | WindowEvent::KeyboardInput { .. }
        ) || (matches!(event, WindowEvent::CursorMoved { .. })
            && (self.controls.orbiting || self.controls.panning))
        {
            self.quality.input_seen = true;
        }
        match event {
            WindowEvent::Resized(_) => self.display.needs_resize = true,
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
                    Key::Character(c) => self.character_key(c.as_str()),
                    _ => {}
                }
            }
            _ => {}
        }
        false
    }

    pub(super) fn apply(&mut self, action: &Action) {
        if !matches!(action, Action::Screenshot(_)) {
            self.quality.input_seen = true;
        }
        let c = &mut self.controls;
        match action {
            Action::Resize(w, h) => {
                let _ = self
                    .display
                    .window
                    .request_inner_size(PhysicalSize::new(*w, *h));
                self.display.needs_resize = true;
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
            Action::Key(key) => self.character_key(key),
            Action::Minimize(on) => self.display.window.set_minimized(*on),
            Action::Screenshot(path) => {
                self.panel.ui.pending_screenshot = Some(path.clone());
            }
            // Applied with the panel's changes (`Viewer::frame`).
            Action::Set(..) => {}
        }
    }

    /// A character key pressed (or a script's `key=` event): the viewer's shortcuts.
    pub(super) fn character_key(&mut self, c: &str) {
        let step = f64::from(self.mesh.bounds().1) * 0.05;
        match c {
            "a" => self.controls.model_offset.x -= step,
            "d" => self.controls.model_offset.x += step,
            "w" => self.controls.model_offset.z -= step,
            "s" => self.controls.model_offset.z += step,
            "q" => self.controls.model_yaw += 0.15,
            "e" => self.controls.model_yaw -= 0.15,
            "n" | "." => self.controls.single_step = true,
            "r" => self.panel.ui.reset_requested = true,
            "f" => self.controls.wind_on = !self.controls.wind_on,
            "+" | "=" => self.controls.wind_strength *= 1.25,
            "-" => self.controls.wind_strength /= 1.25,
            "l" => self.controls.light_orbit = !self.controls.light_orbit,
            "m" => self.controls.shake_on = !self.controls.shake_on,
            "p" => self.controls.screenshot_requested = true,
            "c" | "[" | "]" => super::animation_ui::key(&mut self.session, c),
            digit => {
                // 1, 2, …: the stage views, in `Stage::ALL`'s order.
                let stages = fur_core::render::Stage::ALL;
                let chosen = digit
                    .parse::<usize>()
                    .ok()
                    .and_then(|n| n.checked_sub(1).and_then(|i| stages.get(i).copied()));
                if let Some(stage) = chosen {
                    self.scene.show = stage;
                    self.session.settings.show = stage;
                }
            }
        }
    }

    /// Per-frame scene updates from the controls: model placement, motion, wind, light.
    pub(super) fn update_scene(&mut self) {
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
pub(super) fn controls_view(c: &mut Controls) -> ui::ControlsView<'_> {
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
        quality_pin: &mut c.quality_pin,
    }
}
