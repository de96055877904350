//! The viewer's clock: the wall-clock time of each frame, the simulation time it owes,
//! and the frame times the exit summary reports.

use std::time::Instant;

/// Wall-clock timing of the frames.
pub(super) struct Clock {
    last_frame: Instant,
    /// Seconds of the last frame.
    frame_dt: f64,
    /// Simulation time owed to the clock (seconds, under one step after each frame).
    sim_owed: f64,
    /// Wall-clock milliseconds of every frame after the first (for the exit summary).
    pub frame_times: Vec<f64>,
}

impl Clock {
    pub fn new() -> Self {
        Self {
            last_frame: Instant::now(),
            frame_dt: 0.0,
            sim_owed: 0.0,
            frame_times: Vec::new(),
        }
    }

    /// A frame begins: returns (and keeps) the seconds since the last one began.
    pub fn tick(&mut self) -> f64 {
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f64();
        self.last_frame = now;
        self.frame_dt = dt;
        dt
    }

    /// While paused the simulation owes nothing.
    pub fn pause(&mut self) {
        self.sim_owed = 0.0;
    }

    /// Fixed simulation steps of `step` seconds, decoupled from the frame rate: as many
    /// as wall-clock time has accumulated, at most 4 per frame (so a slow device slows
    /// the simulation down rather than spiralling).
    pub fn steps_owed(&mut self, step: f64) -> usize {
        self.sim_owed = (self.sim_owed + self.frame_dt).min(4.0 * step);
        let n = (self.sim_owed / step).floor() as usize;
        self.sim_owed -= n as f64 * step;
        n
    }
}
