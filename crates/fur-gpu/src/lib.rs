//! fur on a Vulkan device: the layer over `ash` ([`gpu`]), the master hairs in
//! textures ([`strand_textures`]), the simulation's and skinning's compute kernels
//! ([`sim`], [`skinning`]), the render passes ([`render`]) and the session that runs a
//! scene on them frame by frame ([`session`]).
//!
//! The device-free parts (scene, settings, the CPU references the kernels are checked
//! against, lighting models) are `fur-core`'s, named there (`fur_core::scene`); this
//! crate re-exports none of them.

pub mod error;
pub mod frame;
pub mod gpu;
pub mod render;
pub mod session;
pub mod sim;
pub mod skinning;
pub mod strand_textures;

pub use error::{Error, Result};

#[cfg(test)]
mod tests;
