//! The built-in creature: a small four-legged furry animal (think a fox), made by code.
//! Its body is a smooth union of tapered capsules and ellipsoids (one or more per bone),
//! polygonised by surface nets into one closed mesh; each vertex is bound smoothly to
//! the bones whose parts lie nearest the surface there; it walks (a trot, with root
//! motion) and idles (tail wag, ear twitches, breathing, a slow look around).
//!
//! glTF conventions: +Y up, facing +Z, the animal's left on +X; about 1.6 units from the
//! nose to the tail's base, standing on y = 0.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::implicit::{self, Part, Shape};
use super::{Joint, Mesh, Node, Rig, Transform};

mod clips;
#[cfg(test)]
mod tests;

/// Grid spacing of the polygonisation (sets the vertex count: 5,492).
const CELL: f32 = 0.027;
/// Width of the weight blend between neighbouring parts (scene units).
const BLEND: f32 = 0.035;
/// How far the root travels forward over one walk cycle.
const STRIDE: f32 = 1.0;

/// Where the left ear ends (the right ear mirrors it).
const EAR_TIP: Vec3 = Vec3::new(0.12, 1.28, 0.56);

/// A bone of the skeleton: name, parent and rest position in world space (every rest
/// rotation is the identity, so local axes are world axes: x across, y up, z forwards).
type Bone = (String, Option<usize>, Vec3);

fn skeleton() -> Vec<Bone> {
    let mut bones: Vec<Bone> = Vec::new();
    let mut add = |name: &str, parent: Option<usize>, at: [f32; 3]| {
        bones.push((name.to_string(), parent, Vec3::from(at)));
        bones.len() - 1
    };
    let root = add("root", None, [0.0, 0.72, -0.42]);
    let spine = add("spine", Some(root), [0.0, 0.74, -0.10]);
    let chest = add("chest", Some(spine), [0.0, 0.76, 0.20]);
    let neck = add("neck", Some(chest), [0.0, 0.84, 0.36]);
    let head = add("head", Some(neck), [0.0, 1.0, 0.56]);
    add("snout", Some(head), [0.0, 0.99, 0.70]);
    add("ear.L", Some(head), [0.075, 1.10, 0.58]);
    add("ear.R", Some(head), [-0.075, 1.10, 0.58]);
    for (side, x) in [("L", 1.0), ("R", -1.0)] {
        let upper = add(
            &format!("front_leg.{side}.upper"),
            Some(chest),
            [0.12 * x, 0.68, 0.24],
        );
        let lower = add(
            &format!("front_leg.{side}.lower"),
            Some(upper),
            [0.12 * x, 0.40, 0.21],
        );
        add(
            &format!("front_leg.{side}.paw"),
            Some(lower),
            [0.12 * x, 0.12, 0.25],
        );
    }
    let tail = add("tail.1", Some(root), [0.0, 0.76, -0.60]);
    let tail = add("tail.2", Some(tail), [0.0, 0.80, -0.82]);
    add("tail.3", Some(tail), [0.0, 0.88, -1.02]);
    for (side, x) in [("L", 1.0), ("R", -1.0)] {
        let upper = add(
            &format!("hind_leg.{side}.upper"),
            Some(root),
            [0.12 * x, 0.66, -0.40],
        );
        let lower = add(
            &format!("hind_leg.{side}.lower"),
            Some(upper),
            [0.125 * x, 0.40, -0.29],
        );
        add(
            &format!("hind_leg.{side}.paw"),
            Some(lower),
            [0.125 * x, 0.16, -0.46],
        );
    }
    bones
}

/// The index of the bone named `name`.
fn bone(bones: &[Bone], name: &str) -> usize {
    bones
        .iter()
        .position(|b| b.0 == name)
        .expect("a critter bone")
}

