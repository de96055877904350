//! Properties of the Han & Harada simulation, checked on the CPU reference (which the
//! GPU tests hold the compute shaders to): rest, length and shape preservation, wind,
//! and numerical stability across a matrix of extreme parameters.

use fur::scene::{GroomParams, Mesh, Strands};
use fur::sim::{CpuSim, Motion, MotionKind, Real, SimParams, V3};
use glam::{DMat4, Vec3};

fn strands(groom: &GroomParams) -> Strands {
    Strands::grow(&Mesh::icosphere(1), groom).unwrap()
}

fn still(_: f64) -> DMat4 {
    DMat4::IDENTITY
}

/// Largest |segment length / rest length − 1| over all segments.
fn stretch<T: Real>(sim: &CpuSim<T>) -> f64 {
    let v = sim.vertices_per_strand();
    let mut worst = 0.0f64;
    for s in 0..sim.rest.count() {
        for i in 1..v {
            let rest = sim.rest.lengths[s * v + i].to_f64();
            let now = (sim.current[s * v + i] - sim.current[s * v + i - 1])
                .length()
                .to_f64();
            if rest > 0.0 {
                worst = worst.max((now / rest - 1.0).abs());
            }
        }
    }
    worst
}

/// Mean distance of every vertex from its rigidly moved rest position, divided by the
/// hair length.
fn shape_error(sim: &CpuSim<f64>, head: DMat4, hair_length: f64) -> f64 {
    let rest = sim
        .rest
        .positions
        .iter()
        .map(|p| head.transform_point3(p.to_vec3().as_dvec3()));
    let total: f64 = rest
        .zip(&sim.current)
        .map(|(r, c)| (r - c.to_vec3().as_dvec3()).length())
        .sum();
    total / sim.current.len() as f64 / hair_length
}

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

/// One row of the stability matrix.
#[derive(Clone, Debug)]
struct Extreme {
    dt: f32,
    stiffness: (f32, f32),
    iterations: u32,
    force_scale: f32,
    segment_length: f32,
    vertices: u32,
}

impl Extreme {
    /// The stretch a root-pinned chain of n segments can reach when each substep's
    /// forcing f h² is corrected by at least one length pass: about n² f h² / L. A
    /// diverging integrator leaves this behind within a few steps.
    fn stretch_bound(&self) -> f64 {
        let n = f64::from(self.vertices - 1);
        let force = f64::from(self.force_scale) * (9.82f64.hypot(0.0) + 6.0f64.hypot(2.0));
        let h = f64::from(self.dt);
        4.0 * n * n * force * h * h / f64::from(self.segment_length) + 1.0
    }
}

/// Runs `steps` frames and returns the largest stretch seen in the first and second
/// halves; panics on any non-finite position.
fn run_extreme<T: Real>(strands: &Strands, e: &Extreme, steps: usize) -> (f64, f64) {
    let params = SimParams {
        dt: e.dt,
        global_stiffness: e.stiffness.0,
        local_stiffness: e.stiffness.1,
        local_iterations: e.iterations,
        length_iterations: e.iterations,
        gravity: Vec3::new(0.0, -9.82, 0.0) * e.force_scale,
        wind: Vec3::new(6.0, 0.0, 2.0) * e.force_scale,
        ..SimParams::default()
    };
    params.validate().unwrap();
    let motion = Motion {
        kind: MotionKind::Shake,
        amplitude: 0.3,
        rate: 2.0,
    };
    let mut sim = CpuSim::<T>::new(strands, params, motion.head(0.0));
    let (mut first, mut second) = (0.0f64, 0.0f64);
    for step in 0..steps {
        sim.step_frame(|t| motion.head(t));
        assert!(
            sim.current.iter().all(|p| V3::is_finite(*p)),
            "{e:?}: non-finite position at step {step}"
        );
        let s = stretch(&sim);
        if step < steps / 2 {
            first = first.max(s);
        } else {
            second = second.max(s);
        }
    }
    (first, second)
}

fn extremes() -> Vec<Extreme> {
    let mut rows = Vec::new();
    for dt in [1e-4, 1.0 / 60.0, 0.1] {
        for stiffness in [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.5)] {
            for iterations in [0, 1, 64] {
                for force_scale in [1.0, 1000.0] {
                    for (segment_length, vertices) in
                        [(1e-4, 64), (0.02, 17), (10.0, 2), (10.0, 64), (1e-4, 2)]
                    {
                        rows.push(Extreme {
                            dt,
                            stiffness,
                            iterations,
                            force_scale,
                            segment_length,
                            vertices,
                        });
                    }
                }
            }
        }
    }
    rows
}

