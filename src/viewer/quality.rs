//! The viewer's frame-time budget: each frame the controller (`render::budget`) sees
//! the wall-clock frame time and whether input came, and picks the ladder rung the fur
//! is drawn at; drawing choices made in the panel are the base every rung starts from.

use super::Viewer;
use fur_core::render::budget::{Budget, Ladder};
use fur_core::render::{FurStyle, Raster};
use fur_gpu::error::Result;

/// The frame-time budget and the styles it steers between.
pub(super) struct Quality {
    /// The rungs the budget steps along and a rung can be pinned to: the device's.
    pub ladder: Ladder,
    /// None: `--target-fps 0`, always the scene's drawing.
    pub budget: Option<Budget>,
    /// The drawing the scene (and the panel) asks for: rung 0.
    pub base: FurStyle,
    /// The drawing last applied (a change from it is the panel's).
    pub applied: FurStyle,
    /// Input (camera, model, parameters) came since the last frame.
    pub input_seen: bool,
    /// Every change of rung: (frame, rung).
    pub log: Vec<(u64, usize)>,
    /// Seconds since the last input.
    pub still_s: f64,
    /// The rung drawn at the last frame with input.
    pub moving_rung: usize,
    /// Per rung, its ꟻLIP against the default drawing, measured at a still view (None:
    /// not yet; reset when the panel changes the drawing).
    pub errors: Vec<Option<f64>>,
}

impl Quality {
    /// A budget holding `target_fps` (0: none) over `ladder`, starting from the drawing
    /// `style`.
    pub fn new(target_fps: f64, style: &FurStyle, ladder: Ladder) -> Self {
        Self {
            ladder,
            budget: (target_fps > 0.0).then(|| Budget::on(ladder, 1000.0 / target_fps)),
            base: style.clone(),
            applied: style.clone(),
            input_seen: false,
            log: Vec::new(),
            still_s: 0.0,
            moving_rung: 0,
            errors: vec![None; ladder.len()],
        }
    }
}

impl Viewer {
    /// On a CPU driver, and on a device whose geometry stage cannot write storage
    /// buffers, the strands are drawn by the fixed-function rasteriser whatever the scene
    /// or the panel asks: Mesa 22.3's lavapipe crashes drawing the window (the image onto
    /// the swapchain, the panel) after a simulated frame drew its strands in compute, and
    /// the other device cannot write them out; the tiles view, which needs the compute
    /// passes, shows the lit frame. Said once; on a CPU driver `fur render` and `fur
    /// bench` draw in compute.
    pub(super) fn hold_raster(&mut self) {
        let settings = &mut self.session.settings;
        let tiles = settings.show.needs_compute();
        let info = self.device.info();
        let cpu_driver = info.is_cpu();
        if (settings.style.raster != Raster::Compute && !tiles)
            || (!cpu_driver && info.vertex_pipeline_stores)
        {
            return;
        }
        settings.style.raster = Raster::Hardware;
        if tiles {
            settings.show = fur_core::render::Stage::Lit;
        }
        if !std::mem::replace(&mut self.raster_held, true) {
            let why = if cpu_driver {
                "a CPU driver: Mesa's lavapipe crashes drawing the window after the compute \
                 strand passes; fur render and fur bench draw them in compute"
            } else {
                "its geometry stage cannot write storage buffers \
                 (vertexPipelineStoresAndAtomics)"
            };
            eprintln!(
                "warning: the viewer draws the strands with the fixed-function rasteriser on \
                 {} ({why}), and shows the lit frame for the tiles view",
                info.name
            );
        }
    }

    /// Chooses this frame's rung from the last frame's time `dt` (seconds) and applies it.
    pub(super) fn steer_quality(&mut self, dt: f64) {
        // A change made in the panel since the last frame is the new base.
        if self.session.settings.style != self.quality.applied {
            self.quality.base = self.session.settings.style.clone();
            self.quality.errors.fill(None);
        }
        let input = std::mem::take(&mut self.quality.input_seen);
        if input {
            self.quality.still_s = 0.0;
            self.quality.moving_rung = self.hud.rung;
        } else {
            self.quality.still_s += dt;
        }
        let rung = match &mut self.quality.budget {
            Some(budget) if self.scripted.frame_index > 2 => {
                budget.pinned = self.controls.quality_pin;
                budget.observe(dt * 1e3, dt, input)
            }
            Some(budget) => budget.rung,
            None => self
                .controls
                .quality_pin
                .map_or(0, |r| r.min(self.quality.ladder.len() - 1)),
        };
        if rung != self.hud.rung {
            self.quality.log.push((self.scripted.frame_index, rung));
        }
        let style = self.quality.ladder.rung(rung).apply(&self.quality.base);
        self.session.settings.style = style.clone();
        self.quality.applied = style;
        self.hud.rung = rung;
        self.hud.rung_error = if rung == 0 {
            Some(0.0)
        } else {
            self.quality.errors[rung]
        };
        self.hud.budget_missed = self.quality.budget.as_ref().is_some_and(|b| b.missed);
    }

    /// At a still view, measures the ꟻLIP of a rung in use (or the one the view moved
    /// at) against the default drawing: both drawn from the same state, not simulated.
    /// One rung per frame, each once until the panel changes the drawing.
    pub(super) fn measure_rung_error(&mut self) -> Result<()> {
        if self.quality.still_s < Budget::IDLE_SECONDS {
            return Ok(());
        }
        let Some(r) = [self.hud.rung, self.quality.moving_rung]
            .into_iter()
            .find(|&r| r > 0 && self.quality.errors[r].is_none())
        else {
            return Ok(());
        };
        self.device.wait_idle()?;
        let style = self.session.settings.style.clone();
        // The rung in use is drawn last, so the renderer is left as the next frame
        // needs it (a change of sample count between the two is one switch, not two).
        let mut draw = |rung: usize| {
            self.session.settings.style = self.quality.ladder.rung(rung).apply(&self.quality.base);
            self.session.render().map(|(image, _)| image)
        };
        let (reference, drawn) = if self.hud.rung == r {
            let reference = draw(0)?;
            (reference, draw(r)?)
        } else {
            let drawn = draw(r)?;
            (draw(0)?, drawn)
        };
        self.session.settings.style = style;
        let error = fur_core::render::flip(&reference, &drawn);
        self.quality.errors[r] = Some(error);
        if r == self.hud.rung {
            self.hud.rung_error = Some(error);
        }
        Ok(())
    }
}
