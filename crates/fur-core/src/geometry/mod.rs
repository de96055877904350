//! Geometry that the scene and the simulation both build on: indexed triangles' bounds,
//! the scalar and 3-vector maths the CPU reference runs on, signed distance fields, and
//! which vertices and pieces a mesh joins.

pub mod grid;
pub mod math;
pub mod sdf;
pub mod topology;
mod triangles;

pub use math::{Real, V3};
pub use sdf::{Sdf, SdfReport};
pub use triangles::Triangles;
