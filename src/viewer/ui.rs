//! The viewer's parameter panel and HUD (egui).

use std::path::PathBuf;

use super::Hud;
use crate::render::{FurStyle, LightingModel, Primitive, Shading};
use crate::session::{FurSession, SceneOptions};
use crate::sim::SimParams;

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
    /// Texture colour turned on or off: the renderer is rebuilt.
    pub texture: Option<bool>,
}

/// Panel state kept between frames (edited values not yet applied).
pub(crate) struct PanelState {
    scene: SceneOptions,
    sim: SimParams,
    pub reset_requested: bool,
    /// The panel's "save scene" button was pressed.
    pub save_requested: bool,
    pub pending_screenshot: Option<PathBuf>,
}

impl PanelState {
    pub fn new(scene: &SceneOptions, session: &FurSession) -> Self {
        Self {
            scene: scene.clone(),
            sim: session.sim.params().clone(),
            reset_requested: false,
            save_requested: false,
            pending_screenshot: None,
        }
    }

    pub fn show(
        &mut self,
        ctx: &egui::Context,
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
                ui.label(format!(
                    "{} master hairs, {} tessellated points, {} hairs drawn in {} segments",
                    hud.masters, hud.points, hud.hairs, hud.segments
                ));
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

                egui::CollapsingHeader::new("groom (regrows the hairs)").show(ui, |ui| {
                    let s = &mut self.scene;
                    let mut changed = false;
                    changed |= ui.add(egui::Slider::new(&mut s.segments, 1..=63).text("segments")).changed();
                    changed |= ui.add(egui::Slider::new(&mut s.hair_length, 0.02..=1.0).text("hair length (× radius)")).changed();
                    changed |= ui.add(egui::Slider::new(&mut s.comb, 0.0..=4.0).text("comb")).changed();
                    changed |= ui.add(egui::Slider::new(&mut s.thickness_limit, 0.0..=2.0).text("length ≤ × half-thickness (0 = off)")).changed();
                    changed |= ui.add(egui::Slider::new(&mut s.curl, 0.0..=2.0).text("curl")).changed();
                    if changed {
                        changes.groom = Some(s.clone());
                    }
                });

                egui::CollapsingHeader::new("simulation").show(ui, |ui| {
                    let p = &mut self.sim;
                    let mut changed = false;
                    changed |= ui.add(egui::Slider::new(&mut p.substeps, 1..=16).text("substeps")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.damping, 0.0..=1.0).text("damping")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.global_stiffness, 0.0..=1.0).text("global stiffness S_G")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.global_range, 0.0..=1.0).text("global range")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.local_stiffness, 0.0..=1.0).text("local stiffness S_L")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.local_iterations, 0..=16).text("local iterations")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.length_iterations, 0..=16).text("length iterations")).changed();
                    let mut g = -p.gravity.y;
                    if ui.add(egui::Slider::new(&mut g, 0.0..=50.0).text("gravity m/s²")).changed() {
                        p.gravity.y = -g;
                        changed = true;
                    }
                    changed |= ui.checkbox(&mut p.collision, "collide with the body").changed();
                    changed |= ui.add(egui::Slider::new(&mut p.collision_margin, 0.0..=0.2).text("collision margin (of hair length)")).changed();
                    changed |= ui.add(egui::Slider::new(&mut p.friction, 0.0..=1.0).text("friction")).changed();
                    if changed {
                        // Wind is driven by the toggle and strength above.
                        p.wind = session.sim.params().wind;
                        changes.sim = Some(p.clone());
                    }
                });

                egui::CollapsingHeader::new("lighting").show(ui, |ui| {
                    let l = &mut session.settings.lighting;
                    ui.horizontal(|ui| {
                        ui.label("model");
                        for model in [LightingModel::KajiyaKay, LightingModel::Marschner] {
                            ui.radio_value(&mut l.model, model, model.label());
                        }
                    });
                    if l.model == LightingModel::Marschner {
                        let f = &mut l.fibre;
                        ui.add(egui::Slider::new(&mut f.longitudinal_roughness, 0.01..=1.0).text("β_m (longitudinal roughness)"));
                        ui.add(egui::Slider::new(&mut f.azimuthal_roughness, 0.01..=1.0).text("β_n (azimuthal roughness)"));
                        ui.add(egui::Slider::new(&mut f.cuticle_tilt_deg, -10.0..=10.0).text("α (cuticle tilt, °)"));
                        ui.add(egui::Slider::new(&mut f.ior, 1.0..=3.0).text("η (index of refraction)"));
                    }
                    ui.add(egui::Slider::new(&mut l.kd, 0.0..=2.0).text("Kd (diffuse)"));
                    ui.add(egui::Slider::new(&mut l.ks, 0.0..=2.0).text("Ks (specular)"));
                    ui.add(egui::Slider::new(&mut l.shininess, 1.0..=200.0).text("p (exponent)").logarithmic(true));
                    ui.add(egui::Slider::new(&mut l.ambient, 0.0..=1.0).text("ambient"));
                    ui.add(egui::Slider::new(&mut l.intensity, 0.0..=3.0).text("intensity"));
                    ui.add(egui::Slider::new(&mut l.root_occlusion, 0.0..=1.0).text("root darkening"));
                    ui.add(egui::Slider::new(controls.light_yaw_deg, -180.0..=180.0).text("light yaw"));
                    ui.add(egui::Slider::new(controls.light_pitch_deg, -89.0..=89.0).text("light pitch"));
                    ui.checkbox(controls.light_orbit, "orbit the light (l)");
                    color(ui, "root colour", &mut l.root_color);
                    color(ui, "tip colour", &mut l.tip_color);
                    color(ui, "skin colour", &mut l.skin_color);
                });

                egui::CollapsingHeader::new("looks").show(ui, |ui| {
                    let has_texture = session.mesh.texture.is_some();
                    let mut textured = has_texture;
                    ui.add_enabled_ui(hud.texture_available, |ui| {
                        if ui.checkbox(&mut textured, "texture colour (rebuilds)").changed() {
                            changes.texture = Some(textured);
                        }
                    });
                    let l = &mut session.settings.lighting;
                    let h = &mut l.highlights;
                    ui.checkbox(&mut h.secondary, "secondary highlight");
                    ui.add_enabled_ui(h.secondary, |ui| {
                        ui.add(egui::Slider::new(&mut h.primary_shift_deg, -20.0..=20.0).text("primary shift (°, + tipward)"));
                        ui.add(egui::Slider::new(&mut h.secondary_shift_deg, -20.0..=20.0).text("secondary shift (°)"));
                        ui.add(egui::Slider::new(&mut h.secondary_shininess, 1.0..=200.0).text("secondary exponent").logarithmic(true));
                        ui.add(egui::Slider::new(&mut h.secondary_strength, 0.0..=2.0).text("secondary strength"));
                    });
                    let s = &mut l.shadows;
                    ui.checkbox(&mut s.enabled, "self-shadowing");
                    ui.add_enabled_ui(s.enabled, |ui| {
                        egui::ComboBox::from_label("shadow map")
                            .selected_text(format!("{0}×{0}", s.resolution))
                            .show_ui(ui, |ui| {
                                for r in [256, 512, 1024, 2048] {
                                    ui.selectable_value(&mut s.resolution, r, format!("{r}×{r}"));
                                }
                            });
                        ui.add(egui::Slider::new(&mut s.opacity, 0.0..=1.0).text("opacity per hair layer"));
                    });
                    ui.checkbox(&mut session.settings.style.thin_hair_aa, "thin-hair anti-aliasing");
                });

                egui::CollapsingHeader::new("fur drawing").show(ui, |ui| {
                    let f = &mut session.settings.style;
                    ui.add(egui::Slider::new(&mut f.density, 10.0..=200_000.0).text("hairs per unit²").logarithmic(true));
                    ui.add(egui::Slider::new(&mut f.lod_distance, 0.1..=100.0).text("full-density distance").logarithmic(true));
                    ui.add(egui::Slider::new(&mut f.hair_width, 0.0001..=0.05).text("hair width").logarithmic(true));
                    ui.add(egui::Slider::new(&mut f.min_pixel_width, 0.0..=4.0).text("min width (px)"));
                    ui.add(egui::Slider::new(&mut f.jitter, 0.0..=0.2).text("jitter"));
                    ui.add(egui::Slider::new(&mut f.length_jitter, 0.0..=1.0).text("length jitter"));
                    ui.checkbox(&mut f.cull, "cull back-facing / off-screen triangles");
                    draw_controls(ui, f, &session.renderer.supported_samples());
                    ui.checkbox(&mut session.settings.draw_mesh, "draw skin");
                    ui.checkbox(&mut session.settings.draw_fur, "draw fur");
                });
                ui.small("drag: orbit · right-drag: pan · wheel: zoom · WASD/arrows, Q/E: move the model · Esc: quit");
            });
        changes
    }
}

