//! The quality ladder the frame-time budget steps along on the device measured
//! (`render::budget::Ladder`): every rung's frame time and image error (ꟻLIP against a
//! supersampled reference) on both scenes, and whether each rung costs less and errs
//! more than the one above.

use std::fmt::Write as _;

use super::metrics::flip;
use super::plot::{Plot, Series, PALETTE};
use super::quality::Shot;
use super::Bench;
use fur_core::render::budget::MOST_RUNGS;
use fur_gpu::error::Result;

/// Progress ticks: each scene's reference and rungs (the longer ladder's).
pub(super) fn tasks(scenes: usize) -> u64 {
    scenes as u64 * (1 + MOST_RUNGS as u64)
}

impl Bench<'_> {
    pub(super) fn ladder(&mut self) -> Result<()> {
        // The ladder's order is a property of the image size it is drawn at, so even the
        // quick suite measures it at 1280×720 (the viewer's default window): at 640×360
        // and below, one-sample drawings alias so much that thinning the hair out (the
        // density-LOD rung) reads closer to the reference than the 1× rungs above it
        // (measured).
        let extent = ash::vk::Extent2D {
            width: 1280,
            height: 720,
        };
        let factor = if self.quick { 2 } else { 4 };
        let _ = writeln!(
            self.md,
            "## Quality ladder ({}×{})\n\nThe rungs `fur view --target-fps` and `fur render \
             --budget-ms` step along, most accurate first: a still frame of each scene at \
             each rung, its wall-clock frame time and its ꟻLIP against the {factor}×{factor} \
             supersampled reference (as in the render-quality table). *Ordered*: the rung \
             costs less and errs more than the one above.\n",
            extent.width, extent.height
        );
        let mut series = Vec::new();
        // Per rung, its ꟻLIP on the first scene (the one the orbit runs on).
        let mut first_errors = Vec::new();
        for (k, bench_scene) in self.scenes.clone().iter().enumerate() {
            let scene = &bench_scene.name;
            let shot = Shot::new(self.device, &bench_scene.scene, extent)?;
            let reference = shot.reference(factor)?;
            (self.progress)(&format!("{scene} ladder reference"));
            let ladder = self.device.info.ladder(shot.settings.style.raster);
            let _ = writeln!(
                self.md,
                "### {scene}\n\n| rung | drawing | frame ms | ꟻLIP | ordered |\n| --- | --- | --- | --- | --- |"
            );
            let mut points: Vec<(f64, f64)> = Vec::new();
            for (r, rung) in ladder.rungs.iter().enumerate() {
                let style = rung.apply(&shot.settings.style);
                let drawn = shot.draw(&style, self.frames())?;
                let error = flip(&reference, &drawn.image);
                let ordered = points
                    .last()
                    .is_none_or(|&(ms, e)| drawn.frame_ms < ms && error > e);
                let case = format!("{scene}: rung {r} ({})", rung.name);
                self.row("ladder", case.clone(), "frame_ms", drawn.frame_ms, "ms");
                self.row("ladder", case.clone(), "flip", error, "0..1");
                self.row(
                    "ladder",
                    case,
                    "ordered",
                    f64::from(u8::from(ordered)),
                    "bool",
                );
                let _ = writeln!(
                    self.md,
                    "| {r} | {} | {:.1} | {error:.4} | {} |",
                    rung.name,
                    drawn.frame_ms,
                    if r == 0 {
                        "–"
                    } else if ordered {
                        "yes"
                    } else {
                        "no"
                    }
                );
                points.push((drawn.frame_ms, error));
                if k == 0 {
                    first_errors.push(error);
                }
                (self.progress)(&format!("{scene}: rung {r}"));
            }
            self.md.push('\n');
            series.push(Series {
                name: scene.to_string(),
                points,
                color: PALETTE[k % PALETTE.len()],
                line: true,
            });
        }
        self.orbit(&first_errors)?;
        self.plots.push((
            "ladder.svg",
            Plot {
                title: "Quality ladder: ꟻLIP against frame time, rung by rung".into(),
                x_label: "frame ms (wall clock)".into(),
                y_label: "ꟻLIP against the supersampled reference".into(),
                log_x: true,
                log_y: true,
                series,
                highlight: None,
            },
        ));
        Ok(())
    }
}