#[test]
fn stability_matrix_on_the_cpu_reference() {
    // 3 dt × 4 stiffness pairs × 3 iteration counts × 2 force scales × 5 strand shapes.
    let rows = extremes();
    assert_eq!(rows.len(), 360);
    let mesh = Mesh::icosphere(0);
    let mut worst_growth = 0.0f64;
    let mut by_iterations: std::collections::HashMap<String, (Extreme, Vec<(u32, f64)>)> =
        Default::default();
    for e in &rows {
        let groom = GroomParams {
            segments: e.vertices - 1,
            segment_length: e.segment_length,
            curl: 0.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        let (first, second) = run_extreme::<f32>(&strands, e, 40);
        run_extreme::<f64>(&strands, e, 6);
        if e.iterations > 0 {
            let bound = e.stretch_bound();
            assert!(
                first.max(second) <= bound,
                "{e:?}: stretch {first} then {second} exceeds {bound}"
            );
            worst_growth = worst_growth.max(first.max(second) / bound);
        }
        let key = format!(
            "{:?}",
            Extreme {
                iterations: 0,
                ..e.clone()
            }
        );
        by_iterations
            .entry(key)
            .or_insert_with(|| (e.clone(), Vec::new()))
            .1
            .push((e.iterations, first.max(second)));
    }
    // More iterations never make the stretch worse, beyond the last wind push (applied
    // after the length constraint, so no iteration count can undo it).
    for (key, (e, runs)) in &by_iterations {
        let at = |n: u32| runs.iter().find(|(i, _)| *i == n).map(|(_, s)| *s).unwrap();
        let h = f64::from(e.dt);
        let wind_push =
            f64::from(e.force_scale) * 6.0f64.hypot(2.0) * h * h / f64::from(e.segment_length);
        let slack = 2.0 * wind_push + 0.01 * at(1) + 1e-3;
        assert!(
            at(64) <= at(1) + slack,
            "{key}: 64 iterations stretch {} vs {} for 1",
            at(64),
            at(1)
        );
    }
    println!("worst stretch as a fraction of its bound: {worst_growth}");
}

#[test]
fn zero_length_segments_stay_finite() {
    // A strand that folds onto itself: vertices 2..5 coincide.
    let mut s = strands(&GroomParams {
        segments: 8,
        ..Default::default()
    });
    let v = s.vertices_per_strand as usize;
    for strand in 0..s.count() {
        let p = s.positions[strand * v + 2];
        for i in 3..6 {
            s.positions[strand * v + i] = p;
        }
    }
    for force_scale in [0.0f32, 1.0, 1000.0] {
        let params = SimParams {
            gravity: Vec3::new(0.0, -9.82, 0.0) * force_scale,
            wind: Vec3::new(3.0, 0.0, 0.0) * force_scale,
            ..SimParams::default()
        };
        let mut sim = CpuSim::<f32>::new(&s, params, DMat4::IDENTITY);
        let start = sim.current.clone();
        for _ in 0..50 {
            sim.step_frame(still);
            assert!(
                sim.current.iter().all(|p| p.is_finite()),
                "non-finite with zero-length segments"
            );
        }
        if force_scale == 0.0 {
            assert_eq!(sim.current, start, "a folded strand at rest moved");
        }
    }
}

#[test]
fn stability_matrix_collision_rows() {
    // 3 dt × 2 stiffness pairs × 2 iteration counts × 2 force scales × 5 strand shapes,
    // colliding with the icosahedron the strands grow from: never a NaN, and after
    // every frame no vertex deeper inside the body than a quarter of a grid cell.
    let mesh = Mesh::icosphere(0);
    let mut rows = 0;
    let mut deepest = 0.0f64;
    for (segment_length, vertices) in [(1e-4, 64), (0.02, 17), (10.0, 2), (10.0, 64), (1e-4, 2)] {
        let groom = GroomParams {
            segments: vertices - 1,
            segment_length,
            curl: 0.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        let hair = strands.hair_length();
        let (sdf, _) = fur::sim::Sdf::build(&mesh, 32, hair).unwrap();
        let sdf = std::sync::Arc::new(sdf);
        for dt in [1e-4, 1.0 / 60.0, 0.1] {
            for stiffness in [(0.0, 0.0), (1.0, 1.0)] {
                for iterations in [1, 64] {
                    for force_scale in [1.0f32, 1000.0] {
                        let params = SimParams {
                            dt,
                            global_stiffness: stiffness.0,
                            local_stiffness: stiffness.1,
                            local_iterations: iterations,
                            length_iterations: iterations,
                            gravity: Vec3::new(0.0, -9.82, 0.0) * force_scale,
                            wind: Vec3::new(6.0, 0.0, 2.0) * force_scale,
                            ..SimParams::default()
                        };
                        let motion = Motion {
                            kind: MotionKind::Shake,
                            amplitude: 0.3,
                            rate: 2.0,
                        };
                        let mut sim = CpuSim::<f32>::new(&strands, params, motion.head(0.0))
                            .with_sdf(sdf.clone());
                        let v = strands.vertices_per_strand as usize;
                        for step in 0..30 {
                            sim.step_frame(|t| motion.head(t));
                            let to_model = motion.head(sim.time).inverse().as_mat4();
                            for (i, p) in sim.current.iter().enumerate() {
                                assert!(
                                    V3::is_finite(*p),
                                    "non-finite at step {step}: dt {dt}, {stiffness:?}, {iterations} it, ×{force_scale}, {vertices} × {segment_length}"
                                );
                                if i % v == 0 {
                                    continue;
                                }
                                let m = to_model.transform_point3(p.to_vec3());
                                if let Some((d, _)) = sdf.sample(V3::<f64>::from_vec3(m)) {
                                    deepest = deepest.max(-d / f64::from(sdf.cell));
                                }
                            }
                        }
                        rows += 1;
                    }
                }
            }
        }
    }
    assert_eq!(rows, 120);
    println!("deepest vertex: {deepest} cells inside");
    assert!(
        deepest <= 0.25,
        "a vertex ended {deepest} cells inside the body"
    );
}