/// The body's parts, each with the bone it moves with, in smooth-union order.
fn parts(bones: &[Bone]) -> Vec<(usize, Part)> {
    let at = |name: &str| bones[bone(bones, name)].2;
    let cone = |name: &str, a: Vec3, ra: f32, b: Vec3, rb: f32, blend: f32| {
        (
            bone(bones, name),
            Part::new(Shape::Cone { a, b, ra, rb }, blend),
        )
    };
    let ellipsoid = |name: &str, centre: Vec3, radii: Vec3, blend: f32| {
        (
            bone(bones, name),
            Part::new(Shape::Ellipsoid { centre, radii }, blend),
        )
    };
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let mut parts = vec![
        cone("root", v(0.0, 0.72, -0.47), 0.175, at("spine"), 0.17, 0.0),
        cone("spine", at("spine"), 0.17, at("chest"), 0.2, 0.05),
        cone("chest", at("chest"), 0.2, v(0.0, 0.78, 0.30), 0.19, 0.05),
        ellipsoid("chest", v(0.0, 0.72, 0.16), v(0.18, 0.22, 0.24), 0.08),
        cone("neck", v(0.0, 0.82, 0.34), 0.13, at("head"), 0.10, 0.08),
        cone("snout", at("snout"), 0.08, v(0.0, 0.95, 0.93), 0.04, 0.05),
    ];
    for (name, x) in [("ear.L", 1.0), ("ear.R", -1.0)] {
        let mut ear = cone(name, at(name), 0.065, EAR_TIP * v(x, 1.0, 1.0), 0.032, 0.03);
        // Thin front to back.
        ear.1.squash = Some((at(name), Vec3::Z, 1.6));
        parts.push(ear);
    }
    parts.push(cone(
        "tail.1",
        v(0.0, 0.76, -0.56),
        0.065,
        at("tail.2"),
        0.058,
        0.06,
    ));
    parts.push(cone(
        "tail.2",
        at("tail.2"),
        0.058,
        at("tail.3"),
        0.05,
        0.02,
    ));
    parts.push(cone(
        "tail.3",
        at("tail.3"),
        0.05,
        v(0.0, 1.0, -1.18),
        0.03,
        0.02,
    ));
    for (limb, top, knee, toe) in [
        ("front_leg", 0.08, 0.055, 0.29),
        ("hind_leg", 0.095, 0.06, -0.38),
    ] {
        for side in ["L", "R"] {
            let name = |part: &str| format!("{limb}.{side}.{part}");
            let (upper, lower, paw) = (at(&name("upper")), at(&name("lower")), at(&name("paw")));
            parts.push(cone(&name("upper"), upper, top, lower, knee, 0.05));
            parts.push(cone(&name("lower"), lower, knee - 0.003, paw, 0.037, 0.03));
            parts.push(cone(
                &name("paw"),
                paw,
                0.037,
                v(paw.x, 0.05, toe - 0.02),
                0.039,
                0.02,
            ));
            parts.push(ellipsoid(
                &name("paw"),
                v(paw.x, 0.04, toe),
                v(0.048, 0.04, 0.065),
                0.03,
            ));
        }
    }
    // The head last: it blends with the neck, snout and ears before it.
    parts.push(ellipsoid(
        "head",
        v(0.0, 1.02, 0.60),
        v(0.145, 0.13, 0.15),
        0.06,
    ));
    parts
}

