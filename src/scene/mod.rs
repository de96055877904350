//! What is drawn: the mesh, its master hairs and the camera.

mod camera;
mod groom;
mod mesh;
mod model;
mod shapes;

pub use camera::Camera;
pub use groom::{hash_unit, GroomParams, Strands};
pub use mesh::Mesh;
pub use model::ModelSpec;
