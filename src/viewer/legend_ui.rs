//! The stage view's colour key in the panel: the same [`Legend`] `fur render` draws into
//! a PNG's corner, as a colour bar with its labels.

use crate::legend::{Legend, Swatch};
use fur_core::colour::linear_to_srgb8;

fn colour(c: glam::Vec3) -> egui::Color32 {
    egui::Color32::from_rgb(
        linear_to_srgb8(c.x),
        linear_to_srgb8(c.y),
        linear_to_srgb8(c.z),
    )
}

/// Shows `legend` in `ui`.
pub(super) fn show(ui: &mut egui::Ui, legend: &Legend) {
    ui.label(legend.title);
    let width = ui.available_width().min(260.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 14.0), egui::Sense::hover());
    let painter = ui.painter();
    let steps = 64;
    for i in 0..steps {
        let t0 = i as f32 / steps as f32;
        let t1 = (i + 1) as f32 / steps as f32;
        let x0 = rect.left() + t0 * rect.width();
        let x1 = rect.left() + t1 * rect.width();
        let strip =
            egui::Rect::from_min_max(egui::pos2(x0, rect.top()), egui::pos2(x1, rect.bottom()));
        painter.rect_filled(strip, 0.0, colour((legend.colour)((t0 + t1) * 0.5)));
    }
    let (labels, _) = ui.allocate_exact_size(egui::vec2(width, 14.0), egui::Sense::hover());
    let font = egui::FontId::proportional(11.0);
    for (t, label) in &legend.ticks {
        let x = labels.left() + t * labels.width();
        ui.painter().text(
            egui::pos2(x, labels.top()),
            egui::Align2::CENTER_TOP,
            label,
            font.clone(),
            ui.visuals().text_color(),
        );
    }
    ui.horizontal(|ui| {
        for (swatch, label) in &legend.swatches {
            let (square, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
            match swatch {
                Swatch::Colour(c) => {
                    ui.painter().rect_filled(square, 0.0, colour(*c));
                }
                Swatch::Hatched => {
                    ui.painter()
                        .rect_filled(square, 0.0, colour(glam::Vec3::splat(0.1)));
                    let stroke = egui::Stroke::new(2.0, colour(glam::Vec3::splat(0.3)));
                    for k in [-0.5f32, 0.0, 0.5] {
                        let a = square.left_top() + egui::vec2((k + 0.5) * 12.0, 0.0);
                        let b = a + egui::vec2(-12.0 * 0.5, 12.0 * 0.5) * 2.0;
                        ui.painter()
                            .with_clip_rect(square)
                            .line_segment([a, b], stroke);
                    }
                }
            }
            ui.label(label.as_str());
        }
    });
}
