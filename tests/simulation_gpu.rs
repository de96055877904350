//! The compute-shader simulation against the CPU reference (the oracle), on lavapipe
//! with validation on.

mod common;

use common::rounding;

use fur_core::scene::{GroomParams, Mesh, Strands};
use fur_core::sim::{CpuSim, Motion, MotionKind, SimParams, StepConstants};
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;
use glam::{DMat4, Vec3};

fn strands(subdivisions: u32, groom: &GroomParams) -> Strands {
    Strands::grow(&Mesh::icosphere(subdivisions), groom).unwrap()
}

fn max_error(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f32::max)
}

/// How far the GPU may be from the CPU reference, both in f32 running the same steps
/// in the same order: one frame's rounding budget (tests/common/rounding.rs: each
/// operation of each step within what Vulkan allows a device to differ from the CPU's
/// one rounding, in ulps of the size it rounds), so it holds on any conforming device.
/// These tests let the two run apart for up to 100 frames: damping and the shape and
/// length constraints pull every strand back towards one state, so the differences do
/// not add up over frames (they stay within one frame's budget), and the budget is not
/// multiplied by the frame count.
fn parity_tolerance(params: &SimParams, cpu: &CpuSim<f32>, positions: &[Vec3]) -> f32 {
    let v = cpu.vertices_per_strand();
    let segment = positions
        .chunks(v)
        .flat_map(|s| s.windows(2).map(|w| (w[1] - w[0]).length()))
        .fold(0.0f32, f32::max);
    rounding::frame_budget(
        params,
        rounding::Body::Rigid,
        v as u32,
        rounding::reach(positions),
        segment,
    )
}

#[test]
fn gpu_matches_cpu_f32_after_1_10_and_100_steps() {
    let device = common::device();
    let groom = GroomParams {
        curl: 0.6,
        ..Default::default()
    };
    let strands = strands(3, &groom); // 642 strands of 17 vertices
    let params = SimParams {
        wind: Vec3::new(3.0, 0.0, 1.0),
        ..Default::default()
    };
    let motion = Motion {
        kind: MotionKind::Shake,
        amplitude: 0.2,
        rate: 2.0,
    };
    let head = |t: f64| motion.head(t);
    let mut textures = StrandTextures::new(&device, &strands, head(0.0).as_mat4()).unwrap();
    let mut gpu = GpuSim::new(&device, &textures, params.clone()).unwrap();
    let mut cpu = CpuSim::<f32>::new(&strands, params, head(0.0));
    let mut done = 0;
    for target in [1, 10, 100] {
        gpu.run_frames(&mut textures, target - done, head).unwrap();
        for _ in done..target {
            cpu.step_frame(head);
        }
        done = target;
        let on_gpu = textures.read_positions(textures.current).unwrap();
        let on_cpu: Vec<Vec3> = cpu.current.iter().map(|v| v.to_vec3()).collect();
        let error = max_error(&on_gpu, &on_cpu);
        let tolerance = parity_tolerance(&cpu.params, &cpu, &on_cpu);
        println!("after {target} steps: max |gpu - cpu| = {error:e} (tolerance {tolerance:e})");
        assert!(
            error <= tolerance,
            "after {target} steps the GPU is {error} away from the CPU"
        );
        // And the hair really moved, so the comparison means something.
        let rest: Vec<Vec3> = strands
            .positions
            .iter()
            .map(|p| head(cpu.time).as_mat4().transform_point3(*p))
            .collect();
        assert!(max_error(&on_gpu, &rest) > 10.0 * tolerance);
    }
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}

/// Several substeps per dispatch, frames batched into one submission, and kernels with
/// steps compiled out: positions *and* previous positions (the velocity) match the CPU.
#[test]
fn gpu_matches_cpu_with_substeps_and_steps_compiled_out() {
    let device = common::device();
    let groom = GroomParams {
        curl: 0.4,
        segments: 11,
        ..Default::default()
    };
    let strands = strands(2, &groom);
    let motion = Motion {
        kind: MotionKind::Nod,
        amplitude: 20.0,
        rate: 1.5,
    };
    let head = |t: f64| motion.head(t);
    let cases = [
        SimParams {
            substeps: 4,
            wind: Vec3::new(0.0, 1.0, 4.0),
            ..Default::default()
        },
        SimParams {
            substeps: 2,
            global_stiffness: 0.0,
            length_iterations: 0,
            ..Default::default()
        },
        SimParams {
            local_stiffness: 0.0,
            damping: 0.0,
            ..Default::default()
        },
    ];
    for params in cases {
        let mut textures = StrandTextures::new(&device, &strands, head(0.0).as_mat4()).unwrap();
        let mut gpu = GpuSim::new(&device, &textures, params.clone()).unwrap();
        let mut cpu = CpuSim::<f32>::new(&strands, params.clone(), head(0.0));
        gpu.run_frames(&mut textures, 30, head).unwrap();
        for _ in 0..30 {
            cpu.step_frame(head);
        }
        let steps = gpu.active_steps();
        for (image, on_cpu, what) in [
            (textures.current, &cpu.current, "positions"),
            (1 - textures.current, &cpu.previous, "previous positions"),
        ] {
            let on_gpu = textures.read_positions(image).unwrap();
            let on_cpu: Vec<Vec3> = on_cpu.iter().map(|v| v.to_vec3()).collect();
            let error = max_error(&on_gpu, &on_cpu);
            let tolerance = parity_tolerance(&cpu.params, &cpu, &on_cpu);
            println!(
                "{steps:?}, {} substeps: {what} {error:e} (tolerance {tolerance:e})",
                params.substeps
            );
            assert!(
                error <= tolerance,
                "{what} differ by {error} with {steps:?} and {} substeps",
                params.substeps
            );
        }
    }
    common::assert_clean(&device);
}

