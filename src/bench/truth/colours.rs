//! The truth section's light and dark fur, and texture: the first scene in three fur
//! presets and with the built-in tabby texture, each lighting model with and without
//! shadows, against each variant's own reference; then each lit by one light alone
//! ([`lights`](super::lights)), and each drawing's distance by scale
//! ([`scales`](super::scales)).

use std::fmt::Write as _;
use std::path::Path;

use super::noise::capitalised;
use super::{
    cached_traces, delta_cell, differences, export, noise_sentence, percent, seed_spread, Sampling,
};
use crate::bench::Bench;
use crate::export::compare::{errors, to_srgb8};
use crate::export::reference::Reference;
use fur_core::render::{flip, FurPreset, LightingModel};
use fur_core::scene::TextureSpec;
use fur_gpu::error::Result;

use crate::bench::quality::Shot;

impl Bench<'_> {
    /// Light and dark fur and texture (the first scene in the fur presets `white`,
    /// `blond` and `black`, and with `--texture tabby`; the quick suite's `white` and
    /// `tabby`): each lighting model, alone and with shadows, against its reference.
    pub(super) fn truth_colours(
        &mut self,
        reference: &Reference,
        dir: &Path,
        extent: ash::vk::Extent2D,
        sampling: Sampling,
    ) -> Result<()> {
        let Some(base) = self.scenes.first().cloned() else {
            return Ok(());
        };
        // The quick suite draws the lightest preset and the texture: every path of the
        // code, half the work.
        let furs: &[FurPreset] = if self.quick {
            &[FurPreset::White]
        } else {
            &[FurPreset::White, FurPreset::Blond, FurPreset::Black]
        };
        let which = if self.quick {
            "the lightest fur preset (the quick suite's one)"
        } else {
            "three fur presets"
        };
        let _ = writeln!(
            self.md,
            "### Light and dark fur, and texture ({})\n\nThe {} scene in {which} \
             (colours as melanin, docs/design.md) and with the built-in texture \
             (`--texture tabby`: the fur and skin coloured through the model's UVs), each \
             against its own reference; Δ: the drawing's \
             ꟻLIP minus Kajiya–Kay's, with its own noise (how much the second reference \
             moves it; ≈ where it is not ten times that; below the table).\n\n| fur | drawing | frame ms \
             | ꟻLIP | Δ ꟻLIP (noise) | RMSE |\n| --- | --- | --- | --- | --- | --- |",
            base.name, base.name
        );
        let mut noises = Vec::new();
        let mut sentences = Vec::new();
        let mut term_columns = Vec::new();
        let mut light_rows = Vec::new();
        let mut scale_rows = Vec::new();
        let presets = furs
            .iter()
            .map(|&p| (p.name(), Some(p)))
            .chain([("tabby", None)]);
        for (variant, preset) in presets {
            let mut scene = base.scene.clone();
            match preset {
                Some(p) => scene.options.lighting.preset = p,
                None => scene.options.texture = Some(TextureSpec::Tabby),
            }
            let shot = Shot::new(self.device, &scene, extent)?;
            let own = shot.look(&shot.settings.style);
            let name = format!("{}-{variant}", base.name);
            let (_, usda, text, _) = export(&shot, &own, &dir.join(format!("{name}.usda")))?;
            let mut traced =
                cached_traces(reference, &usda, &text, sampling, &[(0, None), (1, None)])?;
            let (truth, second) = (traced.remove(0).image, traced.remove(0).image);
            let noise = flip(&to_srgb8(&truth), &to_srgb8(&second));
            (self.progress)(&format!("{name}: references"));
            to_srgb8(&truth).write_png(&dir.join(format!("{name}-reference.png")))?;
            let mut drawings = Vec::new();
            let mut kajiya_kay_image = None;
            let mut marschner = None;
            let cases = [
                (LightingModel::KajiyaKay, false),
                (LightingModel::KajiyaKay, true),
                (LightingModel::Marschner, false),
                (LightingModel::Marschner, true),
            ];
            {
                for (model, shadows) in cases {
                    let mut look = own.clone();
                    look.lighting.model = model;
                    look.lighting.shadows.enabled = shadows;
                    let drawn = shot.draw_look(&look, self.frames())?;
                    let (f, e) = errors(&drawn.image, &truth)?;
                    if !shadows {
                        let file = format!("{name}-{}.png", model.name());
                        drawn.image.write_png(&dir.join(file))?;
                    }
                    let what = format!(
                        "{}{}",
                        model.label(),
                        if shadows { ", shadows on" } else { "" }
                    );
                    let f_second = errors(&drawn.image, &second)?.0;
                    drawings.push((what, drawn.frame_ms, f, e, f_second));
                    match (model, shadows) {
                        (LightingModel::Marschner, false) => marschner = Some((drawn.image, f)),
                        (LightingModel::KajiyaKay, false) => {
                            kajiya_kay_image = Some((drawn.image, f))
                        }
                        _ => {}
                    }
                }
            }
            (self.progress)(&format!("{name}: drawings"));
            let kajiya_kay = drawings[0].2;
            let terms = self.term_errors(&name, &shot, &own, &truth)?;
            term_columns.push((variant, kajiya_kay, terms));
            if let (Some((kk, kk_flip)), Some((m, m_flip))) = (&kajiya_kay_image, &marschner) {
                let both = [
                    (LightingModel::KajiyaKay, kk, *kk_flip),
                    (LightingModel::Marschner, m, *m_flip),
                ];
                scale_rows.extend(self.scale_rows(&name, variant, &both, &truth)?);
            }
            if let Some((image, _)) = &marschner {
                let lit = (reference, dir, sampling);
                let full = (&truth, image);
                light_rows.extend(self.light_by_light(variant, &name, &shot, &own, full, lit)?);
            }
            let pairs: Vec<(f64, f64)> = drawings.iter().map(|d| (d.2, d.4)).collect();
            let (spread, _) = seed_spread(&pairs);
            let deltas = differences(&pairs);
            self.row("truth", name.clone(), "seed_spread_flip", spread, "0..1");
            self.difference_rows(&name, &pairs);
            let names: Vec<String> = drawings.iter().map(|d| d.0.clone()).collect();
            sentences.push(format!(
                "{} fur: {}",
                capitalised(variant),
                noise_sentence(&pairs, &names, "Kajiya–Kay's")
            ));
            for ((what, ms, f, e, _), delta) in drawings.into_iter().zip(deltas) {
                let _ = writeln!(
                    self.md,
                    "| {} | {what} | {ms:.1} | {f:.4} | {} | {e:.4} |",
                    variant,
                    delta_cell(delta)
                );
                let case = format!("{name}: {what}");
                self.row("truth", case.clone(), "frame_ms", ms, "ms");
                self.row("truth", case.clone(), "flip", f, "0..1");
                self.row("truth", case, "rmse", e, "linear");
            }
            self.row("truth", name, "noise_flip", noise, "0..1");
            noises.push(format!("{} {noise:.4}", variant));
        }
        let _ = writeln!(
            self.md,
            "\nReference noise (ꟻLIP): {}.\n\n{}\n",
            noises.join(", "),
            sentences.join("\n\n")
        );
        self.colour_terms(&term_columns);
        self.light_table(&light_rows);
        self.scale_table(&scale_rows);
        Ok(())
    }

    /// One table of what each Marschner term does to each fur's distance, beside the
    /// fidelity target (half of Kajiya–Kay's ꟻLIP).
    fn colour_terms(&mut self, columns: &[TermColumn]) {
        let header: Vec<&str> = columns.iter().map(|c| c.0).collect();
        let _ = writeln!(
            self.md,
            "What each term of the Marschner model does to each fur's distance, as in the \
             scenes' term tables: the drawing without a shadow map, then with one term \
             dropped (ꟻLIP, and the change as a share of the full drawing's; positive: the \
             term brings the drawing closer to the truth); last, the fidelity target, half \
             of Kajiya–Kay's ꟻLIP.\n\n| term dropped | {} |\n| --- |{}",
            header.join(" | "),
            " --- |".repeat(columns.len())
        );
        let Some(first) = columns.first() else {
            return;
        };
        for (i, (term, _, _)) in first.2.iter().enumerate() {
            let cells: Vec<String> = columns
                .iter()
                .map(|(_, _, terms)| {
                    let (all, f) = (terms[0].1, terms[i].1);
                    if i == 0 {
                        format!("{f:.4}")
                    } else {
                        format!("{f:.4} ({})", percent(100.0 * (f - all) / all))
                    }
                })
                .collect();
            let _ = writeln!(self.md, "| {term} | {} |", cells.join(" | "));
        }
        let targets: Vec<String> = columns
            .iter()
            .map(|(_, kajiya_kay, _)| format!("{:.4}", kajiya_kay / 2.0))
            .collect();
        let _ = writeln!(
            self.md,
            "| target: half of Kajiya–Kay's | {} |\n",
            targets.join(" | ")
        );
    }
}

/// A fur variant's name, Kajiya–Kay's ꟻLIP, and the Marschner drawing's errors with all
/// its terms and each dropped ([`Bench::term_errors`]).
type TermColumn = (&'static str, f64, Vec<(&'static str, f64, f64)>);
