//! The panel's quality line: the ladder rung in use, the budget, and a rung to pin.

use super::Hud;

pub(super) fn show(ui: &mut egui::Ui, hud: &Hud, pin: &mut Option<usize>) {
    let ladder = hud.ladder;
    let Some(rung) = ladder.get(hud.rung.min(ladder.len().saturating_sub(1))) else {
        return;
    };
    let budget = if hud.target_fps > 0.0 {
        format!("budget {:.0} fps", hud.target_fps)
    } else {
        "no budget".to_string()
    };
    ui.label(format!(
        "quality: {} (rung {} of {}), {budget}",
        rung.name,
        hud.rung,
        ladder.len() - 1
    ));
    ui.label(match hud.rung_error {
        Some(e) if hud.rung > 0 => format!("ꟻLIP {e:.4} against the default drawing"),
        Some(_) => "the default drawing".to_string(),
        None => "ꟻLIP against the default: measured when the view is still".to_string(),
    });
    if hud.budget_missed {
        ui.colored_label(
            egui::Color32::YELLOW,
            "even the cheapest drawing misses the budget",
        );
    }
    let label = |p: Option<usize>| {
        p.map_or("auto".to_string(), |r| {
            ladder.get(r).map_or("auto", |rung| rung.name).to_string()
        })
    };
    egui::ComboBox::from_label("pin quality")
        .selected_text(label(*pin))
        .show_ui(ui, |ui| {
            ui.selectable_value(pin, None, "auto");
            for (r, rung) in ladder.iter().enumerate() {
                ui.selectable_value(pin, Some(r), rung.name);
            }
        });
}
