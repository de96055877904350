//! The viewer's parameter panel and HUD (egui).

use std::path::PathBuf;

use super::Hud;
use fur_core::scene_file::SceneOptions;
use fur_core::scene_file::{Effect, Scene};
use fur_core::sim::SimParams;
use fur_gpu::session::FurSession;

/// Controls the panel shares with the keyboard.
pub(crate) struct ControlsView<'a> {
    pub paused: &'a mut bool,
    pub single_step: &'a mut bool,
    pub wind_on: &'a mut bool,
    pub wind_strength: &'a mut f32,
    pub shake_on: &'a mut bool,
    pub light_orbit: &'a mut bool,
    pub light_yaw_deg: &'a mut f32,
    pub light_pitch_deg: &'a mut f32,
    pub screenshot: &'a mut bool,
    pub quality_pin: &'a mut Option<usize>,
}

/// What the panel changed that needs more than a uniform update.
#[derive(Default)]
pub(crate) struct Changes {
    /// New groom: the hairs are regrown.
    pub groom: Option<SceneOptions>,
    /// New simulation parameters.
    pub sim: Option<SimParams>,
    /// New lighting or drawing: taken by the next frame.
    pub frame: Option<SceneOptions>,
    /// Texture colour turned on or off: the renderer is rebuilt.
    pub texture: Option<bool>,
}

impl Changes {
    /// What a setting of `effect` changed in `scene` asks for.
    pub fn note(&mut self, effect: Effect, scene: &Scene) {
        match effect {
            Effect::Regrow => self.groom = Some(scene.options.clone()),
            Effect::Simulation => self.sim = Some(scene.sim.clone()),
            Effect::Frame => self.frame = Some(scene.options.clone()),
            Effect::Restart => {}
        }
    }
}

/// Panel state kept between frames.
pub(crate) struct PanelState {
    pub reset_requested: bool,
    /// The panel's "save scene" button was pressed.
    pub save_requested: bool,
    pub pending_screenshot: Option<PathBuf>,
}

impl PanelState {
    pub fn new() -> Self {
        Self {
            reset_requested: false,
            save_requested: false,
            pending_screenshot: None,
        }
    }

