//! Holding a frame rate by trading image quality: a ladder of drawing settings from the
//! default down to the cheapest that still reads as fur (each rung costs less and errs
//! more than the one above; `fur bench --only ladder` measures both), and a controller
//! that picks the most accurate rung whose cost fits a frame-time budget, predicted from
//! the frame times it observes on this device and scene.
//!
//! The first descent is quick: from the default's second frame (the faster of its first
//! two is its cost: the first may be cold), the controller jumps to the most accurate
//! rung the cost ratios predict to fit, looks once
//! at the rung above if the prediction was close, and holds there (a device 1× or 10×
//! slower than the ratios' guess settles within three frames). A rung's first frame
//! that takes more than twice its prediction is taken as cold (its pipelines compiling)
//! and not observed. After that the controller holds still against noise: it steps down only when the current rung's
//! smoothed time is over the budget, up only when the rung above is predicted to fit with
//! room to spare, and changes at most once every [`Budget::SETTLE_FRAMES`] frames. When no
//! input has come for [`Budget::IDLE_SECONDS`], it goes back to the default at once,
//! whatever the frame rate: a person inspecting the fur sees it at full quality. When
//! input comes again it returns to the rung it was moving at, so a person moving the
//! fur sees it move without stepping down the ladder again.

use super::{FurStyle, Primitive, Raster};

/// One rung: how the fur is drawn, relative to the scene's own style.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rung {
    pub name: &'static str,
    pub samples: u32,
    pub primitive: Primitive,
    /// Vertex LOD tolerance in pixels.
    pub vertex_lod_px: f32,
    /// Multiplies the full-density distance (below 1 the density LOD starts closer; the
    /// hairs it thins out are widened, so coverage is kept).
    pub density_lod: f32,
    /// The strand rasteriser the rung draws with; `None` keeps the scene's.
    pub raster: Option<Raster>,
}

/// The first rung of every ladder: the scene's own drawing.
const DEFAULT: Rung = Rung {
    name: "default",
    samples: 4,
    primitive: Primitive::Ribbons,
    vertex_lod_px: 0.05,
    density_lod: 1.0,
    raster: None,
};

/// A rung at `samples` per pixel with `primitive` through the fixed-function
/// rasteriser, the default vertex LOD and density.
const fn msaa(name: &'static str, samples: u32, primitive: Primitive) -> Rung {
    Rung {
        name,
        samples,
        primitive,
        raster: Some(Raster::Hardware),
        ..DEFAULT
    }
}

/// A rung drawn by the compute rasteriser with the vertex LOD `vertex_lod_px` and the
/// density distance scaled by `density_lod`.
const fn compute(name: &'static str, vertex_lod_px: f32, density_lod: f32) -> Rung {
    Rung {
        name,
        vertex_lod_px,
        density_lod,
        raster: Some(Raster::Compute),
        ..DEFAULT
    }
}

/// The ladder of CPU drivers, most accurate first: the scene's own drawing (in compute
/// unless the scene asks for the fixed-function rasteriser), then 4× lines, 1-sample
/// ribbons, 1-sample blended lines and coarser vertex and density LOD, all through the
/// fixed-function rasteriser, each cheaper on lavapipe than the rung above (`fur bench
/// --only ladder` measures whether they are).
pub const LADDER: [Rung; 6] = [
    DEFAULT,
    msaa("4x lines", 4, Primitive::Lines),
    msaa("1x ribbons", 1, Primitive::Ribbons),
    msaa("1x lines", 1, Primitive::Lines),
    Rung {
        vertex_lod_px: 0.5,
        ..msaa("1x lines, vertex LOD 0.5 px", 1, Primitive::Lines)
    },
    Rung {
        vertex_lod_px: 0.5,
        density_lod: 0.25,
        ..msaa("1x lines, quarter density distance", 1, Primitive::Lines)
    },
];

