//! Capsules bound to a skinned body's bones, fitted from its skin weights (no hand
//! tuning): what keeps hair out of *other* parts of the body as they move (a leg
//! swinging through the belly's fur), where the rest-pose field carried by each
//! strand's own root pose knows only the body around that root.
//!
//! Each bone's capsule runs from its joint to its first child joint (a leaf bone: to
//! twice the centroid of its vertices) and is *inscribed*: its radius is the 10th
//! percentile of its vertices' distances to that segment, so it lies inside the body
//! and never pushes hair off the skin where the body is thicker than a capsule.

use glam::{Mat4, Vec3, Vec4};

use crate::scene::Rig;

/// Fewest vertices a bone needs to get a capsule.
const MIN_VERTICES: usize = 4;
/// The percentile of the vertices' distances that is the radius.
const RADIUS_PERCENTILE: f32 = 0.1;

/// A capsule in bind space, moved by one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    pub joint: usize,
    pub a: Vec3,
    pub b: Vec3,
    pub radius: f32,
}

/// The distance from `p` to the segment `a`–`b`, and the closest point on it.
pub fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> (f32, Vec3) {
    let ab = b - a;
    let len2 = ab.dot(ab);
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let c = a + ab * t;
    (p.distance(c), c)
}

/// The joint a vertex is bound to most.
fn heaviest(joints: &[u16; 4], weights: &[f32; 4]) -> usize {
    let k = (0..4)
        .max_by(|&a, &b| weights[a].total_cmp(&weights[b]))
        .unwrap_or(0);
    usize::from(joints[k])
}

/// Per vertex of `rig`, the index of its heaviest joint's capsule, or [`u32::MAX`].
pub fn own(rig: &Rig, capsules: &[Capsule]) -> Vec<u32> {
    rig.influences
        .iter()
        .zip(&rig.weights)
        .map(|(j, w)| {
            let joint = heaviest(j, w);
            capsules
                .iter()
                .position(|c| c.joint == joint)
                .map_or(u32::MAX, |c| c as u32)
        })
        .collect()
}

/// One inscribed capsule per bone that has vertices of its own (those whose heaviest
/// influence it is).
pub fn fit(rig: &Rig) -> Vec<Capsule> {
    let heads: Vec<Vec3> = rig
        .joints
        .iter()
        .map(|j| j.inverse_bind.inverse().w_axis.truncate())
        .collect();
    let mut owned: Vec<Vec<Vec3>> = vec![Vec::new(); rig.joints.len()];
    for (v, (joints, weights)) in rig.influences.iter().zip(&rig.weights).enumerate() {
        if let Some(list) = owned.get_mut(heaviest(joints, weights)) {
            list.push(rig.bind_positions[v]);
        }
    }
    let mut capsules = Vec::new();
    for (j, joint) in rig.joints.iter().enumerate() {
        let points = &owned[j];
        if points.len() < MIN_VERTICES {
            continue;
        }
        let a = heads[j];
        let child = rig
            .joints
            .iter()
            .position(|c| rig.nodes.get(c.node).and_then(|n| n.parent) == Some(joint.node));
        let b = match child {
            Some(c) => heads[c],
            None => {
                let centroid = points.iter().copied().sum::<Vec3>() / points.len() as f32;
                a + 2.0 * (centroid - a)
            }
        };
        let mut distances: Vec<f32> = points
            .iter()
            .map(|&p| segment_distance(p, a, b).0)
            .collect();
        distances.sort_by(f32::total_cmp);
        let radius = distances[((distances.len() - 1) as f32 * RADIUS_PERCENTILE) as usize];
        if radius > 0.0 && radius.is_finite() {
            capsules.push(Capsule {
                joint: j,
                a,
                b,
                radius,
            });
        }
    }
    capsules
}

/// The capsules posed by the joint `matrices`, as the simulation reads them: per capsule
/// `(a, radius)` and `(b, 0)` in model space. A joint's scale scales its radius.
pub fn pose(capsules: &[Capsule], matrices: &[Mat4]) -> Vec<[Vec4; 2]> {
    capsules
        .iter()
        .map(|c| {
            let m = matrices.get(c.joint).copied().unwrap_or(Mat4::IDENTITY);
            let scale = m.determinant().abs().cbrt();
            [
                m.transform_point3(c.a).extend(c.radius * scale),
                m.transform_point3(c.b).extend(0.0),
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_critters_capsules_lie_inside_its_body() {
        let (mesh, rig) = crate::scene::critter();
        let capsules = fit(&rig);
        assert!(capsules.len() >= 15, "{} capsules", capsules.len());
        // Points on each capsule's axis are inside the closed body.
        let axis: Vec<Vec3> = capsules.iter().map(|c| (c.a + c.b) * 0.5).collect();
        let d = crate::geometry::sdf::exact_distances(&mesh, &axis);
        let outside = d.iter().filter(|&&d| d > 0.0).count();
        assert!(
            outside <= capsules.len() / 10,
            "{outside} axes outside the body"
        );
        // And most of the surface lies outside every capsule.
        let inside = mesh
            .positions
            .iter()
            .filter(|&&p| {
                capsules
                    .iter()
                    .any(|c| segment_distance(p, c.a, c.b).0 < c.radius * 0.999)
            })
            .count();
        assert!(
            inside * 5 < mesh.vertex_count(),
            "{inside} of {} vertices inside a capsule",
            mesh.vertex_count()
        );
    }

    #[test]
    fn segment_distance_clamps_to_the_ends() {
        let (a, b) = (Vec3::ZERO, Vec3::X);
        assert_eq!(segment_distance(Vec3::new(0.5, 2.0, 0.0), a, b).0, 2.0);
        assert_eq!(segment_distance(Vec3::new(3.0, 0.0, 0.0), a, b).0, 2.0);
        assert_eq!(segment_distance(Vec3::new(-1.0, 0.0, 0.0), a, b).1, a);
    }
}
