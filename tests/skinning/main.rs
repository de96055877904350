//! Fur on a skinned, animated body (the built-in critter), on lavapipe with validation
//! on: the device's skinning and per-strand simulation against the CPU reference, roots
//! on the skinned surface, a held pose at rest, and a hair count that does not change
//! as the joints bend. Parity with the CPU reference is in `parity.rs`, a held pose's
//! rest in `rest.rs`, and the depth of hair in the walking skin in `depth.rs`.

#[path = "../common/mod.rs"]
mod common;

mod depth;
mod parity;
mod rest;

use std::sync::Arc;

use fur_core::scene::{critter, GroomParams, Mesh, Rig, Strands};
use fur_core::sim::{CpuSim, SimParams};
use fur_core::skinning::{self, Playback, SkinnedBody};
use fur_gpu::sim::{GpuSim, SkinnedMotion};
use fur_gpu::strand_textures::StrandTextures;
use glam::{DMat4, Vec3, Vec4};

fn groom() -> GroomParams {
    GroomParams {
        segments: 8,
        segment_length: 0.012,
        ..Default::default()
    }
}

fn walk(rig: &Rig) -> Playback {
    Playback {
        clip: Some(rig.clip_index("walk").unwrap()),
        ..Default::default()
    }
}

/// The device simulation of `textures`' strands on the skinned `body` playing `playback`,
/// one frame in flight, colliding with `field` when given.
fn skinned_sim(
    device: &Arc<fur_gpu::gpu::Device>,
    textures: &StrandTextures,
    params: SimParams,
    field: Option<&fur_core::sim::Sdf>,
    motion: SkinnedMotion,
) -> GpuSim {
    GpuSim::build(device, textures, params, 1, field, Some(motion)).unwrap()
}

fn max_error(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f32::max)
}

/// The largest move of any vertex in each of the next `frames` frames of `gpu` (the
/// head still).
fn largest_move(gpu: &mut GpuSim, textures: &mut StrandTextures, frames: usize) -> f32 {
    let head = |_: f64| DMat4::IDENTITY;
    let mut last = textures.read_positions(textures.current).unwrap();
    let mut moved = 0.0f32;
    for _ in 0..frames {
        gpu.run_frames(textures, 1, head).unwrap();
        let now = textures.read_positions(textures.current).unwrap();
        moved = moved.max(max_error(&last, &now));
        last = now;
    }
    moved
}

/// The session's groom on the critter: hair 0.2 × its radius, combed along the bones,
/// every hair full length.
fn session_strands(mesh: &Mesh, rig: &Rig) -> (Strands, GroomParams) {
    let (mut groom, _) = fur_core::scene_file::SceneOptions::default()
        .resolve(mesh)
        .unwrap();
    groom.comb_field = Some(skinning::fur_flow(rig));
    // Every hair full length: the thickness limit leaves hairs on the ears with
    // segments (~6e-4) shorter than gravity moves a vertex in one step (2.7e-3), a
    // stiff case where f32 rounding on the two devices (fused multiply-adds on one)
    // grows into millimetres within 20 frames, with or without collision (measured).
    groom.thickness_limit = 0.0;
    (Strands::grow(mesh, &groom).unwrap(), groom)
}

/// The critter with the session's groom ([`session_strands`]), its skinned body and the
/// rest pose's distance field for `params`.
fn critter_with_field(params: &SimParams) -> (Strands, Arc<SkinnedBody>, fur_core::sim::Sdf) {
    let (mesh, rig) = critter();
    let (strands, _) = session_strands(&mesh, &rig);
    let (sdf, _) =
        fur_core::sim::Sdf::for_hair(&mesh, params, strands.hair_length(), true).unwrap();
    (strands, Arc::new(SkinnedBody::new(&mesh, rig)), sdf)
}

fn body() -> (Mesh, Arc<SkinnedBody>, Strands) {
    let (mesh, rig) = critter();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let body = Arc::new(SkinnedBody::new(&mesh, rig));
    (mesh, body, strands)
}