/// The ladder of GPUs for a scene drawn by the fixed-function rasteriser: 4× lines,
/// then the strands drawn in compute, then with coarser vertex and density LOD. On the
/// one GPU measured (an NVIDIA H200, docs/gpu.md) the compute frame erred less than
/// every 1-sample rung and cost less than all of them but the one that thins the hair
/// out.
pub const COMPUTE_LADDER: [Rung; 5] = [
    DEFAULT,
    msaa("4x lines", 4, Primitive::Lines),
    compute("compute strands", 0.05, 1.0),
    compute("compute strands, vertex LOD 0.5 px", 0.5, 1.0),
    compute("compute strands, quarter density distance", 0.5, 0.25),
];

/// The ladder of GPUs for a scene drawn in compute (the default): the compute strands
/// with coarser vertex and density LOD (the fixed-function rungs cost more there).
pub const IN_COMPUTE_LADDER: [Rung; 3] = [
    DEFAULT,
    compute("compute strands, vertex LOD 0.5 px", 0.5, 1.0),
    compute("compute strands, quarter density distance", 0.5, 0.25),
];

/// A ladder: its rungs, most accurate first, and a first guess of each rung's cost
/// relative to the first (a starting point, read once off the ladder's measurement on
/// its kind of device, refined as soon as a rung is drawn; only their order matters
/// before that: `a_bad_first_guess_is_corrected`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ladder {
    pub rungs: &'static [Rung],
    guesses: &'static [f64],
}

impl Ladder {
    /// [`LADDER`], guessed from lavapipe's measurement.
    pub const FIXED: Self = Self {
        rungs: &LADDER,
        guesses: &[1.0, 0.57, 0.4, 0.27, 0.19, 0.09],
    };
    /// [`COMPUTE_LADDER`]: 4× lines' and the compute strands' read off an NVIDIA H200's
    /// run (its ladder and quality tables), the LOD rungs' guessed below them.
    pub const COMPUTE: Self = Self {
        rungs: &COMPUTE_LADDER,
        guesses: &[1.0, 0.61, 0.4, 0.3, 0.15],
    };
    /// [`IN_COMPUTE_LADDER`]: [`Ladder::COMPUTE`]'s guesses for its LOD rungs, against
    /// its compute strands.
    pub const IN_COMPUTE: Self = Self {
        rungs: &IN_COMPUTE_LADDER,
        guesses: &[1.0, 0.75, 0.375],
    };

    /// Rung `r`, or the cheapest past the end.
    pub fn rung(&self, r: usize) -> &'static Rung {
        &self.rungs[r.min(self.rungs.len() - 1)]
    }

    /// The number of rungs.
    pub fn len(&self) -> usize {
        self.rungs.len()
    }

    /// Never: every ladder has its default rung.
    pub fn is_empty(&self) -> bool {
        self.rungs.is_empty()
    }
}

impl Rung {
    /// `style` drawn at this rung; rung 0 leaves `style` exactly as it is.
    pub fn apply(&self, style: &FurStyle) -> FurStyle {
        if *self == DEFAULT {
            return style.clone();
        }
        FurStyle {
            samples: self.samples.min(style.samples),
            primitive: self.primitive,
            vertex_lod_px: self.vertex_lod_px.max(style.vertex_lod_px),
            lod_distance: style.lod_distance * self.density_lod,
            thickness_compensation: true,
            raster: self.raster.unwrap_or(style.raster),
            ..style.clone()
        }
    }
}

/// The most rungs a ladder has (progress counts).
pub const MOST_RUNGS: usize = if LADDER.len() > COMPUTE_LADDER.len() {
    LADDER.len()
} else {
    COMPUTE_LADDER.len()
};