/// The speed/quality levers of the fur pass.
fn draw_controls(ui: &mut egui::Ui, f: &mut FurStyle, samples: &[u32]) {
    egui::ComboBox::from_label("samples per pixel")
        .selected_text(f.samples.to_string())
        .show_ui(ui, |ui| {
            for &n in samples {
                ui.selectable_value(&mut f.samples, n, n.to_string());
            }
        });
    egui::ComboBox::from_label("hairs as")
        .selected_text(f.primitive.name())
        .show_ui(ui, |ui| {
            for p in [Primitive::Ribbons, Primitive::Lines, Primitive::Auto] {
                ui.selectable_value(&mut f.primitive, p, p.name());
            }
        });
    if f.primitive == Primitive::Auto {
        ui.add(egui::Slider::new(&mut f.ribbon_above_px, 0.0..=8.0).text("ribbons from (px)"));
    }
    egui::ComboBox::from_label("lighting")
        .selected_text(f.shading.name())
        .show_ui(ui, |ui| {
            for s in [Shading::Vertex, Shading::Fragment] {
                ui.selectable_value(&mut f.shading, s, s.name());
            }
        });
    ui.add(
        egui::Slider::new(&mut f.vertex_lod_px, 0.0..=2.0)
            .text("vertex LOD tolerance (px)")
            .logarithmic(true),
    );
    ui.checkbox(&mut f.thickness_compensation, "thickness compensation");
}

fn color(ui: &mut egui::Ui, label: &str, value: &mut glam::Vec3) {
    ui.horizontal(|ui| {
        let mut rgb = value.to_array();
        if ui.color_edit_button_rgb(&mut rgb).changed() {
            *value = glam::Vec3::from_array(rgb);
        }
        ui.label(label);
    });
}
