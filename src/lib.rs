//! Real-time fur rendering and simulation on raw Vulkan.
//!
//! The application over the two lower crates: the command line's work ([`export`],
//! [`mod@bench`]), the window ([`viewer`]) and the drawings on top of a frame
//! ([`legend`], [`flow_marks`]). Everything below it is named where it lives:
//! `fur_core` holds what runs without a device (the scene, settings, the CPU
//! references, lighting models, images) and `fur_gpu` the device (the Vulkan layer,
//! kernels, passes, the session); neither is re-exported here.

pub mod bench;
pub mod export;
pub mod flow_marks;
pub mod legend;
pub mod setting_args;
pub mod viewer;

pub use fur_gpu::{Error, Result};
