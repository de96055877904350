//! Scripted head motions: the mesh's model-to-world transform H as a function of time.

use std::f64::consts::TAU;
use std::str::FromStr;

use glam::{DMat4, DVec3};

/// What the head does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MotionKind {
    /// Stays put.
    #[default]
    Still,
    /// Side to side along x: `amplitude` metres at `rate` Hz.
    Shake,
    /// Turns about y at `rate` turns per second.
    Spin,
    /// Tilts about x: `amplitude` degrees at `rate` Hz.
    Nod,
}

impl MotionKind {
    pub fn name(self) -> &'static str {
        match self {
            Self::Still => "still",
            Self::Shake => "shake",
            Self::Spin => "spin",
            Self::Nod => "nod",
        }
    }
}

impl FromStr for MotionKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "still" | "none" => Ok(Self::Still),
            "shake" => Ok(Self::Shake),
            "spin" => Ok(Self::Spin),
            "nod" => Ok(Self::Nod),
            _ => Err(format!(
                "unknown motion `{s}` (expected still, shake, spin or nod)"
            )),
        }
    }
}

/// A scripted motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub kind: MotionKind,
    /// Metres for `shake`, degrees for `nod`; unused by `spin`.
    pub amplitude: f64,
    /// Hz for `shake` and `nod`, turns per second for `spin`.
    pub rate: f64,
}

impl Default for Motion {
    fn default() -> Self {
        Self {
            kind: MotionKind::Still,
            amplitude: 0.3,
            rate: 1.0,
        }
    }
}

/// The motion's amplitudes (a fraction of the bounding radius, or degrees) and rates
/// (Hz, or turns a second) a scene accepts.
pub const AMPLITUDE: crate::span::Span = crate::span::Span::within(-1e9, 1e9);
pub const RATE: crate::span::Span = crate::span::Span::within(0.0, 1e9);

impl Motion {
    pub fn still() -> Self {
        Self::default()
    }

    /// The head transform at `t` seconds.
    pub fn head(&self, t: f64) -> DMat4 {
        let phase = TAU * self.rate * t;
        match self.kind {
            MotionKind::Still => DMat4::IDENTITY,
            MotionKind::Shake => {
                DMat4::from_translation(DVec3::new(self.amplitude * phase.sin(), 0.0, 0.0))
            }
            MotionKind::Spin => DMat4::from_rotation_y(phase),
            MotionKind::Nod => DMat4::from_rotation_x(self.amplitude.to_radians() * phase.sin()),
        }
    }

    pub fn validate(&self) -> crate::Result<()> {
        AMPLITUDE
            .check("motion amplitude", self.amplitude)
            .and_then(|()| RATE.check("motion rate", self.rate))
            .map_err(crate::Error::Parameter)
    }
}
