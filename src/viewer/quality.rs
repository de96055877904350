//! The viewer's frame-time budget: each frame the controller (`render::budget`) sees
//! the wall-clock frame time and whether input came, and picks the ladder rung the fur
//! is drawn at; drawing choices made in the panel are the base every rung starts from.

use super::Viewer;
use crate::render::budget::LADDER;

impl Viewer {
    /// Chooses this frame's rung from the last frame's time `dt` (seconds) and applies it.
    pub(super) fn steer_quality(&mut self, dt: f64) {
        // A change made in the panel since the last frame is the new base.
        if self.session.settings.style != self.quality.applied {
            self.quality.base = self.session.settings.style.clone();
        }
        let input = std::mem::take(&mut self.quality.input_seen);
        let rung = match &mut self.quality.budget {
            Some(budget) if self.frame_index > 2 => {
                budget.pinned = self.controls.quality_pin;
                budget.observe(dt * 1e3, dt, input)
            }
            Some(budget) => budget.rung,
            None => self.controls.quality_pin.unwrap_or(0),
        };
        if rung != self.hud.rung {
            self.quality.log.push((self.frame_index, rung));
        }
        let style = LADDER[rung].apply(&self.quality.base);
        self.session.settings.style = style.clone();
        self.quality.applied = style;
        self.hud.rung = rung;
        self.hud.budget_missed = self.quality.budget.as_ref().is_some_and(|b| b.missed);
    }
}
