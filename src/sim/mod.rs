//! Han & Harada (2012) strand simulation: parameters, the CPU reference and the
//! compute-shader implementation.

mod collide;
pub mod cpu;
mod field;
mod math;
mod motion;
mod params;
mod rest;
pub mod sdf;
mod steps;

pub use cpu::CpuSim;
pub use math::{Real, M3, V3};
pub use motion::{Motion, MotionKind};
pub use params::{SimParams, StepConstants};
pub use rest::RestPose;
pub use sdf::{Sdf, SdfReport};
mod gpu;
mod kernel;
pub use gpu::{GpuSim, SimStep, MAX_VERTICES};
