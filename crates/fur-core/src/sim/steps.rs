//! The named steps of a substep, as `shaders/simulate.comp` runs them, and which of
//! them a scene needs.

use super::params::SimParams;

/// The named steps of a substep, in the order `simulate.comp` runs them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimStep {
    Integrate,
    Global,
    Local,
    Length,
    Wind,
    Collision,
}

impl SimStep {
    pub const ALL: [SimStep; 6] = [
        Self::Integrate,
        Self::Global,
        Self::Local,
        Self::Length,
        Self::Wind,
        Self::Collision,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Integrate => "integrate",
            Self::Global => "global shape",
            Self::Local => "local shape",
            Self::Length => "edge length",
            Self::Wind => "wind",
            Self::Collision => "collision",
        }
    }

    /// Its one-word name, as the `arrows` setting takes it.
    pub fn key(self) -> &'static str {
        match self {
            Self::Integrate => "integrate",
            Self::Global => "global",
            Self::Local => "local",
            Self::Length => "length",
            Self::Wind => "wind",
            Self::Collision => "collision",
        }
    }

    /// This step's bit in the kernel's `STEPS` specialization constant.
    pub fn bit(self) -> u32 {
        1 << self as u32
    }

    /// Whether `params` make this step do anything (collision also needs a body).
    pub fn needed(self, params: &SimParams, vertices: u32, has_body: bool) -> bool {
        match self {
            Self::Integrate => true,
            Self::Global => params.global_cutoff(vertices) > 0,
            Self::Local => params.local_stiffness > 0.0 && params.local_iterations > 0,
            Self::Length => params.length_iterations > 0,
            Self::Wind => params.wind_enabled(),
            Self::Collision => params.collision && has_body,
        }
    }
}
