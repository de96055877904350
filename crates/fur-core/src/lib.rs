//! fur's core, without Vulkan: the scene (meshes, rigs, grooms, the camera), the
//! settings and scene files, the simulation's and skinning's CPU references, the
//! drawing's settings and lighting models with their CPU twins, images, colour and
//! files. The GPU layer (`fur`) builds on it; nothing here knows a device.

pub mod colour;
pub mod error;
pub mod files;
pub mod geometry;
pub mod groom_file;
pub mod interrupt;
pub mod isolate;
pub mod render;
pub mod scene;
pub mod scene_file;
pub mod setting;
pub mod sim;
pub mod skinning;
pub mod span;

pub use error::{Error, Result};

#[cfg(test)]
mod test_alloc;
