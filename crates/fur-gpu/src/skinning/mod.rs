//! Skinned bodies in motion: the core's clips, root frames and CPU reference
//! ([`fur_core::skinning`]) and the compute pass that skins the body on the device.

pub mod gpu;

pub use gpu::{GpuSkin, SkinCapacity};
