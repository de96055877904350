//! What each look costs and what it changes in the image: the default blob with the
//! built-in tabby texture, lit by Kajiya–Kay (the secondary highlight is its look, as
//! the seed has it), drawn with every look off, each alone, and all four on.
//! Cost is the frame's wall-clock time against the plain frame; the change is ꟻLIP
//! and RMSE against the plain frame; the error is ꟻLIP against a supersampled
//! reference of the same look (see `quality.rs`).

use std::fmt::Write as _;

use super::metrics::{flip, rmse};
use super::quality::{Look, Shot};
use super::Bench;
use fur_core::render::LightingModel;
use fur_core::scene::{ModelSpec, TextureSpec};
use fur_core::scene_file::Scene;
use fur_gpu::error::Result;

pub(super) fn tasks(quick: bool) -> u64 {
    if quick {
        3
    } else {
        6
    }
}

/// The looks: texture, secondary highlight, shadows, thin-hair AA.
#[derive(Clone, Copy)]
struct Switches([bool; 4]);

const NAMES: [&str; 4] = [
    "texture colour",
    "secondary highlight",
    "self-shadowing",
    "thin-hair AA",
];

impl Switches {
    fn name(self) -> String {
        match self.0.iter().filter(|on| **on).count() {
            0 => "none (plain)".into(),
            4 => "all four".into(),
            _ => NAMES
                .iter()
                .zip(self.0)
                .filter(|(_, on)| *on)
                .map(|(n, _)| *n)
                .collect::<Vec<_>>()
                .join(" + "),
        }
    }

    fn look(self, shot: &Shot) -> Look {
        let mut look = shot.look(&shot.settings.style);
        let [texture, secondary, shadows, aa] = self.0;
        look.textured = texture;
        look.lighting.highlights.secondary = secondary;
        look.lighting.shadows.enabled = shadows;
        look.style.thin_hair_aa = aa;
        look
    }
}

impl Bench<'_> {
    pub(super) fn looks(&mut self) -> Result<()> {
        let mut scene = Scene::defaults(ModelSpec::Blob);
        scene.options.texture = Some(TextureSpec::Tabby);
        scene.options.lighting.model = LightingModel::KajiyaKay;
        let shot = Shot::new(self.device, &scene, self.frame_extent())?;
        let frames = self.frames();
        let factor = if self.quick { 2 } else { 4 };
        let _ = writeln!(
            self.md,
            "## Looks\n\nThe default blob ({}×{}) with the built-in tabby texture, lit by \
             Kajiya–Kay (the seed's model, whose look the secondary highlight is); each look \
             alone over the plain frame, then all four. Change: ꟻLIP / RMSE against the plain \
             frame. Error: ꟻLIP against a {factor}×{factor}-supersampled reference of the same \
             look.\n\n\
             | looks | frame ms | × plain | change ꟻLIP | change RMSE | error ꟻLIP |\n\
             | --- | --- | --- | --- | --- | --- |",
            shot.extent.width, shot.extent.height
        );
        let mut cases = vec![Switches([false; 4])];
        if self.quick {
            cases.push(Switches([true; 4]));
        } else {
            for k in 0..4 {
                let mut on = [false; 4];
                on[k] = true;
                cases.push(Switches(on));
            }
            cases.push(Switches([true; 4]));
        }
        let mut plain: Option<(f64, fur_core::render::RgbaImage)> = None;
        for case in cases {
            let look = case.look(&shot);
            let drawn = shot.draw_look(&look, frames)?;
            let reference = shot.reference_of(&look, factor)?;
            let error = flip(&reference, &drawn.image);
            let name = case.name();
            let (base_ms, base_image) = plain.get_or_insert((drawn.frame_ms, drawn.image.clone()));
            let (ratio, change_flip, change_rmse) = (
                drawn.frame_ms / *base_ms,
                flip(base_image, &drawn.image),
                rmse(base_image, &drawn.image),
            );
            self.row("looks", &name, "frame", drawn.frame_ms, "ms");
            self.row("looks", &name, "cost", ratio, "x");
            self.row("looks", &name, "change_flip", change_flip, "flip");
            self.row("looks", &name, "change_rmse", change_rmse, "rmse");
            self.row("looks", &name, "error_flip", error, "flip");
            let _ = writeln!(
                self.md,
                "| {name} | {:.1} | {ratio:.2}× | {change_flip:.4} | {change_rmse:.4} | {error:.4} |",
                drawn.frame_ms
            );
            (self.progress)(&name);
        }
        self.md.push('\n');
        Ok(())
    }
}
