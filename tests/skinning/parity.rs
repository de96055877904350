//! The device's simulation on the walking critter against the CPU reference, without
//! and with collision (and the skin's blend).

use super::*;
use common::rounding::{self, Body};
use fur_core::sim::V3;

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
        SkinnedMotion {
            body: body.clone(),
            playback: playback.clone(),
        },
    );
    let poses_at = |t: f64| skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, t));
    let mut cpu = CpuSim::<f32>::new(&strands, params, DMat4::IDENTITY);
    cpu.place(DMat4::IDENTITY, Some(&poses_at(0.0).roots));
    let no_contact = |_: &CpuSim<f32>, _: usize| false;
    let parity = frame_by_frame(
        &mut gpu,
        &mut textures,
        &mut cpu,
        40,
        &poses_at,
        Body::Skinned { blend: false },
        no_contact,
    );
    println!("{parity}");
    parity.assert_held();
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
/// budget, the contacts decided apart, and what broke parity (the first of each frame).
struct Parity {
    error: f32,
    budget: f32,
    flips: usize,
    broken: Vec<String>,
}

impl Parity {
    fn assert_held(&self) {
        assert!(self.broken.is_empty(), "{}", self.broken.join("\n"));
    }
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
    gpu: &mut GpuSim,
    textures: &mut StrandTextures,
    cpu: &mut CpuSim<f32>,
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
        broken: Vec::new(),
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
        let over_before = parity.broken.len();
        for (i, ((g, c), p)) in on_gpu.iter().zip(&cpu.current).zip(&before).enumerate() {
            let off = (*g - c.to_vec3()).length();
            if off <= budget {
                parity.error = parity.error.max(off);
                continue;
            }
            over += 1;
            let step = (*g - *p).length();
            if !(contact(cpu, i) && off <= budget + step) && over_before == parity.broken.len() {
                parity.broken.push(format!(
                    "frame {frame}: vertex {i} is {off:e} off (budget {budget:e}, its step {step:e}, \
                     in contact: {})",
                    contact(cpu, i)
                ));
            }
        }
        if over > 0 {
            let contacts = (0..on_gpu.len())
                .filter(|&i| i % v != 0 && contact(cpu, i))
                .count();
            if 100 * over > contacts {
                parity.broken.push(format!(
                    "frame {frame}: {over} vertices beyond the budget {budget:e}, of {contacts} in contact"
                ));
            }
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
    clip_parity(Clip::Walk, true, 40).assert_held();
}

/// The same without the skin's blend (`--skin-blend off`): the root poses and capsules
/// alone.
#[test]
fn gpu_matches_cpu_on_a_walking_body_without_the_skins_blend() {
    clip_parity(Clip::Walk, false, 20).assert_held();
}

/// The same where only child bones move: a clip made here turns each front paw on its
/// still leg and the head on its still neck. A capsule counts as moved by as much as its
/// child bone's far end moved (the skin at its end bends with the child), which the walk
/// never exercises alone (it turns no paw on a still leg). The kernel without that rule
/// (`FUR_TEST_NO_CHILD_MOTION`) must fail parity with the CPU reference, which keeps it
/// (its own unit test, `a_capsule_counts_as_far_as_its_child_bone_moved`, binds it on the
/// CPU): both runs are here, so the test fails if either side loses the rule.
#[test]
fn gpu_matches_cpu_where_only_child_bones_move() {
    let parity = clip_parity(Clip::ChildrenTurn, true, CHILDREN_FRAMES);
    parity.assert_held();
    let without =
        fur_gpu::gpu::shader::with_test_defines(&[("FUR_TEST_NO_CHILD_MOTION", "1")], || {
            clip_parity(Clip::ChildrenTurn, true, CHILDREN_FRAMES)
        });
    println!("without the child's motion: {without}");
    assert!(
        !without.broken.is_empty(),
        "the kernel without the child bone's motion still matches the CPU reference"
    );
}

/// Frames of [`gpu_matches_cpu_where_only_child_bones_move`].
const CHILDREN_FRAMES: usize = 30;

/// What the critter plays in [`clip_parity`].
#[derive(Clone, Copy)]
enum Clip {
    Walk,
    /// Made here: the front paws and the head turn by a radian over a quarter of a
    /// second on their still parents, then hold.
    ChildrenTurn,
}

impl Clip {
    /// The clip's index in `rig`, added to it where it is made here.
    fn index_in(self, rig: &mut Rig) -> usize {
        use fur_core::scene::{Channel, Interpolation, Property};
        match self {
            Clip::Walk => walk(rig).clip.unwrap(),
            Clip::ChildrenTurn => {
                let turn = |name: &str, axis: Vec3| Channel {
                    node: rig.nodes.iter().position(|n| n.name == name).unwrap(),
                    property: Property::Rotation,
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 0.25, 10.0],
                    values: [0.0, 1.0, 1.0]
                        .map(|a| Vec4::from(glam::Quat::from_axis_angle(axis, a)))
                        .to_vec(),
                };
                let channels = vec![
                    turn("front_leg.L.paw", Vec3::X),
                    turn("front_leg.R.paw", Vec3::X),
                    turn("head", Vec3::Y),
                ];
                rig.clips.push(fur_core::scene::Clip {
                    name: "children turn".into(),
                    channels,
                });
                rig.clips.len() - 1
            }
        }
    }
}

/// GPU/CPU parity on the critter playing `clip` with collision, frame by frame over
/// `frames`.
fn clip_parity(clip: Clip, skin_blend: bool, frames: usize) -> Parity {
    let device = common::device();
    let params = SimParams {
        wind: Vec3::new(2.0, 0.0, 1.0),
        skin_blend: Some(skin_blend),
        ..Default::default()
    };
    let (strands, body, sdf) = critter_with_field(&params);
    let mut rig = body.rig.clone();
    let playback = Playback {
        clip: Some(clip.index_in(&mut rig)),
        ..Default::default()
    };
    let body = Arc::new(SkinnedBody {
        rig,
        ..(*body).clone()
    });
    let sdf = Arc::new(sdf);
    let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = skinned_sim(
        &device,
        &textures,
        params.clone(),
        Some(&sdf),
        SkinnedMotion {
            body: body.clone(),
            playback: playback.clone(),
        },
    );
    assert_eq!(
        gpu.active_steps()
            .contains(&fur_core::sim::SimStep::Collision),
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
    // The pose of the frame asked about, skinned once a frame, not once a vertex.
    let posed_now = std::cell::RefCell::new((f64::NAN, None));
    let contact = |sim: &CpuSim<f32>, i: usize| {
        let mut cached = posed_now.borrow_mut();
        if cached.0 != sim.time {
            *cached = (sim.time, Some(poses_at(sim.time)));
        }
        let posed = cached.1.as_ref().unwrap();
        let p = sim.current[i].to_vec3();
        let pose = &posed.roots[i / v];
        let rest = pose.rotation.transpose() * (p - pose.root) + strands.positions[i / v * v];
        near_capsule(p, posed)
            || sim
                .sdf
                .as_ref()
                .and_then(|f| f.sample(V3::<f32>::from_vec3(rest)))
                .is_some_and(|(d, _)| d < 2.0 * margin)
    };
    let parity = frame_by_frame(
        &mut gpu,
        &mut textures,
        &mut cpu,
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
    parity
}