/// The built-in creature: its rest-pose mesh (5,492 vertices, closed, outward
/// wound, smooth normals, mirrored cylindrical texture coordinates) and its rig (23
/// named nodes, all joints, bind pose = rest pose; clips `Walk`, 1 s, and `Idle`, 2 s).
/// Deterministic.
pub fn critter() -> (Mesh, Rig) {
    let bones = skeleton();
    let tagged = parts(&bones);
    let parts: Vec<Part> = tagged.iter().map(|(_, p)| *p).collect();
    // The unshifted grid gives a closed surface (so do all 32 shifts tried: they are a
    // fallback should the shapes change).
    let (positions, indices) = (0..32u32)
        .find_map(|k| {
            let shift = Vec3::new(0.618_034, 0.414_213_6, 0.732_050_8) * k as f32;
            implicit::surface_nets(&parts, CELL, shift - shift.floor())
        })
        .expect("the critter polygonises to a closed surface");
    let normals: Vec<Vec3> = positions
        .iter()
        .map(|&p| implicit::gradient(&parts, p, 0.25 * CELL))
        .collect();
    let uvs = body_uvs(&positions, &indices);
    let mesh = Mesh {
        positions,
        normals,
        indices,
        uvs,
        texture: None,
    };

    let nodes: Vec<Node> = bones
        .iter()
        .map(|(name, parent, at)| {
            let translation = *at - parent.map_or(Vec3::ZERO, |p| bones[p].2);
            Node {
                name: name.clone(),
                parent: *parent,
                rest: Transform {
                    translation,
                    ..Transform::default()
                },
            }
        })
        .collect();
    let mut rig = Rig {
        nodes,
        joints: Vec::new(),
        influences: Vec::new(),
        weights: Vec::new(),
        bind_positions: mesh.positions.clone(),
        bind_normals: mesh.normals.clone(),
        clips: Vec::new(),
        scale: 1.0,
    };
    let world = rig.world(&rig.pose(None, 0.0, false));
    rig.joints = world
        .iter()
        .enumerate()
        .map(|(node, m)| Joint {
            node,
            inverse_bind: m.inverse(),
        })
        .collect();
    (rig.influences, rig.weights) = bind(&tagged, bones.len(), &mesh.positions);
    rig.clips = vec![clips::walk(&bones), clips::idle(&bones)];
    (mesh, rig)
}

/// Texture coordinates per corner from one value per vertex (so every corner of a
/// vertex agrees, with no seam): u = |angle around the body's long axis| / π, 0 along
/// the back's midline and 1 along the belly's (both flanks mirror one image), v from
/// the nose (0) to the tail's tip (1).
fn body_uvs(positions: &[Vec3], indices: &[u32]) -> Vec<Vec2> {
    let (lo, hi) = positions.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| {
        (lo.min(p.z), hi.max(p.z))
    });
    indices
        .iter()
        .map(|&i| {
            let p = positions[i as usize];
            Vec2::new(p.x.atan2(p.y - 0.74).abs() / PI, (hi - p.z) / (hi - lo))
        })
        .collect()
}

/// Smooth skin weights: per vertex, each bone scores a Gaussian of how much further its
/// nearest part lies than the nearest part of all (so a leg never pulls the far side of
/// the body, and neighbouring parts blend over about `BLEND`); the four best, those
/// above 1% of the best, renormalised. Sorted heaviest first; unused slots are joint 0
/// with weight 0.
fn bind(
    parts: &[(usize, Part)],
    bones: usize,
    positions: &[Vec3],
) -> (Vec<[u16; 4]>, Vec<[f32; 4]>) {
    positions
        .iter()
        .map(|&p| {
            let d: Vec<f32> = parts.iter().map(|(_, part)| part.distance(p)).collect();
            let nearest = d.iter().copied().fold(f32::MAX, f32::min);
            let mut score = vec![0.0f32; bones];
            for ((b, _), d) in parts.iter().zip(d) {
                score[*b] = score[*b].max((-((d - nearest) / BLEND).powi(2)).exp());
            }
            let mut order: Vec<usize> = (0..bones).collect();
            order.sort_by(|a, b| score[*b].total_cmp(&score[*a]).then(a.cmp(b)));
            let best = score[order[0]];
            let (mut joints, mut weights) = ([0u16; 4], [0.0f32; 4]);
            for (k, &b) in order.iter().take(4).enumerate() {
                if score[b] > 0.01 * best {
                    (joints[k], weights[k]) = (b as u16, score[b]);
                }
            }
            let sum: f32 = weights.iter().sum();
            (joints, weights.map(|w| w / sum))
        })
        .unzip()
}
