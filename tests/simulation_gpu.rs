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
