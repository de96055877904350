//! The device's simulation on the walking critter against the CPU reference, without
//! and with collision (and the skin's blend).

use super::*;
use common::rounding::{self, Body};
use fur::sim::V3;

/// The animated simulation on the device matches the CPU reference over 40 frames of the
/// walk, frame by frame from the same state, within each frame's rounding budget
/// (tests/common/rounding.rs), and the hair really moved.
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
    let no_contact = |_: &CpuSim<f32>, _: usize| false;
    let parity = frame_by_frame(
        (&mut gpu, &mut textures, &mut cpu),
        40,
        &poses_at,
        Body::Skinned { blend: false },
        no_contact,
    );
    println!("{parity}");
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

/// What [`frame_by_frame`] saw: the largest difference within the budget, the largest
/// budget, and the contacts decided apart.
struct Parity {
    error: f32,
    budget: f32,
    flips: usize,
}

impl std::fmt::Display for Parity {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "max |gpu − cpu| over a frame {:e} (budget up to {:e}), {} contacts decided apart",
            self.error, self.budget, self.flips
        )
    }
}

/// Runs `frames` frames of the walk on the device and, from the same state each frame
/// (the CPU takes the device's positions and previous positions first), on the CPU, and
/// asserts that every vertex lands within the frame's rounding budget
/// ([`rounding::frame_budget`]: derived from the precision Vulkan allows, so it holds on
/// any conforming device, not one driver's result). The exceptions are contacts decided
/// apart: a vertex within a rounding of the collision margin is pushed on one side and
/// not on the other, which changes what the next substep carries by at most its step.
/// Each must be a contact (`contact`), within the budget plus its step, and they may be
/// at most 1 % of the vertices in contact: a collision step that differs for every
/// contact fails.
fn frame_by_frame(
    (gpu, textures, cpu): (&mut GpuSim, &mut StrandTextures, &mut CpuSim<f32>),
    frames: usize,
    poses_at: &dyn Fn(f64) -> skinning::cpu::Posed,
    body: Body,
    contact: impl Fn(&CpuSim<f32>, usize) -> bool,
) -> Parity {
    let head = |_: f64| DMat4::IDENTITY;
    let v = cpu.vertices_per_strand();
    let segment = longest_segment(&cpu.current, v);
    let mut parity = Parity {
        error: 0.0,
        budget: 0.0,
        flips: 0,
    };
    for frame in 0..frames {
        common::take_device_state(cpu, textures);
        gpu.run_frames(textures, 1, head).unwrap();
        cpu.step_frame_posed(head, poses_at);
        assert_eq!(cpu.time, gpu.time);
        let on_gpu = textures.read_positions(textures.current).unwrap();
        let before = textures.read_positions(1 - textures.current).unwrap();
        let budget = rounding::frame_budget(
            &cpu.params,
            body,
            v as u32,
            rounding::reach(&on_gpu),
            segment,
        );
        parity.budget = parity.budget.max(budget);
        let mut over = 0;
        for (i, ((g, c), p)) in on_gpu.iter().zip(&cpu.current).zip(&before).enumerate() {
            let off = (*g - c.to_vec3()).length();
            if off <= budget {
                parity.error = parity.error.max(off);
                continue;
            }
            over += 1;
            let step = (*g - *p).length();
            assert!(
                contact(cpu, i) && off <= budget + step,
                "frame {frame}: vertex {i} is {off:e} off (budget {budget:e}, its step {step:e}, \
                 in contact: {})",
                contact(cpu, i)
            );
        }
        if over > 0 {
            let contacts = (0..on_gpu.len())
                .filter(|&i| i % v != 0 && contact(cpu, i))
                .count();
            assert!(
                100 * over <= contacts,
                "frame {frame}: {over} vertices beyond the budget {budget:e}, of {contacts} in contact"
            );
        }
        parity.flips += over;
    }
    parity
}

/// The longest segment of any strand: the size of what the constraints' corrections round.
fn longest_segment(positions: &[V3<f32>], v: usize) -> f32 {
    positions
        .chunks(v)
        .flat_map(|s| s.windows(2).map(|w| (w[1] - w[0]).to_vec3().length()))
        .fold(0.0, f32::max)
}

/// GPU/CPU parity on the walking critter with collision on, as by default: the rest
/// field carried by each strand's root pose, the bones' capsules, and for the hair's
/// outer eighth the skin's blend of bones (the blend grid, the bones' motions of each
/// substep and the blended matrix's inverse agree on both sides), frame by frame within
/// each frame's rounding budget.
#[test]
fn gpu_matches_cpu_on_a_walking_body_with_collision() {
    walking_parity(true, 40);
}

/// The same without the skin's blend (`--skin-blend off`): the root poses and capsules
/// alone.
#[test]
fn gpu_matches_cpu_on_a_walking_body_without_the_skins_blend() {
    walking_parity(false, 20);
}

/// GPU/CPU parity on the walking critter with collision, frame by frame over `frames`.
fn walking_parity(skin_blend: bool, frames: usize) {
    let device = common::device();
    let params = SimParams {
        wind: Vec3::new(2.0, 0.0, 1.0),
        skin_blend: Some(skin_blend),
        ..Default::default()
    };
    let (strands, body, sdf) = critter_with_field(&params);
    let playback = walk(&body.rig);
    let sdf = Arc::new(sdf);
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
    let v = strands.vertices_per_strand as usize;
    let margin = cpu.params.collision_margin * strands.hair_length();
    // A contact: within two margins of a capsule of the pose, or of the rest field
    // carried by the strand's root pose.
    let near_capsule = |p: Vec3, posed: &skinning::cpu::Posed| {
        posed.capsules.iter().any(|c| {
            let (d, _) = skinning::capsules::segment_distance(p, c[0].truncate(), c[1].truncate());
            d - c[0].w < 2.0 * margin
        })
    };
    let contact = |sim: &CpuSim<f32>, i: usize| {
        let posed = poses_at(sim.time);
        let p = sim.current[i].to_vec3();
        let pose = &posed.roots[i / v];
        let rest = pose.rotation.transpose() * (p - pose.root) + strands.positions[i / v * v];
        near_capsule(p, &posed)
            || sim
                .sdf
                .as_ref()
                .and_then(|f| f.sample(V3::<f32>::from_vec3(rest)))
                .is_some_and(|(d, _)| d < 2.0 * margin)
    };
    let parity = frame_by_frame(
        (&mut gpu, &mut textures, &mut cpu),
        frames,
        &poses_at,
        Body::Skinned { blend: skin_blend },
        contact,
    );
    println!("{parity}");
    // Collisions happened: many vertices sit within twice the margin of a capsule.
    let posed = poses_at(cpu.time);
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
