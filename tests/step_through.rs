//! Stepping through the simulation: the simulation view's arrows (the correction each
//! step of a substep makes, recorded by the kernel's probe) and the viewer's single
//! step, on lavapipe with validation on.

mod common;

use fur_core::scene::{GroomParams, Mesh, Strands};
use fur_core::sim::{Motion, MotionKind, Sdf, SimParams, SimStep};
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;
use glam::{Vec3, Vec4Swizzles};

/// One frame's worth of the blob's shaken, windy, colliding hair at one substep per
/// frame: the positions before and after frame `frames` and the arrows of `step`
/// (`None`: no arrows) in it.
struct Frame {
    before: Vec<Vec3>,
    after: Vec<Vec3>,
    arrows: Vec<Vec3>,
}

fn frame(step: Option<SimStep>, frames: usize, strands: &Strands, sdf: &Sdf) -> Frame {
    let device = common::device();
    let params = SimParams {
        substeps: 1,
        wind: Vec3::new(6.0, 0.0, 2.0),
        global_stiffness: 0.05,
        collision: true,
        ..Default::default()
    };
    let motion = Motion {
        kind: MotionKind::Shake,
        amplitude: 0.3,
        rate: 2.0,
    };
    let head = |t: f64| motion.head(t);
    let mut textures = StrandTextures::new(&device, strands, head(0.0).as_mat4()).unwrap();
    let mut gpu = GpuSim::with_body(&device, &textures, params, 1, Some(sdf)).unwrap();
    gpu.set_probe(Some(step), &mut textures).unwrap();
    gpu.run_frames(&mut textures, frames - 1, head).unwrap();
    let before = textures.read_positions(textures.current).unwrap();
    gpu.run_frames(&mut textures, 1, head).unwrap();
    let after = textures.read_positions(textures.current).unwrap();
    let arrows = if step.is_some() {
        let probe = textures.read_probe().unwrap();
        probe.iter().map(|a| a.xyz()).collect()
    } else {
        Vec::new()
    };
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
    Frame {
        before,
        after,
        arrows,
    }
}

/// The arrows of the six steps of a substep are the pieces of its motion: run the same
/// frame six times (the simulation is deterministic and the probe changes no position),
/// each time recording another step's corrections, and they add up, vertex by vertex,
/// to how far the frame moved it. A step recorded twice, or one left out, or a
/// correction taken at the wrong moment, breaks the sum. Every step the scene runs
/// moves something.
#[test]
fn the_steps_arrows_add_up_to_the_frames_motion() {
    let mesh = Mesh::blob();
    let groom = GroomParams {
        segments: 6,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let (_, radius) = mesh.bounds();
    let params = SimParams::default();
    let (sdf, _) = Sdf::build(
        &mesh,
        params.sdf_cells(2.0 * radius + 2.0 * hair, hair, false),
        hair,
    )
    .unwrap();
    let frames = 6;
    let plain = frame(None, frames, &strands, &sdf);
    let mut sum = vec![Vec3::ZERO; plain.after.len()];
    for step in SimStep::ALL {
        let f = frame(Some(step), frames, &strands, &sdf);
        assert_eq!(
            f.after, plain.after,
            "{step:?}: the probe changed the simulation"
        );
        let largest = f.arrows.iter().map(|a| a.length()).fold(0.0, f32::max);
        println!("{}: largest correction {largest:e}", step.key());
        assert!(largest > 0.0, "{step:?} moved nothing");
        for (s, a) in sum.iter_mut().zip(&f.arrows) {
            *s += *a;
        }
    }
    let reach = plain
        .after
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f32::max);
    let mut worst = 0.0f32;
    for (i, s) in sum.iter().enumerate() {
        let moved = plain.after[i] - plain.before[i];
        worst = worst.max((*s - moved).length());
    }
    let tolerance = 16.0 * f32::EPSILON * reach;
    println!("worst |Σ arrows − motion| = {worst:e} (tolerance {tolerance:e})");
    assert!(
        worst <= tolerance,
        "the arrows miss the motion by {worst:e}"
    );
}