/// A frame-time budget over a [`Ladder`].
#[derive(Clone, Debug)]
pub struct Budget {
    /// The rungs it steps along (its per-rung state is sized from them).
    ladder: Ladder,
    /// Milliseconds a frame may take.
    pub target_ms: f64,
    /// The rung in use.
    pub rung: usize,
    /// A rung the user pinned: the controller keeps it.
    pub pinned: Option<usize>,
    /// Per rung, the smoothed frame time observed there (None: never drawn).
    observed: Vec<Option<f64>>,
    /// Per rung, the cost relative to rung 0 as first guessed, refined by what is seen.
    ratio: Vec<f64>,
    frames_since_change: u32,
    /// Seconds since the last input (camera, model or parameters).
    idle_s: f64,
    /// The rung in use when the input stopped (None: not refined since).
    moving_rung: Option<usize>,
    /// The cheapest rung missed the budget (said once).
    pub missed: bool,
    /// The first descent is under way (no rung has been seen to fit yet).
    descending: bool,
    /// The first descent has looked at the rung above the one it jumped to.
    probed: bool,
    /// The first descent's frames at the default: it decides on the second, taking the
    /// faster of the two as the default's cost (the first may be cold).
    first_frames: u32,
    /// Per rung, a first frame was already taken as cold.
    cold_seen: Vec<bool>,
}

impl Budget {
    // The constants below are tuned (docs/testing.md, "Tuned constants"); the unit tests
    // work every frame count out from them.

    /// Frames between two changes of rung, at least.
    pub const SETTLE_FRAMES: u32 = 8;
    /// Seconds without input after which the controller refines.
    pub const IDLE_SECONDS: f64 = 0.5;
    /// Step down above this share of the budget.
    const OVER: f64 = 1.05;
    /// Step up when the rung above is predicted under this share of it.
    const UNDER: f64 = 0.8;
    /// Smoothing of the observed times (weight of the newest frame).
    const SMOOTHING: f64 = 0.3;
    /// A rung's first frame over this many times its prediction is taken as cold.
    const COLD: f64 = 2.0;
    /// The first descent looks at the rung above the one it jumped to when that is
    /// predicted under this share of the budget: the first guesses of the ratios can be
    /// a third off (the fake device of the tests: 0.27 guessed, 0.2 there).
    const PROBE: f64 = 1.3;

    /// A budget of `target_ms` per frame over [`Ladder::FIXED`], starting at the
    /// default rung (the tests' fake device).
    #[cfg(test)]
    fn new(target_ms: f64) -> Self {
        Self::on(Ladder::FIXED, target_ms)
    }

    /// The rungs it steps along.
    pub fn ladder(&self) -> Ladder {
        self.ladder
    }

    /// A budget of `target_ms` per frame over `ladder`, starting at the default rung.
    pub fn on(ladder: Ladder, target_ms: f64) -> Self {
        Self {
            ladder,
            target_ms,
            rung: 0,
            pinned: None,
            observed: vec![None; ladder.len()],
            ratio: ladder.guesses.to_vec(),
            frames_since_change: 0,
            idle_s: 0.0,
            moving_rung: None,
            missed: false,
            descending: true,
            probed: false,
            first_frames: 0,
            cold_seen: vec![false; ladder.len()],
        }
    }

    /// The predicted frame time of rung `r`: observed there, else scaled from the
    /// nearest observed rung by the cost ratios.
    pub fn predicted_ms(&self, r: usize) -> Option<f64> {
        if let Some(ms) = self.observed[r] {
            return Some(ms);
        }
        let (near, ms) = (0..self.ladder.len())
            .filter_map(|k| self.observed[k].map(|ms| (k, ms)))
            .min_by_key(|(k, _)| k.abs_diff(r))?;
        Some(ms * self.ratio[r] / self.ratio[near])
    }

