//! The compute-shader simulation against the CPU reference (the oracle), on lavapipe
//! with validation on.

mod common;

use fur::scene::{GroomParams, Mesh, Strands};
use fur::sim::{CpuSim, GpuSim, Motion, MotionKind, SimParams};
use fur::strand_textures::StrandTextures;
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
    let hair_length = groom.segment_length * groom.segments as f32;
    let tolerance = 1e-4 * hair_length;
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
    let hair_length = groom.segment_length * groom.segments as f32;
    let tolerance = 1e-4 * hair_length;
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
            println!("{steps:?}, {} substeps: {what} {error:e}", params.substeps);
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

/// Largest |segment / rest − 1| of positions laid out strand after strand.
fn stretch(positions: &[Vec3], rest: &[Vec3], v: usize) -> f32 {
    let mut worst = 0.0f32;
    for (now, then) in positions.chunks(v).zip(rest.chunks(v)) {
        for i in 1..v {
            let r = (then[i] - then[i - 1]).length();
            if r > 0.0 {
                worst = worst.max(((now[i] - now[i - 1]).length() / r - 1.0).abs());
            }
        }
    }
    worst
}

#[test]
fn gpu_stays_finite_and_bounded_at_the_extremes() {
    // A representative subset of the CPU stability matrix (tests/simulation_cpu.rs).
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
        Row {
            dt: 1.0 / 60.0,
            stiffness: 1.0,
            iterations: 2,
            force_scale: 1.0,
            segment_length: 0.02,
            vertices: 33,
        },
    ];
    let device = common::device();
    let mesh = Mesh::icosphere(1);
    for row in &rows {
        let groom = GroomParams {
            segments: row.vertices - 1,
            segment_length: row.segment_length,
            curl: 0.5,
            ..Default::default()
        };
        let mut s = Strands::grow(&mesh, &groom).unwrap();
        // Fold every strand onto itself at vertex 1: a zero-length segment.
        let v = row.vertices as usize;
        if v > 2 {
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
        let mut gpu = GpuSim::new(&device, &textures, params).unwrap();
        let mut worst = 0.0f32;
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
            worst = worst.max(stretch(&now, &s.positions, v));
        }
        if row.iterations > 0 {
            // The same bound as the CPU matrix: about n² f h² / L.
            let n = (v - 1) as f32;
            let force = row.force_scale * (9.82 + 6.0f32.hypot(2.0));
            let bound = 4.0 * n * n * force * row.dt * row.dt / row.segment_length + 1.0;
            assert!(
                worst <= bound,
                "dt {} V {v}: stretch {worst} exceeds {bound}",
                row.dt
            );
        }
    }
    common::assert_clean(&device);
}
