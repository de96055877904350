//! Rest, length, shape preservation and wind on the CPU reference.

use super::*;

#[test]
fn at_rest_nothing_moves_in_f32_or_f64() {
    let groom = GroomParams {
        curl: 0.7,
        ..Default::default()
    };
    let s = strands(&groom);
    for local_iterations in [1, 2, 5] {
        let params = SimParams {
            local_iterations,
            ..SimParams::at_rest()
        };
        let mut single = CpuSim::<f32>::new(&s, params.clone(), DMat4::IDENTITY);
        let mut double = CpuSim::<f64>::new(&s, params, DMat4::IDENTITY);
        let (start_single, start_double) = (single.current.clone(), double.current.clone());
        for step in 0..300 {
            single.step_frame(still);
            double.step_frame(still);
            // Exactly the start: no drift, and no flicker between two states.
            assert_eq!(
                single.current, start_single,
                "f32 moved at step {step} ({local_iterations} local iterations)"
            );
            assert_eq!(double.current, start_double, "f64 moved at step {step}");
        }
    }
}

/// Hair hanging under gravity (collision off) settles and then stays exactly still in
/// f32: once a frame moves a strand by no more than rounding noise (16 ulps of its
/// largest coordinate) the strand is put back where the frame started, so it neither
/// drifts nor dithers; in f64 as well. The same on a body 100 times larger (with
/// 100 times the gravity, the same motion scaled), where an ulp is 100 times larger.
#[test]
fn hanging_hair_comes_to_rest_exactly() {
    for scale in [1.0f32, 100.0] {
        let mut mesh = Mesh::icosphere(1);
        for p in &mut mesh.positions {
            *p *= scale;
        }
        let groom = GroomParams {
            segments: 8,
            segment_length: 0.016 * scale,
            ..Default::default()
        };
        let s = Strands::grow(&mesh, &groom).unwrap();
        let params = SimParams {
            collision: false,
            gravity: SimParams::default().gravity * scale,
            ..SimParams::default()
        };
        let mut single = CpuSim::<f32>::new(&s, params.clone(), DMat4::IDENTITY);
        let mut double = CpuSim::<f64>::new(&s, params, DMat4::IDENTITY);
        let start = single.current.clone();
        for _ in 0..600 {
            single.step_frame(still);
            double.step_frame(still);
        }
        // It hangs: the tips fell.
        let v = single.vertices_per_strand();
        let fell = (0..s.count())
            .map(|k| (single.current[k * v + v - 1] - start[k * v + v - 1]).length())
            .fold(0.0f32, f32::max);
        assert!(
            fell > 0.01 * s.hair_length(),
            "scale {scale}: nothing fell ({fell})"
        );
        let (settled_single, settled_double) = (single.current.clone(), double.current.clone());
        for frame in 0..60 {
            single.step_frame(still);
            double.step_frame(still);
            let at = format!("scale {scale}, frame {frame}");
            assert_eq!(single.current, settled_single, "f32 moved at {at}");
            assert_eq!(single.previous, settled_single, "f32 moving at {at}");
            assert_eq!(double.current, settled_double, "f64 moved at {at}");
        }
    }
}

#[test]
fn length_error_is_bounded_and_shrinks_with_length_iterations() {
    let s = strands(&GroomParams::default());
    let mut errors = Vec::new();
    for iterations in [1u32, 2, 4, 8, 16] {
        let params = SimParams {
            length_iterations: iterations,
            local_stiffness: 0.0,
            global_stiffness: 0.0,
            ..SimParams::default()
        };
        let mut sim = CpuSim::<f64>::new(&s, params, DMat4::IDENTITY);
        let mut worst = 0.0f64;
        for _ in 0..200 {
            sim.step_frame(still);
            worst = worst.max(stretch(&sim));
        }
        errors.push(worst);
    }
    // With no shape constraints to help, a 16-segment chain hanging under gravity is the
    // hardest case for even/odd Gauss–Seidel: the top segment carries the whole chain.
    println!("max stretch in 200 steps for 1, 2, 4, 8, 16 length iterations: {errors:?}");
    assert!(
        errors[0].is_finite() && errors[0] < 10.0,
        "one iteration: stretch {}",
        errors[0]
    );
    // Each doubling of the iterations at least roughly halves the error.
    assert!(
        errors.windows(2).all(|w| w[1] < 0.7 * w[0]),
        "stretch does not shrink: {errors:?}"
    );
}

