//! The frame-time budget at work, as `fur view --target-fps` runs it: the default scene
//! orbited under a 100 ms budget (10 fps), simulated and drawn every frame (left on the
//! device, as the viewer's frames are, not copied to the host), the controller fed each
//! frame's wall-clock time; then no input, until the default drawing is back. Reports the median frame once the controller has settled, the rung it
//! settled on (and that rung's ꟻLIP from the ladder), and how long after the last input
//! the default frame was done.

use std::fmt::Write as _;
use std::time::Instant;

use super::metrics::median;
use super::Bench;
use fur_core::render::budget::Budget;
use fur_gpu::error::Result;

/// The budget the benchmark holds: 10 frames a second.
const TARGET_MS: f64 = 100.0;

impl Bench<'_> {
    /// Orbits the first scene under the budget; `errors[r]` is rung r's ꟻLIP there.
    pub(super) fn orbit(&mut self, errors: &[f64]) -> Result<()> {
        let Some(scene) = self.scenes.first().cloned() else {
            return Ok(());
        };
        let mut session = self.session(&scene, &scene.scene.options.draw)?;
        let base = session.settings.style.clone();
        let mut budget = Budget::on(self.device.info.ladder(base.raster), TARGET_MS);
        let (moving, still) = if self.quick { (30, 20) } else { (120, 40) };
        // (rung, wall ms) of every orbiting frame.
        let mut frames: Vec<(usize, f64)> = Vec::new();
        for _ in 0..moving {
            fur_core::interrupt::check()?;
            session.settings.camera.yaw_deg += 3.0;
            session.settings.style = budget.ladder().rung(budget.rung).apply(&base);
            let rung = budget.rung;
            let start = Instant::now();
            self.device
                .submit_once(|cmd| session.record_frame(cmd, 0, 1))?;
            let ms = start.elapsed().as_secs_f64() * 1e3;
            frames.push((rung, ms));
            budget.observe(ms, ms / 1e3, true);
        }
        (self.progress)(&format!("{}: orbit under the budget", scene.name));
        // The settled orbit: the frames since the last change of rung.
        let settled_rung = frames.last().map_or(0, |f| f.0);
        let since = frames
            .iter()
            .rposition(|f| f.0 != settled_rung)
            .map_or(0, |k| k + 1);
        let settled: Vec<f64> = frames[since..].iter().map(|f| f.1).collect();
        let orbit_ms = median(&settled);
        // Still: frames until the default drawing is done.
        let mut elapsed = 0.0;
        let (mut chosen_s, mut back_s) = (f64::NAN, f64::NAN);
        for _ in 0..still {
            fur_core::interrupt::check()?;
            session.settings.style = budget.ladder().rung(budget.rung).apply(&base);
            let rung = budget.rung;
            if rung == 0 && chosen_s.is_nan() {
                chosen_s = elapsed;
            }
            let start = Instant::now();
            self.device
                .submit_once(|cmd| session.record_frame(cmd, 0, 1))?;
            let ms = start.elapsed().as_secs_f64() * 1e3;
            elapsed += ms / 1e3;
            if rung == 0 {
                back_s = elapsed;
                break;
            }
            budget.observe(ms, ms / 1e3, false);
        }
        (self.progress)(&format!("{}: back to the default", scene.name));
        let error = errors.get(settled_rung).copied().unwrap_or(f64::NAN);
        let case = format!("{}: orbit at {TARGET_MS:.0} ms", scene.name);
        for (metric, value, unit) in [
            ("median_ms", orbit_ms, "ms"),
            ("settled_frames", settled.len() as f64, "count"),
            ("rung", settled_rung as f64, "index"),
            ("flip", error, "0..1"),
            ("default_chosen_s", chosen_s, "s"),
            ("back_to_default_s", back_s, "s"),
        ] {
            self.row("ladder", case.clone(), metric, value, unit);
        }
        let verdict = if orbit_ms <= TARGET_MS {
            "meets the target".to_string()
        } else if budget.missed {
            "misses the target: even the cheapest rung is too slow here".to_string()
        } else {
            "misses the target".to_string()
        };
        let _ = writeln!(
            self.md,
            "**The budget at work** ({}, {TARGET_MS:.0} ms a frame, as `fur view --target-fps \
             10`): orbiting 3° a frame, simulated and drawn every frame (not copied to the host), \
             the controller \
             settled on rung {settled_rung} ({}, ꟻLIP {error:.4}) after {since} frames; the \
             median of the {} frames since: {orbit_ms:.1} ms ({verdict}). With no input after \
             that, the controller chose the default {chosen_s:.2} s after the last input and \
             the default frame was done {back_s:.2} s after it (target: within 2 s).\n",
            scene.name,
            budget.ladder().rung(settled_rung).name,
            settled.len(),
        );
        Ok(())
    }
}