#[test]
fn gpu_at_rest_stays_exactly_put() {
    let device = common::device();
    let strands = strands(2, &GroomParams::default());
    let params = SimParams {
        local_iterations: 1,
        ..SimParams::at_rest()
    };
    let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = GpuSim::new(&device, &textures, params).unwrap();
    let start = textures.read_positions(textures.current).unwrap();
    let mut previous = start.clone();
    for i in 0..12 {
        gpu.run_frames(&mut textures, 1, |_| DMat4::IDENTITY)
            .unwrap();
        let now = textures.read_positions(textures.current).unwrap();
        let step = max_error(&now, &previous);
        let drift = max_error(&now, &start);
        println!("step {i}: moved {step:e}, drift {drift:e}");
        assert!(
            step == 0.0 && drift == 0.0,
            "moved at rest: step {step}, drift {drift}"
        );
        previous = now;
    }
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}

#[test]
fn gpu_stays_finite_and_bounded_at_the_extremes() {
    // A representative subset of the CPU stability matrix (tests/simulation_cpu.rs).
    // The rows with full global stiffness have a real bound: each substep puts every
    // vertex on the moved rest pose before the wind pushes it, so the positions are
    // known exactly (`common::seed::rest_pose_pushed_by_wind`). The others are extremes
    // nothing bounds in closed form: checked for finite positions only.
    struct Row {
        dt: f32,
        stiffness: f32,
        iterations: u32,
        force_scale: f32,
        segment_length: f32,
        vertices: u32,
    }
    let rows = [
        Row {
            dt: 0.1,
            stiffness: 1.0,
            iterations: 64,
            force_scale: 1000.0,
            segment_length: 10.0,
            vertices: 64,
        },
        Row {
            dt: 1.0 / 60.0,
            stiffness: 1.0,
            iterations: 2,
            force_scale: 1.0,
            segment_length: 0.02,
            vertices: 33,
        },
        // Finite only:
        Row {
            dt: 1e-4,
            stiffness: 0.0,
            iterations: 0,
            force_scale: 1.0,
            segment_length: 1e-4,
            vertices: 2,
        },
        Row {
            dt: 1.0 / 60.0,
            stiffness: 0.5,
            iterations: 1,
            force_scale: 1000.0,
            segment_length: 1e-4,
            vertices: 64,
        },
        Row {
            dt: 0.1,
            stiffness: 0.0,
            iterations: 64,
            force_scale: 1000.0,
            segment_length: 0.02,
            vertices: 17,
        },
    ];
    let device = common::device();
    let mesh = Mesh::icosphere(1);
    let mut predicted = 0;
    for row in &rows {
        let groom = GroomParams {
            segments: row.vertices - 1,
            segment_length: row.segment_length,
            curl: 0.5,
            ..Default::default()
        };
        let mut s = Strands::grow(&mesh, &groom).unwrap();
        // Fold every strand of the finite-only rows onto itself at vertex 1: a
        // zero-length segment. (Not the predicted rows: after the constraints the ends
        // of a folded segment differ by rounding only, and the local walk's frame and
        // the wind's tangent there follow that rounding's direction, which no equation
        // predicts.)
        let v = row.vertices as usize;
        if v > 2 && row.stiffness < 1.0 {
            for strand in 0..s.count() {
                s.positions[strand * v + 2] = s.positions[strand * v + 1];
            }
        }
        let params = SimParams {
            dt: row.dt,
            global_stiffness: row.stiffness,
            local_stiffness: row.stiffness,
            local_iterations: row.iterations,
            length_iterations: row.iterations,
            gravity: Vec3::new(0.0, -9.82, 0.0) * row.force_scale,
            wind: Vec3::new(6.0, 0.0, 2.0) * row.force_scale,
            ..SimParams::default()
        };
        let motion = Motion {
            kind: MotionKind::Shake,
            amplitude: 0.3,
            rate: 2.0,
        };
        let mut textures = StrandTextures::new(&device, &s, motion.head(0.0).as_mat4()).unwrap();
        let mut gpu = GpuSim::new(&device, &textures, params.clone()).unwrap();
        for _ in 0..4 {
            gpu.run_frames(&mut textures, 10, |t| motion.head(t))
                .unwrap();
            let now = textures.read_positions(textures.current).unwrap();
            assert!(
                now.iter().all(|p| p.is_finite()),
                "non-finite positions at dt {} V {}",
                row.dt,
                v
            );
            if row.stiffness == 1.0 {
                // The positions the equations give, to the rounding of f32: 16 ulps of
                // the largest coordinate, and the push's error from the tangent's (a
                // segment whose ends are 4 ulps off turns by 8 ulps / L).
                let c = StepConstants::new(&params, gpu.time, motion.head(gpu.time));
                let expected = common::seed::rest_pose_pushed_by_wind(
                    &s.positions,
                    v,
                    c.head,
                    Some(c.wind_h2),
                );
                let strength = f64::from(params.wind.length());
                let h = f64::from(row.dt);
                let push = (0..s.count())
                    .map(|k| common::seed::strand_wind_length(strength, 40.0, h, gpu.time, k))
                    .fold(0.0, f64::max);
                let reach = expected
                    .iter()
                    .map(|p| p.abs().max_element())
                    .fold(1.0, f64::max);
                let tolerance = f64::from(f32::EPSILON)
                    * reach
                    * (16.0 + 8.0 * push / f64::from(row.segment_length));
                let error = now
                    .iter()
                    .zip(&expected)
                    .map(|(a, b)| (a.as_dvec3() - *b).length())
                    .fold(0.0, f64::max);
                println!(
                    "dt {} V {v}: {error:e} off the moved rest pose pushed by the wind \
                     (tolerance {tolerance:e}); stretch {:e}",
                    row.dt,
                    common::seed::stretch(&expected, &s.positions, v)
                );
                assert!(
                    error <= tolerance,
                    "dt {} V {v}: {error:e} off the rest pose pushed by the wind",
                    row.dt
                );
                predicted += 1;
            }
        }
    }
    assert_eq!(predicted, 8);
    common::assert_clean(&device);
}

