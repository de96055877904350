//! Han & Harada (2012) strand simulation: parameters, the CPU reference and the
//! compute-shader implementation.

pub mod cpu;
mod motion;
mod params;
mod rest;
pub mod sdf;

pub use cpu::{CpuSim, Real, V3};
pub use motion::{Motion, MotionKind};
pub use params::{SimParams, StepConstants};
pub use rest::RestPose;
pub use sdf::{Sdf, SdfReport};
mod gpu;
pub use gpu::{GpuSim, SimStep, MAX_VERTICES};
