//! What is drawn: the mesh, its master hairs and the camera.

mod camera;
mod groom;
mod mesh;
mod model;
mod obj;
mod shapes;
mod texture;
mod texture_spec;

pub use camera::Camera;
pub use groom::{hash_unit, GroomParams, Strands};
pub use mesh::Mesh;
pub use model::ModelSpec;
pub use texture::Texture;
pub use texture_spec::TextureSpec;
