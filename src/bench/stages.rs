//! What looking costs: each stage view of the default blob, simulated (its shake and
//! wind) and drawn every frame, against the lit frame. The views are for study, not
//! for speed; this measures that each stays within twice the lit frame.

use std::fmt::Write as _;

use super::Bench;
use fur_core::render::stage::Arrows;
use fur_core::render::Stage;
use fur_core::sim::SimStep;
use fur_gpu::error::Result;

pub(super) fn tasks() -> u64 {
    Stage::ALL.len() as u64
}

impl Bench<'_> {
    pub(super) fn stages(&mut self) -> Result<()> {
        let Some(scene) = self.scenes.first().cloned() else {
            return Ok(());
        };
        let _ = writeln!(
            self.md,
            "## Stage views: what looking costs\n\n\
             The {}, simulated and drawn each frame at {}×{} (median wall-clock frame after \
             warm-up), in each stage view (`--show`); the simulation view with its arrows \
             (`--arrows length`). Ratios are to the lit frame of the same run.\n\n\
             | view | frame ms | × lit |\n| --- | --- | --- |",
            scene.name,
            self.frame_extent().width,
            self.frame_extent().height,
        );
        let draw = scene.scene.options.draw.clone();
        let mut lit_ms = f64::NAN;
        for stage in Stage::ALL {
            let mut session = self.session(&scene, &draw)?;
            session.settings.show = stage;
            if stage == Stage::Simulation {
                session.settings.arrows = Arrows::Step(SimStep::Length);
            }
            let ms = self.time_frames(&mut session)?.wall;
            if stage == Stage::Lit {
                lit_ms = ms;
            }
            let ratio = ms / lit_ms;
            self.row("stages", stage.name(), "frame", ms, "ms");
            self.row("stages", stage.name(), "ratio to lit", ratio, "x");
            let _ = writeln!(self.md, "| {} | {ms:.1} | {ratio:.2}× |", stage.name());
            (self.progress)(&format!("stage view {}", stage.name()));
        }
        self.md.push('\n');
        Ok(())
    }
}
