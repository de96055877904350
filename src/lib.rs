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
//! Three crates hold it, each layer only using the ones below: `fur-core` (everything
//! without a device: the scene, settings, the CPU references, lighting models, images),
//! `fur-gpu` (the Vulkan layer, kernels, passes and the session) and this one, the
//! application (the command line, the viewer, the benchmark, the frame export). The
//! lower crates' modules are re-exported here under the same paths.

pub mod bench;
pub mod export;
pub mod flow_marks;
pub mod legend;
pub mod setting_args;
pub mod viewer;

pub use fur_gpu::{
    colour, error, files, geometry, gpu, groom_file, interrupt, render, scene, scene_file, session,
    sim, skinning, strand_textures,
};

pub use error::{Error, Result};
