//! Fur on a skinned, animated body (the built-in critter), on lavapipe with validation
//! on: the device's skinning and per-strand simulation against the CPU reference, roots
//! on the skinned surface, a held pose at rest, and a hair count that does not change
//! as the joints bend.

mod common;

use std::sync::Arc;

use fur::scene::{critter, GroomParams, Mesh, Rig, Strands};
use fur::sim::{CpuSim, GpuSim, SimParams};
use fur::skinning::{self, Playback, SkinnedBody};
use fur::strand_textures::StrandTextures;
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
    device: &Arc<fur::gpu::Device>,
    textures: &StrandTextures,
    params: SimParams,
    field: Option<&fur::sim::Sdf>,
    (body, playback): (Arc<SkinnedBody>, Playback),
) -> GpuSim {
    GpuSim::build(device, textures, params, 1, field, Some((body, playback))).unwrap()
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
        (body.clone(), playback.clone()),
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

/// The animated simulation on the device matches the CPU reference within 1e-4 of the
/// hair length over 40 frames of the walk, and the hair really moved.
#[test]
fn gpu_matches_cpu_on_a_walking_body() {
    let device = common::device();
    let (mesh, body, strands) = body();
    let playback = walk(&body.rig);
    let params = SimParams {
        wind: Vec3::new(2.0, 0.0, 1.0),
        collision: false,
        ..Default::default()
    };
    let head = |_: f64| DMat4::IDENTITY;
    let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = skinned_sim(
        &device,
        &textures,
        params.clone(),
        None,
        (body.clone(), playback.clone()),
    );
    let poses_at = |t: f64| skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, t));
    let mut cpu = CpuSim::<f32>::new(&strands, params, DMat4::IDENTITY);
    cpu.place(DMat4::IDENTITY, Some(&poses_at(0.0).roots));
    let tolerance = 1e-4 * strands.hair_length();
    let mut done = 0;
    for target in [1, 10, 40] {
        gpu.run_frames(&mut textures, target - done, head).unwrap();
        for _ in done..target {
            cpu.step_frame_posed(head, poses_at);
        }
        done = target;
        let on_gpu = textures.read_positions(textures.current).unwrap();
        let on_cpu: Vec<Vec3> = cpu.current.iter().map(|v| v.to_vec3()).collect();
        let error = max_error(&on_gpu, &on_cpu);
        println!("after {target} frames: max |gpu − cpu| = {error:e} (tolerance {tolerance:e})");
        assert!(error <= tolerance, "after {target} frames: {error}");
    }
    let moved = max_error(
        &textures.read_positions(textures.current).unwrap(),
        &strands.positions,
    );
    let (_, size) = mesh.bounds();
    assert!(
        moved > 0.05 * size,
        "the walk did not move the hair ({moved})"
    );
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}

/// A clip that holds `locals` for half a second with every kind of key: rotations
/// spherically interpolated (LINEAR), translations as a flat CUBICSPLINE, scales STEP.
fn holding(name: &str, locals: &[fur::scene::Transform]) -> fur::scene::Clip {
    use fur::scene::{Channel, Clip, Interpolation, Property};
    let times = vec![0.0, 0.25, 0.5];
    let mut channels = Vec::new();
    for (node, l) in locals.iter().enumerate() {
        let t = l.translation.extend(0.0);
        let flat = [Vec4::ZERO, t, Vec4::ZERO];
        channels.push(Channel {
            node,
            property: Property::Translation,
            interpolation: Interpolation::CubicSpline,
            times: times.clone(),
            values: flat.repeat(3),
        });
        channels.push(Channel {
            node,
            property: Property::Rotation,
            interpolation: Interpolation::Linear,
            times: times.clone(),
            values: vec![Vec4::from(l.rotation); 3],
        });
        channels.push(Channel {
            node,
            property: Property::Scale,
            interpolation: Interpolation::Step,
            times: times.clone(),
            values: vec![l.scale.extend(0.0); 3],
        });
    }
    Clip {
        name: name.into(),
        channels,
    }
}