    pub fn show(
        &mut self,
        ctx: &egui::Context,
        scene: &mut Scene,
        session: &mut FurSession,
        hud: &Hud,
        controls: &mut ControlsView<'_>,
    ) -> Changes {
        let mut changes = Changes::default();
        egui::Window::new("fur")
            .default_pos([12.0, 12.0])
            .default_width(280.0)
            .show(ctx, |ui| {
                ui.label(format!(
                    "{:.1} fps ({:.1} ms)",
                    1000.0 / hud.frame_ms.max(1e-3),
                    hud.frame_ms
                ));
                if hud.binning {
                    ui.label(
                        "stage timings: not shown, a binning rasteriser (lavapipe) \
                         misattributes them; the frame time above is the wall clock",
                    );
                } else {
                    ui.label(format!(
                        "GPU: frame {:.2} ms, simulation {:.2} ms ({:.2} per substep)",
                        hud.gpu_frame_ms,
                        hud.sim_ms,
                        hud.sim_ms / f64::from(session.sim.params().substeps),
                    ));
                }
                super::quality_ui::show(ui, hud, controls.quality_pin);
                let show = session.settings.show;
                if show.shows_lighting() {
                    ui.label(format!(
                        "view: {}, {} lighting",
                        show.name(),
                        session.settings.lighting.model.label()
                    ));
                } else {
                    ui.label(format!("view: {} (unlit)", show.name()));
                }
                ui.label(format!(
                    "{} master hairs, {} tessellated points, {} hairs drawn in {} segments, \
                     {} triangles culled",
                    hud.masters, hud.points, hud.hairs, hud.segments, hud.culled
                ));
                if let Some(counts) = &hud.raster {
                    let (line, overflowed) = raster_line(counts);
                    if overflowed {
                        ui.colored_label(egui::Color32::YELLOW, line);
                    } else {
                        ui.label(line);
                    }
                }
                let max_level = session.renderer.max_level();
                if let Some(legend) = crate::legend::Legend::of(&session.settings, max_level) {
                    super::legend_ui::show(ui, &legend);
                }
                ui.horizontal(|ui| {
                    ui.checkbox(controls.paused, "paused (space)");
                    if ui.button("step (n)").clicked() {
                        *controls.single_step = true;
                    }
                    if ui.button("save scene").clicked() {
                        self.save_requested = true;
                    }
                    if ui.button("reset (r)").clicked() {
                        self.reset_requested = true;
                    }
                });
                ui.horizontal(|ui| {
                    ui.checkbox(controls.shake_on, "shake (m)");
                    ui.checkbox(controls.wind_on, "wind (f)");
                    if ui.button("screenshot (F12)").clicked() {
                        *controls.screenshot = true;
                    }
                });
                ui.add(egui::Slider::new(controls.wind_strength, 0.0..=100.0).text("wind m/s²").logarithmic(true));

                super::animation_ui::panel(ui, session);

                egui::CollapsingHeader::new("light and looks").show(ui, |ui| {
                    ui.add(egui::Slider::new(controls.light_yaw_deg, -180.0..=180.0).text("light yaw"));
                    ui.add(egui::Slider::new(controls.light_pitch_deg, -89.0..=89.0).text("light pitch"));
                    ui.checkbox(controls.light_orbit, "orbit the light (l)");
                    let has_texture = session.mesh.texture.is_some();
                    let mut textured = has_texture;
                    ui.add_enabled_ui(hud.texture_available, |ui| {
                        if ui.checkbox(&mut textured, "texture colour (rebuilds)").changed() {
                            changes.texture = Some(textured);
                        }
                    });
                    ui.checkbox(&mut session.settings.draw_mesh, "draw skin");
                    ui.checkbox(&mut session.settings.draw_fur, "draw fur");
                });
                // Every setting whose definition asks for a control.
                let samples = session.renderer.supported_samples();
                for effect in super::settings_ui::show(ui, scene, &samples) {
                    changes.note(effect, scene);
                }
                ui.small("drag: orbit · right-drag: pan · wheel: zoom · WASD/arrows, Q/E: move the model · Esc: quit");
            });
        changes
    }
}

/// The HUD's line for a frame drawn by the compute rasteriser: what it binned and
/// blended past each pixel's nearest, and what found a pool full (then true: the line
/// is a warning).
fn raster_line(c: &fur_gpu::render::ComputeCounts) -> (String, bool) {
    let mut line = format!(
        "drawn in compute: {} tile entries, {} fragments ({} blended past the nearest), {} \
         pixels opaque before their tile's list ended",
        c.entries, c.fragments, c.tail_fragments, c.pixels_stopped
    );
    let overflowed = c.hairs_lost > 0 || c.entries_lost > 0;
    if overflowed {
        line += &format!(
            "; pools full: {} hairs and {} tile entries not drawn (the pools grow for the \
             next frame)",
            c.hairs_lost, c.entries_lost
        );
    }
    (line, overflowed)
}

#[cfg(test)]
mod tests {
    use super::raster_line;
    use fur_gpu::render::ComputeCounts;

    #[test]
    fn the_raster_line_warns_only_when_a_pool_was_full() {
        let mut counts = ComputeCounts {
            entries: 1200,
            tail_fragments: 34,
            pixels_stopped: 56,
            fragments: 789,
            ..ComputeCounts::default()
        };
        let (line, warned) = raster_line(&counts);
        assert!(!warned && line.contains("1200 tile entries") && line.contains("789 fragments"));
        assert!(line.contains("(34 blended past the nearest)"), "{line}");
        assert!(line.contains("56 pixels opaque"), "{line}");
        assert!(!line.contains("pools full"), "{line}");
        for (hairs, entries) in [(2, 0), (0, 5)] {
            counts.hairs_lost = hairs;
            counts.entries_lost = entries;
            let (line, warned) = raster_line(&counts);
            assert!(warned, "{line}");
            assert!(
                line.contains(&format!(
                    "{hairs} hairs and {entries} tile entries not drawn"
                )),
                "{line}"
            );
        }
    }
}
