//! What is drawn: the mesh, its master hairs and the camera.

mod camera;
mod critter;
mod flow;
mod gltf;
pub(crate) mod groom;
mod groom_bind;
mod groom_draw;
mod implicit;
mod mesh;
mod model;
mod obj;
mod rig;
mod rig_check;
mod rig_pose;
mod shapes;
mod texture;
mod texture_spec;

pub use camera::Camera;
pub use critter::critter;
pub use flow::{
    critical_points, singular_points, Flow, FlowField, FlowFrom, Singularity, AXIS_LEAN, CAP,
    HEAT_TIME,
};
pub use gltf::{load_gltf, write_glb, GltfBody};
pub use groom::{
    hash_unit, BoneFlow, Comb, GroomParams, Strands, BODY_PERCENTILE, FLAT_LEAN, ONE_BONE, THICK,
    THIN,
};
pub use groom_bind::{
    closest_on_triangle, nearest_surface_point, resample, GroomMode, GroomReport, GroomSource,
    Outside, SurfacePoint, BALD_FRACTION, BIND_LIMIT, BIND_TOLERANCE, BLEND_GUIDES, EXACT_ROOT,
    REGION_SPACINGS,
};
pub use groom_draw::{DrawnGroom, HairPatches};
pub use mesh::Mesh;
pub use model::ModelSpec;
pub use rig::{Channel, Clip, Interpolation, Joint, Node, Property, Rig, Transform};
pub use texture::Texture;
pub use texture_spec::TextureSpec;