/// Holds `locals` on the critter with a looping clip, settles the hair under gravity for
/// 90 frames, then returns the most any vertex moved in one of the next 3 frames, and how
/// far gravity moved the hair while settling.
fn held_pose_motion(
    device: &Arc<fur::gpu::Device>,
    (mesh, rig, strands): (&Mesh, &Rig, &Strands),
    locals: &[fur::scene::Transform],
) -> (f32, f32) {
    let mut rig = rig.clone();
    rig.clips.push(holding("held", locals));
    let playback = Playback {
        clip: Some(rig.clips.len() - 1),
        ..Default::default()
    };
    let body = Arc::new(SkinnedBody::new(mesh, rig));
    let mut textures = StrandTextures::new(device, strands, glam::Mat4::IDENTITY).unwrap();
    let params = SimParams {
        collision: false,
        ..Default::default()
    };
    let mut gpu = skinned_sim(device, &textures, params, None, (body, playback));
    let head = |_: f64| DMat4::IDENTITY;
    let start = textures.read_positions(textures.current).unwrap();
    gpu.run_frames(&mut textures, 90, head).unwrap();
    let sag = max_error(&start, &textures.read_positions(textures.current).unwrap());
    (largest_move(&mut gpu, &mut textures, 3), sag)
}

/// A clip that holds a pose, looping, leaves the hair at rest: after settling under
/// gravity no vertex moves more than 1e-6 of the hair length a frame. Two poses: the
/// bind pose, and the walk's bent pose at 0.4 s (root rotations far from the identity).
/// The same check rejects the simulation without sleep, whose rounding leaves the hair
/// dithering by an ulp or two a frame.
#[test]
fn a_held_pose_leaves_the_hair_at_rest() {
    let device = common::device();
    let (mesh, rig) = critter();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let walking = rig.clip_index("walk").unwrap();
    let bind = rig.pose(None, 0.0, false);
    let bent = rig.pose(Some(&rig.clips[walking]), 0.4, false);
    // 9.6e-8 here: below one ulp at |x| ≈ 1 (1.2e-7), so a flicker of one ulp in a root
    // pose, in the ride or in the constraints fails it, as does hair still moving.
    let limit = 1e-6 * strands.hair_length();
    for (name, locals) in [("bind", &bind), ("bent", &bent)] {
        let (moved, sag) = held_pose_motion(&device, (&mesh, &rig, &strands), locals);
        println!("{name} pose: moved {moved:e} a frame after settling (limit {limit:e}); gravity moved it {sag:e}");
        assert!(
            moved <= limit,
            "{name} pose: a frame after settling moved the hair by {moved} (limit {limit})"
        );
        // Gravity bent the hair on its way to rest: the stillness is not a strand that
        // never woke.
        assert!(
            sag >= 0.01 * strands.hair_length(),
            "{name} pose: gravity moved the hair by only {sag}"
        );
    }
    let (moved, _) = fur::gpu::shader::with_test_defines(&[("FUR_TEST_NO_SLEEP", "1")], || {
        held_pose_motion(&device, (&mesh, &rig, &strands), &bent)
    });
    println!("without sleep: moved {moved:e} a frame after settling");
    assert!(
        moved > limit,
        "the check passed the simulation without sleep ({moved})"
    );
    common::assert_clean(&device);
}

