//! The truth section's Marschner drawing with each of its terms dropped in turn: what
//! each term does to the distance from the path-traced reference.

use std::fmt::Write as _;

use super::super::quality::{Look, Shot};
use super::super::Bench;
use super::percent;
use crate::export::compare::errors;
use crate::export::reference::LinearImage;
use fur_core::render::marschner::Lobes;
use fur_core::render::LightingModel;
use fur_gpu::error::Result;

impl Bench<'_> {
    /// The Marschner drawing (without a shadow map: the light through the fur is the
    /// coat's estimate) with each of its terms dropped in turn: what each term does to
    /// the distance.
    pub(super) fn truth_terms(
        &mut self,
        scene: &str,
        shot: &Shot,
        own: &Look,
        truth: &LinearImage,
    ) -> Result<()> {
        let terms = self.term_errors(scene, shot, own, truth)?;
        let (all_flip, all_rmse) = (terms[0].1, terms[0].2);
        let _ = writeln!(
            self.md,
            "The Marschner drawing (ꟻLIP {all_flip:.4}; no shadow map: the light through \
             the fur is the coat's estimate) with one of its terms dropped: *change*, what \
             dropping it does to the distance, as a share of that drawing's ꟻLIP \
             (positive: the term brings the drawing closer to the truth; negative: the \
             drawing is closer without it).\n\n| term dropped | ꟻLIP | \
             RMSE | change |\n| --- | --- | --- | --- |\n| none | {all_flip:.4} | \
             {all_rmse:.4} | – |"
        );
        for (name, f, e) in &terms[1..] {
            let change = percent(100.0 * (f - all_flip) / all_flip);
            let _ = writeln!(self.md, "| {name} | {f:.4} | {e:.4} | {change} |");
        }
        self.md.push('\n');
        Ok(())
    }

    /// ꟻLIP and RMSE of the Marschner drawing without a shadow map against `truth`,
    /// with all its terms (first, named `none`) and with each dropped in turn
    /// ([`Lobes::each_dropped`]); each recorded as a CSV row of `case`.
    pub(super) fn term_errors(
        &mut self,
        case: &str,
        shot: &Shot,
        own: &Look,
        truth: &LinearImage,
    ) -> Result<Vec<(&'static str, f64, f64)>> {
        let mut full = own.clone();
        full.lighting.model = LightingModel::Marschner;
        full.lighting.shadows.enabled = false;
        let drawn = shot.draw_look(&full, crate::bench::metrics::Frames::STILL)?;
        let (all_flip, all_rmse) = errors(&drawn.image, truth)?;
        self.row(
            "truth",
            format!("{case}: all terms"),
            "flip",
            all_flip,
            "0..1",
        );
        let mut terms = vec![("none", all_flip, all_rmse)];
        for (name, lobes) in Lobes::each_dropped() {
            let mut look = full.clone();
            look.lighting.lobes = lobes;
            let drawn = shot.draw_look(&look, crate::bench::metrics::Frames::STILL)?;
            let (f, e) = errors(&drawn.image, truth)?;
            self.row(
                "truth",
                format!("{case}: without {name}"),
                "flip",
                f,
                "0..1",
            );
            (self.progress)(&format!("{case}: without {name}"));
            terms.push((name, f, e));
        }
        Ok(terms)
    }
}
