//! The body's signed distance field as the simulation uses it (the field itself:
//! [`crate::geometry::sdf`]): built once per model, padded by the hair length at the
//! simulation's resolution, and the hardest collision case the benchmark and the tests
//! judge it on.

use glam::Vec3;

use crate::error::Result;
pub use crate::geometry::sdf::*;
use crate::scene::Mesh;

impl Sdf {
    /// The field a simulation with `params` uses for hairs of `hair_length` on `mesh`
    /// (`skinned` or rigid): padded by the hair length, at `params`' resolution.
    pub fn for_hair(
        mesh: &Mesh,
        params: &super::params::SimParams,
        hair_length: f32,
        skinned: bool,
    ) -> Result<(Self, SdfReport)> {
        let cells = Self::cells_for_hair(mesh, params, hair_length, skinned);
        Self::build(mesh, cells, hair_length)
    }

    /// The resolution [`Sdf::for_hair`] builds at: `params`' cells along the longest
    /// axis of `mesh`'s box padded by the hair length.
    pub fn cells_for_hair(
        mesh: &Mesh,
        params: &super::params::SimParams,
        hair_length: f32,
        skinned: bool,
    ) -> u32 {
        let (min, max) = mesh.aabb();
        let extent = (max - min).max_element() + 2.0 * hair_length;
        params.sdf_cells(extent, hair_length, skinned)
    }
}

/// The hardest case collision is judged on, shared by the benchmark and the tests: hair
/// 0.3 × the model's bounding `radius` long combed down hard, under strong gravity (4×)
/// with no global shape and soft local shape, so it falls onto the body, while the head
/// shakes by a fifth of the radius at 2 Hz.
pub fn pressing_case(
    radius: f32,
    collision: bool,
) -> (crate::scene::GroomParams, super::SimParams, super::Motion) {
    let groom = crate::scene::GroomParams {
        segments: 12,
        segment_length: 0.3 * radius / 12.0,
        comb_direction: Vec3::NEG_Y,
        comb_strength: 3.0,
        ..Default::default()
    };
    let params = super::SimParams {
        gravity: Vec3::new(0.0, -40.0, 0.0),
        global_stiffness: 0.0,
        local_stiffness: 0.3,
        collision,
        ..super::SimParams::default()
    };
    let motion = super::Motion {
        kind: super::MotionKind::Shake,
        amplitude: 0.2 * f64::from(radius),
        rate: 2.0,
    };
    (groom, params, motion)
}