    /// Records a frame of `frame_ms` drawn at the current rung, `dt_s` seconds after the
    /// last, with or without input since; returns the rung for the next frame.
    pub fn observe(&mut self, frame_ms: f64, dt_s: f64, input: bool) -> usize {
        let r = self.rung;
        // A rung's first frame far over its prediction paid for compiling its
        // pipelines: the next frame at this rung tells (once per rung).
        let cold = self.observed[r].is_none()
            && !self.cold_seen[r]
            && self
                .predicted_ms(r)
                .is_some_and(|p| frame_ms > Self::COLD * p);
        self.cold_seen[r] |= cold;
        if !cold && frame_ms.is_finite() && frame_ms > 0.0 {
            let smoothed = match self.observed[r] {
                Some(old) => old + Self::SMOOTHING * (frame_ms - old),
                None => frame_ms,
            };
            self.observed[r] = Some(smoothed);
            // Keep the ratios consistent with what is seen.
            if let (Some(top), Some(here)) = (self.observed[0], self.observed[r]) {
                if r > 0 && here < top {
                    self.ratio[r] = here / top;
                }
            }
        }
        self.frames_since_change = self.frames_since_change.saturating_add(1);
        if input {
            self.idle_s = 0.0;
        } else {
            self.idle_s += dt_s.max(0.0);
        }
        if let Some(p) = self.pinned {
            return self.set(p.min(self.ladder.len() - 1));
        }
        if self.target_ms <= 0.0 {
            return self.set(0);
        }
        // Still: back to the default at once.
        if self.idle_s >= Self::IDLE_SECONDS {
            if r > 0 {
                self.moving_rung = Some(r);
                return self.set(0);
            }
            return r;
        }
        // Moving again after a refinement: straight back to the rung that was moving.
        if let Some(moving) = self.moving_rung.take() {
            if input {
                return self.set(moving);
            }
        }
        if cold {
            return r;
        }
        if self.descending {
            return self.descend(frame_ms);
        }
        if self.frames_since_change < Self::SETTLE_FRAMES {
            return r;
        }
        let current = self.observed[r].unwrap_or(frame_ms);
        if current > self.target_ms * Self::OVER {
            if r + 1 < self.ladder.len() {
                return self.set(r + 1);
            }
            self.missed = true;
            return r;
        }
        if r > 0 {
            if let Some(up) = self.predicted_ms(r - 1) {
                if up < self.target_ms * Self::UNDER {
                    return self.set(r - 1);
                }
            }
        }
        r
    }

    /// One frame of the first descent at the current rung, which took `frame_ms`.
    fn descend(&mut self, frame_ms: f64) -> usize {
        let r = self.rung;
        if r == 0 && frame_ms.is_finite() && frame_ms > 0.0 {
            self.first_frames += 1;
            match self.first_frames {
                // The first frame may pay for compiling the default's pipelines.
                1 => {
                    self.observed[0] = Some(frame_ms);
                    return r;
                }
                // A cold frame is only ever slower: the faster one is the cost.
                2 => self.observed[0] = self.observed[0].map(|first| first.min(frame_ms)),
                _ => {}
            }
        }
        let current = self.observed[r].unwrap_or(frame_ms);
        if current > self.target_ms * Self::OVER {
            let last = self.ladder.len() - 1;
            if r == last {
                self.missed = true;
                self.descending = false;
                return r;
            }
            // The most accurate rung below predicted to fit, else the cheapest.
            let fits = (r + 1..=last)
                .find(|&k| self.predicted_ms(k).is_some_and(|p| p <= self.target_ms))
                .unwrap_or(last);
            return self.set(fits);
        }
        // It fits. The ratios are guesses: once, look at the rung above if it is
        // predicted near the budget (it is kept only if it fits).
        if r > 0 && !self.probed && self.observed[r - 1].is_none() {
            self.probed = true;
            if self
                .predicted_ms(r - 1)
                .is_some_and(|p| p <= self.target_ms * Self::PROBE)
            {
                return self.set(r - 1);
            }
        }
        self.descending = false;
        r
    }

    fn set(&mut self, r: usize) -> usize {
        if r != self.rung {
            self.rung = r;
            self.frames_since_change = 0;
        }
        r
    }
}

#[cfg(test)]
mod tests;
