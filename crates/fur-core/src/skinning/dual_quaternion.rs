//! Dual-quaternion skinning (Kavan et al. 2007) on the CPU, kept as a measurement: the
//! `animation` benchmark compares it with linear blend skinning on the walking critter
//! to show how much the choice moves the skin and the roots' normals at bent joints
//! (see docs/benchmark.md). The device skins with linear blending.

use glam::{Mat4, Quat, Vec3};

use crate::scene::Rig;

const ZERO: Quat = Quat::from_xyzw(0.0, 0.0, 0.0, 0.0);

/// A rigid transform as a unit dual quaternion `real + ε dual`, with a uniform scale
/// applied first.
#[derive(Clone, Copy, Debug)]
struct Dual {
    real: Quat,
    dual: Quat,
    scale: f32,
}

impl Dual {
    fn from_matrix(m: Mat4) -> Self {
        let (scale, rotation, translation) = m.to_scale_rotation_translation();
        let t = Quat::from_xyzw(translation.x, translation.y, translation.z, 0.0);
        Self {
            real: rotation,
            dual: (t * rotation) * 0.5,
            scale: (scale.x + scale.y + scale.z) / 3.0,
        }
    }
}

/// Skins the rig's bind positions and normals with the blended dual quaternion of each
/// vertex's joints (antipodal quaternions flipped onto the first joint's hemisphere,
/// the blend normalised). Returns (positions, normals).
pub fn skin(rig: &Rig, matrices: &[Mat4]) -> (Vec<Vec3>, Vec<Vec3>) {
    let duals: Vec<Dual> = matrices.iter().map(|m| Dual::from_matrix(*m)).collect();
    let identity = Dual {
        real: Quat::IDENTITY,
        dual: ZERO,
        scale: 1.0,
    };
    let count = rig.bind_positions.len();
    let mut positions = Vec::with_capacity(count);
    let mut normals = Vec::with_capacity(count);
    for v in 0..count {
        let (j, w) = (rig.influences[v], rig.weights[v]);
        let at = |k: usize| duals.get(j[k] as usize).copied().unwrap_or(identity);
        let pivot = at(0).real;
        let (mut real, mut dual) = (ZERO, ZERO);
        let mut scale = 0.0;
        for (k, &weight) in w.iter().enumerate() {
            let d = at(k);
            let sign = if d.real.dot(pivot) < 0.0 {
                -weight
            } else {
                weight
            };
            real = real + d.real * sign;
            dual = dual + d.dual * sign;
            scale += d.scale * weight;
        }
        let norm = real.length();
        if norm <= f32::EPSILON {
            positions.push(rig.bind_positions[v]);
            normals.push(rig.bind_normals[v]);
            continue;
        }
        let (real, dual) = (real * (1.0 / norm), dual * (1.0 / norm));
        // Translation of a unit dual quaternion: 2 · dual · conj(real).
        let t = (dual * real.conjugate()) * 2.0;
        let translation = Vec3::new(t.x, t.y, t.z);
        positions.push(real * (rig.bind_positions[v] * scale) + translation);
        normals.push((real * rig.bind_normals[v]).normalize_or_zero());
    }
    (positions, normals)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One joint: dual-quaternion skinning is that joint's rigid transform.
    #[test]
    fn a_single_joint_moves_rigidly() {
        let (mesh, mut rig) = crate::scene::critter();
        let m = Mat4::from_scale_rotation_translation(
            Vec3::splat(1.5),
            Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.4),
            Vec3::new(0.3, -1.0, 2.0),
        );
        for w in &mut rig.weights {
            *w = [1.0, 0.0, 0.0, 0.0];
        }
        let matrices = vec![m; rig.joints.len()];
        let (p, n) = skin(&rig, &matrices);
        for v in (0..mesh.positions.len()).step_by(97) {
            let want = m.transform_point3(rig.bind_positions[v]);
            assert!(
                (p[v] - want).length() < 1e-5,
                "vertex {v}: {} vs {want}",
                p[v]
            );
            let nw = m.transform_vector3(rig.bind_normals[v]).normalize();
            assert!((n[v] - nw).length() < 1e-5, "normal {v}");
        }
    }

    /// The critter's rig cut to one point, (0, 1, 0), weighted equally on joints 0 and 1.
    fn one_point_on_two_joints() -> crate::scene::Rig {
        let (_, mut rig) = crate::scene::critter();
        rig.bind_positions = vec![Vec3::new(0.0, 1.0, 0.0)];
        rig.bind_normals.truncate(1);
        rig.influences = vec![[0, 1, 0, 0]];
        rig.weights = vec![[0.5, 0.5, 0.0, 0.0]];
        rig
    }

    /// Two joints half a turn apart about an axis, weighted equally: linear blending
    /// collapses the point onto the axis (the candy wrapper), the dual quaternion keeps
    /// its distance from the axis.
    #[test]
    fn a_twist_keeps_its_radius() {
        let rig = one_point_on_two_joints();
        let twist = Mat4::from_rotation_x(std::f32::consts::PI * 0.9);
        let matrices = vec![Mat4::IDENTITY, twist];
        let (p, _) = skin(&rig, &matrices);
        let radius = Vec3::new(0.0, p[0].y, p[0].z).length();
        assert!((radius - 1.0).abs() < 1e-5, "radius {radius}");
        let (lbs, _, _) = rig.skin(&matrices, &[]);
        let collapsed = Vec3::new(0.0, lbs[0].y, lbs[0].z).length();
        assert!(collapsed < 0.2, "linear blending kept radius {collapsed}");
    }

    /// Two joints 1.1 half turns apart about x, after the same translation, weighted
    /// equally: the blend takes the shorter way round (the second joint's quaternion
    /// flipped into the first's hemisphere), to −0.45 half turns, and keeps the
    /// translation: (0, 1, 0) goes to (1, cos 0.45π, −sin 0.45π).
    #[test]
    fn the_blend_takes_the_shorter_way_and_keeps_the_translation() {
        let rig = one_point_on_two_joints();
        let move_x = Mat4::from_translation(Vec3::X);
        let matrices = vec![
            move_x,
            move_x * Mat4::from_rotation_x(std::f32::consts::PI * 1.1),
        ];
        let (p, _) = skin(&rig, &matrices);
        let a = std::f32::consts::PI * 0.45;
        let want = Vec3::new(1.0, a.cos(), -a.sin());
        assert!((p[0] - want).length() < 1e-5, "{} against {want}", p[0]);
    }
}