/// The device places every root on its skinned vertex (the CPU's skinning within 1e-5
/// of the body's size) at several times of the walk.
#[test]
fn roots_sit_on_the_device_skinned_surface() {
    let device = common::device();
    let (mesh, body, strands) = body();
    let (_, size) = mesh.bounds();
    let playback = walk(&body.rig);
    let textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = skinned_sim(
        &device,
        &textures,
        SimParams::default(),
        None,
        SkinnedMotion {
            body: body.clone(),
            playback: playback.clone(),
        },
    );
    let v = strands.vertices_per_strand as usize;
    for t in [0.0, 0.3, 0.55] {
        gpu.time = t;
        gpu.place(&textures, DMat4::IDENTITY).unwrap();
        let on_gpu = textures.read_positions(textures.current).unwrap();
        let posed = skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, t));
        let roots: Vec<Vec3> = on_gpu.iter().step_by(v).copied().collect();
        let error = max_error(&roots, &posed.positions);
        println!("t = {t}: max |gpu root − cpu skinned vertex| = {error:e}");
        assert!(error <= 1e-5 * size, "t = {t}: roots {error} off the skin");
        let rest_error = max_error(&roots, &mesh.positions);
        assert!(
            t == 0.0 || rest_error > 0.05 * size,
            "t = {t}: the body did not move ({rest_error})"
        );
    }
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}

/// The number of hairs comes from the rest pose: every frame of the walk, at a fixed
/// camera with culling off and the density LOD out of reach, tessellates the same
/// number of points and draws the same number of hairs, though the triangles stretch.
#[test]
fn hairs_per_triangle_stay_the_same_as_the_body_walks() {
    let device = common::device();
    let (mesh, rig) = critter();
    let playback = walk(&rig);
    let mut options = fur_core::scene_file::SceneOptions::default();
    options.draw.density *= 0.2;
    options.draw.cull = false;
    options.draw.lod_distance = 1e4;
    let (groom, mut settings) = options.resolve(&mesh).unwrap();
    settings.count_hairs = true;
    let mut session = fur_gpu::session::FurSession::new(
        &device,
        fur_gpu::session::SessionSetup {
            mesh: mesh.clone(),
            rig: Some((rig, playback)),
            groom: &groom,
            sim: SimParams::default(),
            motion: fur_core::sim::Motion::still(),
            settings,
            extent: ash::vk::Extent2D {
                width: 96,
                height: 64,
            },
            frames_in_flight: 1,
        },
    )
    .unwrap();
    let mut seen = Vec::new();
    let mut stretch = 0.0f32;
    for frame in 0..24 {
        let (_, timings) = session.step_and_render().unwrap();
        let points = timings
            .render
            .statistics
            .expect("pipeline statistics (lavapipe has them)")
            .tess_eval_invocations;
        let hairs = timings.render.counts.expect("hair counts").hairs;
        seen.push((points, hairs));
        if frame % 6 == 5 {
            let skinned = session.sim.skinned.as_ref().unwrap();
            let posed = skinning::cpu::pose(
                &skinned.body,
                &skinned
                    .playback
                    .joint_matrices(&skinned.body.rig, session.sim.time),
            );
            // How much the triangles stretch: the largest change of an edge length.
            for t in mesh.indices.chunks_exact(3) {
                let (a, b) = (t[0] as usize, t[1] as usize);
                let rest = mesh.positions[a].distance(mesh.positions[b]);
                let now = posed.positions[a].distance(posed.positions[b]);
                stretch = stretch.max((now / rest - 1.0).abs());
            }
        }
    }
    println!("points and hairs per frame: {seen:?}; edges stretch up to {stretch:.3}");
    assert!(seen.iter().all(|s| *s == seen[0]), "{seen:?}");
    assert!(seen[0].1 > 1000, "too few hairs to tell: {:?}", seen[0]);
    assert!(
        stretch > 0.05,
        "the walk hardly deforms the body ({stretch})"
    );
    drop(session);
    common::assert_clean(&device);
}
