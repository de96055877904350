//! Real-time fur rendering and simulation on raw Vulkan.
//!
//! The pipeline, in the order a frame runs it:
//! - [`scene`]: the mesh, the master hairs grown from it ([`scene::Strands`]), the camera;
//! - [`strand_textures`]: master-hair vertices in RGBA32F images;
//! - [`sim`]: Han & Harada's simulation (CPU reference and compute shaders);
//! - [`render`]: the mesh pass and the tessellated fur pass;
//! - [`geometry`]: the distance fields and maths the scene and the simulation share;
//! - [`gpu`]: the Vulkan layer underneath.
//!
//! Everything without a device (the scene, settings, the CPU references, lighting
//! models, images) is the `fur-core` crate, re-exported here under the same paths.

pub mod bench;
pub mod error;
pub mod export;
pub mod gpu;
pub mod render;
pub mod session;
pub mod sim;
pub mod skinning;
pub mod strand_textures;
pub mod viewer;

pub use fur_core::{colour, files, geometry, interrupt, scene, scene_file};

pub use error::{Error, Result};