/// The session's groom on the critter: hair 0.2 × its radius, combed along the bones,
/// every hair full length.
fn session_strands(mesh: &Mesh, rig: &Rig) -> (Strands, GroomParams) {
    let (mut groom, _) = fur::session::SceneOptions::default().resolve(mesh).unwrap();
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
fn critter_with_field(params: &SimParams) -> (Strands, Arc<SkinnedBody>, fur::sim::Sdf) {
    let (mesh, rig) = critter();
    let (strands, _) = session_strands(&mesh, &rig);
    let (sdf, _) = fur::sim::Sdf::for_hair(&mesh, params, strands.hair_length(), true).unwrap();
    (strands, Arc::new(SkinnedBody::new(&mesh, rig)), sdf)
}

/// GPU/CPU parity on the walking critter with collision on: the rest field carried by
/// each strand's root pose and the bones' capsules, within 1e-4 of the hair length.
#[test]
fn gpu_matches_cpu_on_a_walking_body_with_collision() {
    walking_parity(false, &[1, 20, 40]);
}

/// The same with the rest field carried back through the skin's blend of bones
/// (`--skin-blend on`): the blend grid, the bones' motions of each substep and the
/// blended matrix's inverse agree on both sides.
#[test]
fn gpu_matches_cpu_on_a_walking_body_with_the_skins_blend() {
    walking_parity(true, &[1, 20]);
}

/// GPU/CPU parity on the walking critter with collision, after each of `targets` frames.
fn walking_parity(skin_blend: bool, targets: &[usize]) {
    let device = common::device();
    let params = SimParams {
        wind: Vec3::new(2.0, 0.0, 1.0),
        skin_blend,
        ..Default::default()
    };
    let (strands, body, sdf) = critter_with_field(&params);
    let playback = walk(&body.rig);
    let sdf = Arc::new(sdf);
    let head = |_: f64| DMat4::IDENTITY;
    let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = skinned_sim(
        &device,
        &textures,
        params.clone(),
        Some(&sdf),
        (body.clone(), playback.clone()),
    );
    assert_eq!(
        gpu.active_steps().contains(&fur::sim::SimStep::Collision),
        params.collision
    );
    let poses_at = |t: f64| skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, t));
    let blend = if skin_blend {
        skinning::blend::for_body(&body, &sdf, strands.hair_length()).unwrap()
    } else {
        Vec::new()
    };
    let mut cpu = CpuSim::<f32>::new(&strands, params, DMat4::IDENTITY)
        .with_sdf(sdf)
        .with_blend(blend);
    cpu.place(DMat4::IDENTITY, Some(&poses_at(0.0).roots));
    let tolerance = 1e-4 * strands.hair_length();
    let v = strands.vertices_per_strand as usize;
    let mut done = 0;
    for &target in targets {
        gpu.run_frames(&mut textures, target - done, head).unwrap();
        for _ in done..target {
            cpu.step_frame_posed(head, poses_at);
        }
        done = target;
        let on_gpu = textures.read_positions(textures.current).unwrap();
        let on_cpu: Vec<Vec3> = cpu.current.iter().map(|v| v.to_vec3()).collect();
        let strand_error: Vec<f32> = on_gpu
            .chunks(v)
            .zip(on_cpu.chunks(v))
            .map(|(g, c)| max_error(g, c))
            .collect();
        let within = strand_error.iter().filter(|&&e| e <= tolerance).count();
        let worst = strand_error.iter().copied().fold(0.0, f32::max);
        println!(
            "after {target} frames with collision: {within} of {} strands within {tolerance:e}, worst {worst:e}",
            strand_error.len()
        );
        assert_eq!(
            within,
            strand_error.len(),
            "after {target} frames the GPU is {worst} away from the CPU"
        );
    }
    // Collisions happened: many vertices sit within twice the margin of a capsule.
    let posed = poses_at(cpu.time);
    let margin = cpu.params.collision_margin * strands.hair_length();
    let touching = cpu
        .current
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            i % v != 0
                && posed.capsules.iter().any(|c| {
                    let (d, _) = skinning::capsules::segment_distance(
                        p.to_vec3(),
                        c[0].truncate(),
                        c[1].truncate(),
                    );
                    d - c[0].w < 2.0 * margin
                })
        })
        .count();
    println!("{touching} vertices within two margins of a capsule");
    assert!(touching > 100, "only {touching} vertices near a capsule");
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
    let mut options = fur::session::SceneOptions {
        density_scale: 0.2,
        ..Default::default()
    };
    options.draw.cull = false;
    options.draw.lod_distance = 1e4;
    let (groom, mut settings) = options.resolve(&mesh).unwrap();
    settings.count_hairs = true;
    let mut session = fur::session::FurSession::with_rig(
        &device,
        (mesh.clone(), Some((rig, playback))),
        &groom,
        SimParams::default(),
        fur::sim::Motion::still(),
        settings,
        ash::vk::Extent2D {
            width: 96,
            height: 64,
        },
        1,
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

/// Depth of strand vertices inside the posed critter over the second half of a walk
/// cycle (exact point-to-mesh distances), fractions of the longest hair: (mean, max).
fn walk_depths((collision, skin_blend): (bool, bool)) -> (f64, f64) {
    let device = common::device();
    let (mesh, rig) = critter();
    let (mut groom, _) = fur::session::SceneOptions::default()
        .resolve(&mesh)
        .unwrap();
    groom.comb_field = Some(skinning::fur_flow(&rig));
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let body = Arc::new(SkinnedBody::new(&mesh, rig));
    let playback = walk(&body.rig);
    let params = SimParams {
        collision,
        skin_blend,
        ..fur::scene_file::Scene::default_sim()
    };
    let (field, _) = fur::sim::Sdf::for_hair(&mesh, &params, strands.hair_length(), true).unwrap();
    let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = skinned_sim(
        &device,
        &textures,
        params,
        Some(&field),
        (body.clone(), playback.clone()),
    );
    let v = strands.vertices_per_strand as usize;
    let head = |_: f64| DMat4::IDENTITY;
    gpu.run_frames(&mut textures, 30, head).unwrap();
    let (mut sum, mut count, mut max) = (0.0f64, 0usize, 0.0f64);
    for _ in 0..3 {
        gpu.run_frames(&mut textures, 10, head).unwrap();
        let posed = skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, gpu.time));
        let surface = Mesh {
            positions: posed.positions,
            ..mesh.clone()
        };
        let points: Vec<Vec3> = textures
            .read_positions(textures.current)
            .unwrap()
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % v != 0)
            .map(|(_, p)| p)
            .collect();
        for d in fur::sim::sdf::exact_distances(&surface, &points) {
            let depth = f64::from((-d).max(0.0));
            sum += depth;
            count += 1;
            max = max.max(depth);
        }
    }
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
    let hair = f64::from(strands.hair_length());
    (sum / count as f64 / hair, max / hair)
}

