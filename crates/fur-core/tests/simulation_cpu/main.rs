//! Properties of the Han & Harada simulation, checked on the CPU reference (which the
//! GPU tests hold the compute shaders to): rest, length and shape preservation, wind,
//! and numerical stability across a matrix of extreme parameters.

#[path = "../common/mod.rs"]
mod common;

mod collision;
mod properties;
mod reference;
mod seed;
mod skinned;
mod stability;

use std::cell::RefCell;
use std::sync::Arc;

use fur_core::scene::{GroomParams, Mesh, Strands};
use fur_core::sim::{CpuSim, Motion, MotionKind, Real, Sdf, SimParams, StepConstants, V3};
use fur_core::skinning::cpu::Posed;
use fur_core::skinning::RootPose;
use glam::{DMat4, Vec3};

fn strands(groom: &GroomParams) -> Strands {
    Strands::grow(&Mesh::icosphere(1), groom).unwrap()
}

fn still(_: f64) -> DMat4 {
    DMat4::IDENTITY
}

/// Largest |segment length / rest length − 1| over all segments.
fn stretch<T: Real>(sim: &CpuSim<T>) -> f64 {
    let v = sim.vertices_per_strand();
    let mut worst = 0.0f64;
    for s in 0..sim.rest.count() {
        for i in 1..v {
            let rest = sim.rest.lengths[s * v + i].to_f64();
            let now = (sim.current[s * v + i] - sim.current[s * v + i - 1])
                .length()
                .to_f64();
            if rest > 0.0 {
                worst = worst.max((now / rest - 1.0).abs());
            }
        }
    }
    worst
}

/// Mean distance of every vertex from its rigidly moved rest position, divided by the
/// hair length.
fn shape_error(sim: &CpuSim<f64>, head: DMat4, hair_length: f64) -> f64 {
    let rest = sim
        .rest
        .positions
        .iter()
        .map(|p| head.transform_point3(p.to_vec3().as_dvec3()));
    let total: f64 = rest
        .zip(&sim.current)
        .map(|(r, c)| (r - c.to_vec3().as_dvec3()).length())
        .sum();
    total / sim.current.len() as f64 / hair_length
}

/// Three bent strands of four segments of 0.1 each, rooted apart (written by hand, so a
/// wrong strand or vertex index lands on a different point).
fn bent_strands() -> Strands {
    let mut positions = Vec::new();
    for s in 0..3 {
        let s = s as f32;
        let mut p = Vec3::new(0.3 * s, -0.2 * s, 0.1 * s);
        positions.push(p);
        for k in 0..4 {
            p += 0.1 * Vec3::new(0.2 * k as f32, 1.0, 0.1 * s).normalize();
            positions.push(p);
        }
    }
    Strands {
        vertices_per_strand: 5,
        positions,
    }
}

/// Every strand's root pose at rest: no turn, the root where it grew.
fn held_roots(strands: &Strands) -> Vec<RootPose> {
    (0..strands.count())
        .map(|s| RootPose {
            rotation: glam::Mat3::IDENTITY,
            root: strands.strand(s)[0],
        })
        .collect()
}

/// A posed body of `roots` and `capsules`, whose bind-pose capsules are `rest`.
fn posed_from(
    roots: Vec<RootPose>,
    capsules: Vec<[glam::Vec4; 2]>,
    rest: Vec<[glam::Vec4; 2]>,
) -> Posed {
    Posed {
        positions: Vec::new(),
        normals: Vec::new(),
        roots,
        capsules,
        rest_capsules: rest,
        bones: Vec::new(),
    }
}

/// A posed body of `roots` and `capsules` that moved far (10 units along z) from the
/// bind pose, relative to every root: each capsule at its full radius.
fn posed(roots: Vec<RootPose>, capsules: Vec<[glam::Vec4; 2]>) -> Posed {
    let rest = capsules
        .iter()
        .map(|c| c.map(|p| p - glam::Vec4::new(0.0, 0.0, 10.0, 0.0)))
        .collect();
    posed_from(roots, capsules, rest)
}

/// Every strand turning about its own root at its own rate about a fixed axis while its
/// root travels at (3, 0, −1) per second: at `t` = 0 the rest pose.
fn turning(strands: &Strands, t: f64) -> Posed {
    let axis = Vec3::new(1.0, 2.0, 2.0) / 3.0;
    let roots = (0..strands.count())
        .map(|s| RootPose {
            rotation: glam::Mat3::from_axis_angle(axis, (20.0 * t) as f32 * (1 + s) as f32),
            root: strands.strand(s)[0] + Vec3::new(3.0, 0.0, -1.0) * t as f32,
        })
        .collect();
    posed(roots, Vec::new())
}

/// A simulation position as a glam vector, with no rounding.
fn dvec(p: V3<f64>) -> glam::DVec3 {
    glam::DVec3::new(p.0, p.1, p.2)
}

/// `x ↦ rotation · (x − rest root) + root`, in f64 from the pose's f32 numbers.
fn carried(pose: &RootPose, rest_root: Vec3, x: Vec3) -> glam::DVec3 {
    pose.rotation.as_dmat3() * (x.as_dvec3() - rest_root.as_dvec3()) + pose.root.as_dvec3()
}
