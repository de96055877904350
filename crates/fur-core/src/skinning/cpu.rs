//! The CPU reference of the skinning pass (`shaders/skin.comp`), with the same
//! arithmetic in the same order: linear blend skinning of positions, normals and
//! tangents, then one rigid root pose per strand.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::SkinnedBody;

/// A strand's root transform at one instant: `x ↦ rotation · (x − rest root) + root`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RootPose {
    pub rotation: Mat3,
    /// The skinned root position (model space, before the head transform).
    pub root: Vec3,
}

impl RootPose {
    /// Applies the pose to rest point `x` of a strand whose rest root is `rest_root`.
    pub fn point(&self, x: Vec3, rest_root: Vec3) -> Vec3 {
        self.rotation * (x - rest_root) + self.root
    }
}

/// The frame `[t, n × t, n]` of unit normal `n` and tangent `t` made orthogonal to it.
pub fn frame(n: Vec3, t: Vec3) -> Mat3 {
    let n = n.normalize();
    let t = (t - n * n.dot(t)).normalize();
    Mat3::from_cols(t, n.cross(t), n)
}

/// The skinned body at one pose: positions, normals, each strand's root pose and the
/// bones' capsules (see [`super::capsules::pose`]).
#[derive(Clone, Debug)]
pub struct Posed {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub roots: Vec<RootPose>,
    pub capsules: Vec<[Vec4; 2]>,
    /// The same capsules at the bind pose, where the rest field was built.
    pub rest_capsules: Vec<[Vec4; 2]>,
    /// Per joint, the first three rows of its motion from the rest pose (see
    /// [`super::blend::bone_rows`]).
    pub bones: Vec<[Vec4; 3]>,
}

/// Skins `body` with the joint `matrices` (see [`crate::scene::Rig::joint_matrices`]).
pub fn pose(body: &SkinnedBody, matrices: &[Mat4]) -> Posed {
    let (positions, normals, tangents) = body.rig.skin(matrices, &body.bind_tangents);
    let roots = positions
        .iter()
        .zip(normals.iter().zip(&tangents))
        .zip(&body.rest_frames)
        .map(|((&p, (&n, &t)), &(rt, rn))| {
            let rest = Mat3::from_cols(rt, rn.cross(rt), rn);
            RootPose {
                rotation: frame(n, t) * rest.transpose(),
                root: p,
            }
        })
        .collect();
    Posed {
        positions,
        normals,
        roots,
        capsules: super::capsules::pose(&body.capsules, matrices),
        rest_capsules: super::capsules::pose(&body.capsules, &[]),
        bones: super::blend::bone_rows(matrices, &body.rest_inverse),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_keep_the_normal() {
        let n = Vec3::new(0.3, 0.9, -0.1).normalize();
        let f = frame(n, Vec3::new(1.0, 0.2, 0.5));
        assert!((f.z_axis - n).length() < 1e-6);
        let g = f.transpose() * f;
        assert!((g - Mat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|e| e.abs() < 1e-6));
        assert!(f.determinant() > 0.999);
    }

    #[test]
    fn a_pose_maps_the_rest_root_onto_the_skinned_root_exactly() {
        let pose = RootPose {
            rotation: Mat3::from_rotation_y(0.7),
            root: Vec3::new(1.0, 2.0, 3.0),
        };
        let r = Vec3::new(-0.25, 0.5, 0.125);
        assert_eq!(pose.point(r, r), pose.root);
    }

    /// Every joint turned by one rotation R: every root pose's rotation is R (the
    /// posed frame times the rest frame's transpose), at the rest pose the identity.
    #[test]
    fn a_body_turned_whole_turns_every_root_pose_by_the_same_rotation() {
        let (mesh, rig) = crate::scene::critter();
        let body = SkinnedBody::new(&mesh, rig);
        let joints = body.rig.joints.len();
        let turn = Mat3::from_rotation_y(0.7) * Mat3::from_rotation_x(-0.4);
        for r in [Mat3::IDENTITY, turn] {
            let posed = pose(&body, &vec![Mat4::from_mat3(r); joints]);
            for (v, root) in posed.roots.iter().enumerate().step_by(53) {
                let off = (root.rotation - r).to_cols_array();
                assert!(
                    off.iter().all(|e| e.abs() < 1e-4),
                    "vertex {v}: {:?}",
                    root.rotation
                );
            }
        }
    }
}