/// Collision keeps the walking critter's hair out of its skin: measured against the
/// same walk without collision. The target (max ≤ 1 % of the hair length) is
/// not met everywhere yet (docs/benchmark.md: a paw tip and the armpit's first
/// vertices). Measured here (3 frames): collision divides the mean depth by 120 and
/// the max by 24 (max 1.1 %); the bounds ask for 5 and 3.2, and the max for at most
/// 2.5 %, so a collision doing half its work, or the previous release's (3.0 %), fail.
#[test]
fn collision_keeps_the_walking_hair_out_of_the_skin() {
    let (mean_on, max_on) = walk_depths((true, false));
    let (mean_off, max_off) = walk_depths((false, false));
    println!(
        "depth inside the skin, fractions of the hair length: with collision mean {mean_on:.2e} \
         max {max_on:.3}; without mean {mean_off:.2e} max {max_off:.3}"
    );
    assert!(
        mean_off > 1e-4,
        "the walk without collision hardly enters the skin"
    );
    assert!(max_on <= 0.025, "max depth {max_on} of the hair length");
    assert!(
        mean_on * 5.0 < mean_off,
        "mean depth {mean_on} against {mean_off}"
    );
    assert!(
        max_on * 3.2 < max_off,
        "max depth {max_on} against {max_off}"
    );
}

/// With the rest field carried back through the skin's blend of bones (`--skin-blend
/// on`), hair stays farther out of the walking critter than by its root poses alone:
/// the tips of hair rooted where a paw meets its leg, which the root pose carries with
/// the blend of the two bones while the paw's skin turns with the paw, are no longer
/// the deepest (measured over these frames: max 1.14 % by the root poses, 0.90 % by the
/// skin's blend; mean 3.40e-6 and 2.75e-6).
#[test]
fn the_skins_blend_keeps_hair_out_where_the_skin_bends() {
    // Below the root poses' own max over these frames (0.0114).
    const BLEND_MAX: f64 = 0.011;
    let (mean_root, max_root) = walk_depths((true, false));
    let (mean_blend, max_blend) = walk_depths((true, true));
    println!(
        "depth inside the skin, fractions of the hair length: root poses mean \
         {mean_root:.2e} max {max_root:.4}; the skin's blend mean {mean_blend:.2e} max {max_blend:.4}"
    );
    assert!(
        max_blend <= BLEND_MAX,
        "max depth {max_blend} of the hair length"
    );
    assert!(
        max_blend < max_root,
        "max depth {max_blend} against {max_root}"
    );
    assert!(
        mean_blend < mean_root,
        "mean depth {mean_blend} against {mean_root}"
    );
}

