//! The device's simulation on the walking critter against the CPU reference, without
//! and with collision (and the skin's blend).

use super::*;

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

/// GPU/CPU parity on the walking critter with collision on, as by default: the rest
/// field carried by each strand's root pose, the bones' capsules, and for the hair's
/// outer eighth the skin's blend of bones (the blend grid, the bones' motions of each
/// substep and the blended matrix's inverse agree on both sides), within 1e-4 of the
/// hair length.
#[test]
fn gpu_matches_cpu_on_a_walking_body_with_collision() {
    walking_parity(true, &[1, 20, 40]);
}

/// The same without the skin's blend (`--skin-blend off`): the root poses and capsules
/// alone.
#[test]
fn gpu_matches_cpu_on_a_walking_body_without_the_skins_blend() {
    walking_parity(false, &[1, 20]);
}

/// GPU/CPU parity on the walking critter with collision, after each of `targets` frames.
fn walking_parity(skin_blend: bool, targets: &[usize]) {
    let device = common::device();
    let params = SimParams {
        wind: Vec3::new(2.0, 0.0, 1.0),
        skin_blend: Some(skin_blend),
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
