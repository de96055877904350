//! The panel's settings, drawn from their definitions (`scene_file::GROUPS`): one
//! collapsible section per scene-file section, one control per setting whose
//! definition asks for one (a slider, a checkbox, a row of choices, a colour button).
//! What changed is reported by its effect: a new frame, new simulation parameters or
//! regrown hairs.

use fur_core::scene_file::{Effect, Kind, Panel, Scene, Setting, Value, GROUPS};

/// Shows every section with a visible setting; edits `scene` and returns the effects
/// of what changed. `samples` are the MSAA counts the device supports.
pub(super) fn show(ui: &mut egui::Ui, scene: &mut Scene, samples: &[u32]) -> Vec<Effect> {
    let mut effects = Vec::new();
    for group in GROUPS {
        let visible: Vec<&Setting> = group
            .settings
            .iter()
            .filter(|s| s.panel != Panel::Hidden)
            .collect();
        if visible.is_empty() {
            continue;
        }
        egui::CollapsingHeader::new(group.heading).show(ui, |ui| {
            for setting in visible {
                let allowed = |n: u32| setting.key != "samples" || samples.contains(&n);
                if let Some(value) = control(ui, setting, setting.get(scene), &allowed) {
                    if setting.check(&value).is_ok() {
                        setting.set(scene, value);
                        effects.push(setting.effect);
                    }
                }
            }
        });
    }
    effects
}

/// The setting's control showing `value`; the new value when it was changed.
fn control(
    ui: &mut egui::Ui,
    setting: &Setting,
    value: Value,
    allowed: &dyn Fn(u32) -> bool,
) -> Option<Value> {
    let label = match setting.units {
        "" => setting.label.to_string(),
        units => format!("{} ({units})", setting.label),
    };
    match (setting.kind, setting.panel, value) {
        (Kind::Number { .. }, Panel::Slider { min, max, log }, Value::Number(mut v)) => ui
            .add(
                egui::Slider::new(&mut v, min..=max)
                    .logarithmic(log)
                    .text(label),
            )
            .changed()
            .then_some(Value::Number(v)),
        (Kind::Number { min, max, .. }, _, Value::Number(mut v)) => ui
            .horizontal(|ui| {
                let changed = ui
                    .add(egui::DragValue::new(&mut v).range(min..=max).speed(0.01))
                    .changed();
                ui.label(label);
                changed
            })
            .inner
            .then_some(Value::Number(v)),
        (Kind::Integer { .. }, Panel::Slider { min, max, .. }, Value::Integer(mut v)) => ui
            .add(egui::Slider::new(&mut v, min as u32..=max as u32).text(label))
            .changed()
            .then_some(Value::Integer(v)),
        (Kind::Integer { min, max, .. }, _, Value::Integer(mut v)) => ui
            .horizontal(|ui| {
                let changed = ui
                    .add(egui::DragValue::new(&mut v).range(min..=max))
                    .changed();
                ui.label(label);
                changed
            })
            .inner
            .then_some(Value::Integer(v)),
        (Kind::OneOf(options), _, Value::Integer(mut v)) => {
            let before = v;
            egui::ComboBox::from_label(label)
                .selected_text(v.to_string())
                .show_ui(ui, |ui| {
                    for &n in options.iter().filter(|&&n| allowed(n)) {
                        ui.selectable_value(&mut v, n, n.to_string());
                    }
                });
            (v != before).then_some(Value::Integer(v))
        }
        (Kind::Bool, _, Value::Bool(mut b)) => ui
            .checkbox(&mut b, label)
            .changed()
            .then_some(Value::Bool(b)),
        (Kind::Choice(names), _, Value::Text(mut t)) => {
            let before = t.clone();
            ui.horizontal(|ui| {
                ui.label(label);
                for &name in names {
                    ui.radio_value(&mut t, name.to_string(), name);
                }
            });
            (t != before).then_some(Value::Text(t))
        }
        (Kind::Colour { .. }, _, Value::Vector(v)) => {
            let mut rgb = v.to_array();
            ui.horizontal(|ui| {
                let changed = ui.color_edit_button_rgb(&mut rgb).changed();
                ui.label(label);
                changed
            })
            .inner
            .then(|| Value::Vector(glam::Vec3::from_array(rgb)))
        }
        (Kind::Vector { .. }, _, Value::Vector(v)) => {
            let mut xyz = v.to_array();
            ui.horizontal(|ui| {
                let mut changed = false;
                for c in &mut xyz {
                    changed |= ui.add(egui::DragValue::new(c).speed(0.05)).changed();
                }
                ui.label(label);
                changed
            })
            .inner
            .then(|| Value::Vector(glam::Vec3::from_array(xyz)))
        }
        _ => None,
    }
}
