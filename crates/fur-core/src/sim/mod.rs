//! Han & Harada (2012) strand simulation: parameters, the named steps and the CPU
//! reference (the compute-shader implementation is the GPU layer's `sim` module).

pub mod collide;
pub mod cpu;
pub mod math;
pub mod motion;
pub mod params;
pub mod rest;
pub mod sdf;
pub mod steps;

pub use cpu::CpuSim;
pub use math::{Real, M3, V3};
pub use motion::{Motion, MotionKind};
pub use params::{SimParams, StepConstants};
pub use rest::RestPose;
pub use sdf::{Sdf, SdfReport};
pub use steps::SimStep;
