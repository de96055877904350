//! Han & Harada (2012) strand simulation: the core's parameters and CPU reference
//! ([`fur_core::sim`]) and the compute-shader implementation.

mod field;
mod gpu;
mod kernel;

pub use gpu::{kernel_defines, GpuSim, SkinnedMotion, MAX_VERTICES};