/// Sleep's first guard: a strand sleeps only with its root still. A settled groom whose
/// body then creeps sideways by a fifth of sleep's threshold a frame (2e-4 of the hair
/// length, under `REST_MOTION`), so every other vertex moves slowly enough to sleep:
/// the device's strands must follow their roots as the CPU reference's do, within one
/// frame's rounding budget, and the body must really have moved. Seen failing with the
/// kernel's root check taken out: 3.9e-4 from the reference against a budget of 1.0e-5
/// (5.2e-7 with it), the strands sleeping a frame at a time behind their roots.
#[test]
fn a_creeping_root_keeps_its_strand_awake() {
    let device = common::device();
    let strands = strands(2, &GroomParams::default());
    let params = SimParams::default();
    assert!(
        params.hair_can_rest(),
        "the default simulation lets hair sleep"
    );
    let settle = 1.0;
    let speed =
        0.2 * f64::from(fur_core::sim::cpu::REST_MOTION) * f64::from(strands.hair_length()) * 60.0;
    let head = move |t: f64| {
        DMat4::from_translation(glam::DVec3::new((t - settle).max(0.0) * speed, 0.0, 0.0))
    };
    let mut textures = StrandTextures::new(&device, &strands, head(0.0).as_mat4()).unwrap();
    let mut gpu = GpuSim::new(&device, &textures, params.clone()).unwrap();
    let mut cpu = CpuSim::<f32>::new(&strands, params, head(0.0));
    let frames = 60 + 30;
    gpu.run_frames(&mut textures, frames, head).unwrap();
    for _ in 0..frames {
        cpu.step_frame(head);
    }
    let on_gpu = textures.read_positions(textures.current).unwrap();
    let on_cpu: Vec<Vec3> = cpu.current.iter().map(|v| v.to_vec3()).collect();
    let error = max_error(&on_gpu, &on_cpu);
    let tolerance = parity_tolerance(&cpu.params, &cpu, &on_cpu);
    let crept = 30.0 * speed / 60.0;
    println!("crept {crept:e}; max |gpu - cpu| = {error:e} (tolerance {tolerance:e})");
    assert!(
        crept as f32 > 10.0 * tolerance,
        "the body hardly moved ({crept} against {tolerance})"
    );
    assert!(
        error <= tolerance,
        "the device's strands are {error} from the reference's after creeping"
    );
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}
