//! What moves a skinned body: its node hierarchy, the joints its vertices are bound to
//! with their weights, and its animation clips (glTF 2.0's model of skins and
//! animations, kept in the form the skinning pass reads).
//!
//! Spaces: a skinned vertex is stored in *bind space* ([`Rig::bind_positions`]); joint
//! `k`'s skinning matrix at a pose is `scale · global(node_k) · inverse_bind_k`, and a
//! vertex's posed position is the weighted sum of its joints' matrices applied to its
//! bind position (linear blend skinning). The body's [`super::Mesh`] holds the *rest*
//! pose: every vertex skinned with the nodes at their rest transforms and no clip.

use glam::{Mat4, Quat, Vec3, Vec4};

/// A node's local transform: translation, rotation, scale (applied scale first).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }
}

impl Transform {
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A node of the hierarchy. Nodes are stored parents first: `parent < own index`.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub name: String,
    pub parent: Option<usize>,
    /// The transform with no clip playing.
    pub rest: Transform,
}

/// A skinning joint: the node that moves it and the inverse of its bind transform.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub node: usize,
    pub inverse_bind: Mat4,
}

/// How a channel's keys are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Holds each key until the next.
    Step,
    /// Straight lines; rotations by spherical interpolation on the shorter arc.
    Linear,
    /// Cubic Hermite with an in-tangent and out-tangent per key (glTF's CUBICSPLINE).
    CubicSpline,
}

/// Which part of a node's transform a channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    pub node: usize,
    pub property: Property,
    pub interpolation: Interpolation,
    /// Key times in seconds, strictly increasing, at least one.
    pub times: Vec<f32>,
    /// Per key one value (`Step`, `Linear`) or three (`CubicSpline`: in-tangent, value,
    /// out-tangent), in key order. Translations and scales use xyz (w = 0); rotations are
    /// quaternions as (x, y, z, w).
    pub values: Vec<Vec4>,
}

/// A named animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    pub name: String,
    pub channels: Vec<Channel>,
}

/// The skeleton, skin and clips of a skinned body, vertex-aligned with its mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    pub nodes: Vec<Node>,
    pub joints: Vec<Joint>,
    /// Per mesh vertex, four indices into `joints`.
    pub influences: Vec<[u16; 4]>,
    /// Per mesh vertex, four weights summing to 1 (unused slots weigh 0).
    pub weights: Vec<[f32; 4]>,
    /// Per mesh vertex, its position in bind space.
    pub bind_positions: Vec<Vec3>,
    /// Per mesh vertex, its unit normal in bind space.
    pub bind_normals: Vec<Vec3>,
    pub clips: Vec<Clip>,
    /// Uniform scale applied after skinning (a model rescaled into a sane size).
    pub scale: f32,
}