#[test]
fn full_global_stiffness_returns_the_groom_to_the_moved_rest_pose() {
    let groom = GroomParams {
        curl: 0.5,
        ..Default::default()
    };
    let s = strands(&groom);
    let motion = Motion {
        kind: MotionKind::Spin,
        amplitude: 0.0,
        rate: 0.5,
    };
    let params = SimParams {
        global_stiffness: 1.0,
        global_range: 1.0,
        wind: Vec3::new(5.0, 0.0, 0.0),
        ..SimParams::default()
    };
    let mut sim = CpuSim::<f64>::new(&s, params, motion.head(0.0));
    let hair_length = f64::from(groom.segment_length * groom.segments as f32);
    for _ in 0..30 {
        sim.step_frame(|t| motion.head(t));
    }
    // Wind is applied after the shape constraints: what remains is its one-step push,
    // at most |W| h² per vertex.
    let error = shape_error(&sim, motion.head(sim.time), hair_length);
    let h = sim.params.substep_dt();
    let one_push = 5.0 * h * h / hair_length;
    assert!(
        error <= one_push,
        "S_G = 1 leaves a shape error of {error} (one wind push: {one_push})"
    );
    let without_wind = SimParams {
        wind: Vec3::ZERO,
        ..sim.params.clone()
    };
    let mut sim = CpuSim::<f64>::new(&s, without_wind, motion.head(0.0));
    for _ in 0..30 {
        sim.step_frame(|t| motion.head(t));
    }
    let error = shape_error(&sim, motion.head(sim.time), hair_length);
    // What remains is the f32 rounding of the head transform (the step constants are f32
    // for the GPU's sake, also when the reference runs in f64).
    assert!(
        error < 1e-6,
        "S_G = 1 without wind leaves a shape error of {error}"
    );
}

#[test]
fn more_local_stiffness_keeps_more_of_the_groom() {
    let groom = GroomParams {
        curl: 0.8,
        comb_strength: 0.5,
        ..Default::default()
    };
    let s = strands(&groom);
    let hair_length = f64::from(groom.segment_length * groom.segments as f32);
    let mut errors = Vec::new();
    for stiffness in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
        let params = SimParams {
            global_stiffness: 0.0,
            local_stiffness: stiffness,
            ..SimParams::default()
        };
        let mut sim = CpuSim::<f64>::new(&s, params, DMat4::IDENTITY);
        for _ in 0..200 {
            sim.step_frame(still);
        }
        errors.push(shape_error(&sim, DMat4::IDENTITY, hair_length));
    }
    println!("shape error after 200 steps under gravity for S_L = 0, .25, .5, .75, 1: {errors:?}");
    assert!(
        errors.windows(2).all(|w| w[1] < w[0]),
        "not monotone: {errors:?}"
    );
    assert!(errors[4] < 0.5 * errors[0], "{errors:?}");
}

#[test]
fn wind_moves_tips_along_the_wind_on_average() {
    let s = strands(&GroomParams::default());
    for direction in [
        Vec3::X,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(1.0, 1.0, 0.0).normalize(),
    ] {
        let params = SimParams {
            gravity: Vec3::ZERO,
            wind: direction * 20.0,
            ..SimParams::default()
        };
        let mut sim = CpuSim::<f64>::new(&s, params, DMat4::IDENTITY);
        let start = sim.current.clone();
        for _ in 0..60 {
            sim.step_frame(still);
        }
        let v = sim.vertices_per_strand();
        let mut mean = glam::DVec3::ZERO;
        for strand in 0..sim.rest.count() {
            let tip = strand * v + v - 1;
            mean += (sim.current[tip] - start[tip]).to_vec3().as_dvec3();
        }
        mean /= sim.rest.count() as f64;
        let along = mean.dot(direction.as_dvec3());
        let across = (mean - along * direction.as_dvec3()).length();
        assert!(
            along > 0.0 && along > 2.0 * across,
            "wind {direction}: mean tip motion {mean}"
        );
    }
}