/// A still pose under gravity with collision on (the product's defaults, the session's
/// groom): once the hair has settled onto the body, no vertex moves more than 1e-6 of the
/// hair length a frame. Three things make it so (each measured on the CPU twin):
/// - the carried field is sampled trilinearly: the nearest-point sample jumps in the
///   crease between belly and thighs, and ~80 strands hung there in period-2 cycles of
///   0.15 hair lengths a frame;
/// - a bone's capsule counts only as far as it moved relative to a strand's root: at the
///   pose the field was built in, the thigh's capsule and the field's thigh were two
///   shapes of one thigh, and ~14 strands squeezed between them kept creeping by up to
///   1e-2 a frame;
/// - where the field and a capsule both push a vertex, the contact's normal is the
///   whole push's direction (the first one's left the velocity into the other: at held
///   walk poses 3 to 13 strands crept by up to 9e-3 a frame);
/// - slow motion sleeps (1e-3 of a strand's length a frame, with its root still; without
///   it ~85 strands still move by up to 4e-4 a frame at the bind pose).
#[test]
fn a_still_pose_under_gravity_with_collision_comes_to_rest() {
    for skin_blend in [false, true] {
        still_pose_comes_to_rest(SimParams {
            skin_blend,
            ..Default::default()
        });
    }
}

fn still_pose_comes_to_rest(params: SimParams) {
    let device = common::device();
    let (strands, body, sdf) = critter_with_field(&params);
    // The bind pose, and the walk's bent pose at 0.4 s held (legs apart, where the
    // thighs' capsules have moved relative to the belly's roots).
    let held_walk = Playback {
        speed: 0.0,
        start: 0.4,
        ..walk(&body.rig)
    };
    for (what, playback) in [
        ("bind pose", Playback::default()),
        ("walk at 0.4 s", held_walk),
    ] {
        let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
        let mut gpu = skinned_sim(
            &device,
            &textures,
            params.clone(),
            Some(&sdf),
            (body.clone(), playback),
        );
        gpu.run_frames(&mut textures, 300, |_| DMat4::IDENTITY)
            .unwrap();
        let limit = 1e-6 * strands.hair_length();
        let worst = largest_move(&mut gpu, &mut textures, 5);
        println!(
            "{what} (skin's blend {}): largest move a frame after settling: {worst:e} (limit {limit:e})",
            params.skin_blend
        );
        assert!(
            worst <= limit,
            "{what}: the still pose jitters by {worst} a frame (limit {limit})"
        );
    }
    common::assert_clean(&device);
}

/// The built-in walk never puts one part of the skin inside another (a paw through the
/// other paw on its side): no hair rooted there could be outside both. Points 1 mm under
/// the skin, at 120 poses over the cycle, all read as inside the posed body; where two
/// parts overlap, the ray-cast sign counts two surfaces and reads them as outside.
/// Before the front legs led their diagonal pair by 0.4 rad, 5 to 25 such points showed
/// at 10 % of the cycle (the paws meeting under the body).
#[test]
fn the_walk_keeps_the_skin_out_of_itself() {
    let (mesh, rig) = critter();
    let body = SkinnedBody::new(&mesh, rig);
    let playback = walk(&body.rig);
    let mut worst = (0usize, 0.0f64);
    for k in 0..120 {
        let t = f64::from(k) / 120.0;
        let posed = skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, t));
        let under: Vec<Vec3> = posed
            .positions
            .iter()
            .zip(&posed.normals)
            .map(|(p, n)| *p - n.normalize() * 1e-3)
            .collect();
        let surface = Mesh {
            positions: posed.positions,
            ..mesh.clone()
        };
        let outside = fur::sim::sdf::exact_distances(&surface, &under)
            .iter()
            .filter(|&&d| d > 0.0)
            .count();
        if outside > worst.0 {
            worst = (outside, t);
        }
    }
    assert_eq!(
        worst.0, 0,
        "{} skin points inside another part of the body at t = {}",
        worst.0, worst.1
    );
}
