//! Properties of the Han & Harada simulation, checked on the CPU reference (which the
//! GPU tests hold the compute shaders to): rest, length and shape preservation, wind,
//! and numerical stability across a matrix of extreme parameters.

mod common;

use std::cell::RefCell;
use std::sync::Arc;

use fur::scene::{GroomParams, Mesh, Strands};
use fur::sim::{CpuSim, Motion, MotionKind, Real, Sdf, SimParams, StepConstants, V3};
use fur::skinning::cpu::Posed;
use fur::skinning::RootPose;
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

/// How a row of the stability matrix is judged.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Judged {
    /// S_G = 1 over the whole strand: every substep puts each vertex on the rigidly
    /// moved rest pose before the wind acts, so the positions after the step are known
    /// exactly (`common::seed::rest_pose_pushed_by_wind`) and are checked to the
    /// precision's resolution; the stretch follows.
    Predicted,
    /// One segment, at least one length pass: the pinned root makes the segment exactly
    /// its rest length before the wind pushes the tip across it (the push is
    /// perpendicular to the segment), so the stretch is at most
    /// `√(1 + (W/L)²) − 1` for the strand's wind `W` of that substep, plus rounding.
    WindOnExactLength,
    /// Nothing bounds the stretch in closed form (no length pass, or a chain whose
    /// even/odd passes do not converge in 64 iterations under forcing up to ×1000):
    /// checked only for finite positions, and, where the slack is small, for more
    /// iterations never stretching more.
    FiniteOnly,
}

impl Extreme {
    fn params(&self, wind_scale: f32) -> SimParams {
        SimParams {
            dt: self.dt,
            global_stiffness: self.stiffness.0,
            local_stiffness: self.stiffness.1,
            local_iterations: self.iterations,
            length_iterations: self.iterations,
            gravity: Vec3::new(0.0, -9.82, 0.0) * self.force_scale,
            wind: Vec3::new(6.0, 0.0, 2.0) * self.force_scale * wind_scale,
            ..SimParams::default()
        }
    }

    fn judged(&self) -> Judged {
        if self.stiffness.0 == 1.0 {
            Judged::Predicted
        } else if self.vertices == 2 && self.iterations > 0 {
            Judged::WindOnExactLength
        } else {
            Judged::FiniteOnly
        }
    }

    /// The largest wind displacement any strand takes in the substep ending at `t`
    /// (seed eq. 7 and 8, `common::seed::strand_wind_length`), for wind × `wind_scale`.
    fn wind_reach(&self, t: f64, strands: usize) -> f64 {
        let strength = f64::from((Vec3::new(6.0, 0.0, 2.0) * self.force_scale).length());
        (0..strands)
            .map(|s| common::seed::strand_wind_length(strength, 40.0, f64::from(self.dt), t, s))
            .fold(0.0, f64::max)
    }
}

fn head_motion() -> Motion {
    Motion {
        kind: MotionKind::Shake,
        amplitude: 0.3,
        rate: 2.0,
    }
}

/// What running one row showed.
#[derive(Debug, Default)]
struct Outcome {
    /// Largest stretch over the run.
    stretch: f64,
    /// Largest measured / allowed over the run (Predicted: position error over its
    /// tolerance; WindOnExactLength: stretch over its bound).
    used: f64,
    /// WindOnExactLength: whether the wind's term of the bound dwarfs the rounding term
    /// (otherwise the row is checked at the precision's resolution only).
    wind_resolved: bool,
}

/// Runs `frames` frames of row `e` in precision `T`, panicking on a non-finite
/// position or a broken bound; `wind_scale` runs it with that much more wind than the
/// bound is computed for (to show the bound rejects a wrong wind).
fn run_extreme<T: Real>(strands: &Strands, e: &Extreme, frames: usize, wind_scale: f32) -> Outcome {
    let params = e.params(wind_scale);
    params.validate().unwrap();
    let motion = head_motion();
    let mut sim = CpuSim::<T>::new(strands, params.clone(), motion.head(0.0));
    let v = strands.vertices_per_strand as usize;
    let eps = if std::mem::size_of::<T>() == 4 {
        f64::from(f32::EPSILON)
    } else {
        f64::EPSILON
    };
    let l = f64::from(e.segment_length);
    let mut out = Outcome::default();
    // The end of the frame's substep, kept here rather than read from the simulation.
    let mut time = 0.0f64;
    for frame in 0..frames {
        sim.step_frame(|t| motion.head(t));
        for _ in 0..params.substeps {
            time += params.substep_dt();
        }
        assert_eq!(sim.time, time, "{e:?}: the clock");
        assert!(
            sim.current.iter().all(|p| V3::is_finite(*p)),
            "{e:?}: non-finite position at frame {frame}"
        );
        let now: Vec<glam::DVec3> = sim
            .current
            .iter()
            .map(|p| glam::DVec3::new(p.0.to_f64(), p.1.to_f64(), p.2.to_f64()))
            .collect();
        let s = common::seed::stretch(&now, &strands.positions, v);
        out.stretch = out.stretch.max(s);
        // The largest coordinate: what one rounding of a position is relative to.
        let reach = now
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        match e.judged() {
            Judged::Predicted => {
                // Tolerance: 16 roundings of the largest coordinate (the head
                // transform, the global pull x + (r − x)·1, the local walk's and the
                // length passes' fixed points, the push), each at most one ulp; and the
                // push's error from the tangent's: a segment of length L whose ends are
                // off by 4 ulps turns by up to 8 ulps / L, which turns a push of
                // length W by as much.
                let c = StepConstants::new(&params, time, motion.head(time));
                let wind = params.wind_enabled().then_some(c.wind_h2);
                let predicted =
                    common::seed::rest_pose_pushed_by_wind(&strands.positions, v, c.head, wind);
                let error = now
                    .iter()
                    .zip(&predicted)
                    .map(|(a, b)| (*a - *b).length())
                    .fold(0.0, f64::max);
                let w = e.wind_reach(time, strands.count());
                let tolerance = eps * reach.max(1.0) * (16.0 + 8.0 * w / l);
                assert!(
                    error <= tolerance,
                    "{e:?}: frame {frame} is {error:e} off the rest pose pushed by the \
                     wind (tolerance {tolerance:e}); stretch {s:e} against {:e}",
                    common::seed::stretch(&predicted, &strands.positions, v)
                );
                out.used = out.used.max(error / tolerance);
            }
            Judged::WindOnExactLength => {
                let w = e.wind_reach(time, strands.count()) / l;
                let wind_term = (1.0 + w * w).sqrt() - 1.0;
                // The pinned solve leaves |segment| − L within a few roundings of the
                // coordinates: 4 ulps of the largest one, relative to L.
                let rounding = 4.0 * eps * reach / l;
                let bound = wind_term + rounding;
                out.wind_resolved = wind_term > 10.0 * rounding;
                if wind_scale == 1.0 {
                    assert!(
                        s <= bound,
                        "{e:?}: frame {frame} stretches {s:e}, over its bound {bound:e} \
                         (wind {wind_term:e}, rounding {rounding:e})"
                    );
                }
                out.used = out.used.max(s / bound);
            }
            Judged::FiniteOnly => {}
        }
    }
    out
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
    // 3 dt × 4 stiffness pairs × 3 iteration counts × 2 force scales × 5 strand shapes,
    // 40 frames each in f32 and in f64.
    let rows = extremes();
    assert_eq!(rows.len(), 360);
    let mesh = Mesh::icosphere(0);
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    let (mut tightest_predicted, mut loosest_bound) = (0.0f64, f64::MAX);
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
        let single = run_extreme::<f32>(&strands, e, 40, 1.0);
        let double = run_extreme::<f64>(&strands, e, 40, 1.0);
        *counts.entry(format!("{:?}", e.judged())).or_default() += 1;
        match e.judged() {
            Judged::Predicted => {
                tightest_predicted = tightest_predicted.max(single.used.max(double.used));
            }
            Judged::WindOnExactLength => {
                // The bound binds: the same row with twice the wind (a wind step twice
                // too strong) breaks it, wherever the wind's term is above rounding.
                for (name, outcome, twice) in [
                    ("f32", &single, run_extreme::<f32>(&strands, e, 40, 2.0)),
                    ("f64", &double, run_extreme::<f64>(&strands, e, 40, 2.0)),
                ] {
                    if outcome.wind_resolved {
                        assert!(
                            twice.used > 1.0,
                            "{e:?} ({name}): twice the wind stays within the bound \
                             ({:.2} of it; once: {:.2})",
                            twice.used,
                            outcome.used
                        );
                        loosest_bound = loosest_bound.min(outcome.used);
                        *counts
                            .entry("WindOnExactLength, above rounding".into())
                            .or_default() += 1;
                    }
                }
            }
            Judged::FiniteOnly => {}
        }
        if e.judged() == Judged::FiniteOnly && e.vertices > 2 && e.iterations > 0 {
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
                .push((e.iterations, double.stretch));
        }
    }
    println!(
        "rows by how they are judged: {counts:?}; predicted rows within {tightest_predicted:.2} \
         of their tolerance; wind-bounded rows reach at least {loosest_bound:.2} of their bound"
    );
    assert_eq!(counts["Predicted"], 90);
    assert_eq!(counts["WindOnExactLength"], 72);
    assert_eq!(counts["FiniteOnly"], 198);
    // More length and shape iterations never stretch a chain more, beyond what the wind
    // (applied after the length passes, which no iteration count undoes) can change a
    // segment by: both ends pushed by at most W, so 2W/L. Checked where that slack is
    // under a tenth of the stretch; elsewhere the wind alone decides and the rows are
    // finite-only.
    let mut compared = 0;
    for (key, (e, runs)) in &by_iterations {
        let at = |n: u32| runs.iter().find(|(i, _)| *i == n).map(|(_, s)| *s).unwrap();
        let reach = (0..=40)
            .map(|k| e.wind_reach(f64::from(e.dt) * f64::from(k), 12))
            .fold(0.0, f64::max);
        let slack = 2.0 * reach / f64::from(e.segment_length);
        if slack < 0.1 * at(1) {
            compared += 1;
            assert!(
                at(64) <= at(1) + slack,
                "{key}: 64 iterations stretch {} vs {} for 1 (slack {slack:e})",
                at(64),
                at(1)
            );
        }
    }
    println!(
        "iteration counts compared in {compared} of {} chains",
        by_iterations.len()
    );
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

/// Collision rows of the stability matrix: 3 dt × 2 stiffness pairs × 2 iteration
/// counts × 2 force scales × 5 strand shapes, colliding with the icosahedron the strands
/// grow from. Depth is judged by exact distances to the mesh (not by the field the
/// collider uses), in scene units. The field has 128 cells over the body's box padded
/// by the hair length, at most 0.5: padding by a 630-unit hair would spread the cells
/// over its reach and leave the body unresolved, and vertices beyond the grid are too
/// far out to touch the body. Never a NaN anywhere; the strand shapes are judged by
/// what the field can resolve:
/// - hair 0.32 long (17 vertices): the collider keeps every vertex at least the margin
///   out by its field, and the field is within `e` of exact distances near the surface
///   (measured here), so every vertex is at least `margin − e` out. The margin is 0.1 of
///   the hair (1.75 cells, e ≈ 0.2 cells) so that this is a real distance outside the
///   body; it binds: the same rows with half the margin (a collider keeping half the
///   distance it should) fall under it wherever the hair touches the body.
/// - hair 0.0063 and 0.0001 long: shorter than the field's error, so no collider using
///   this field can keep them a margin out; no vertex is deeper inside than `e`.
/// - 10-unit segments: every vertex but the root is 10 units from the body, beyond the
///   field: finite only.
#[test]
fn stability_matrix_collision_rows() {
    let mesh = Mesh::icosphere(0);
    let mut rows = 0;
    let (mut resolved, mut limited, mut far, mut touching) = (0, 0, 0, 0);
    for (segment_length, vertices) in [(1e-4, 64), (0.02, 17), (10.0, 2), (10.0, 64), (1e-4, 2)] {
        let groom = GroomParams {
            segments: vertices - 1,
            segment_length,
            curl: 0.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        let hair = strands.hair_length();
        let (sdf, _) = fur::sim::Sdf::build(&mesh, 128, hair.min(0.5)).unwrap();
        let e = common::field_error(&mesh, &sdf, (-2.0 * sdf.cell, 2.0 * sdf.cell));
        let sdf = std::sync::Arc::new(sdf);
        let is_resolved = segment_length == 0.02;
        let is_far = segment_length >= 10.0;
        let margin_fraction = if is_resolved { 0.1 } else { 0.02 };
        // The smallest exact distance of a non-root vertex to the body over 30 frames,
        // with the collider keeping `fraction` of the hair length out.
        let clearance = |params: &SimParams, fraction: f32| {
            let motion = head_motion();
            let params = SimParams {
                collision_margin: fraction,
                ..params.clone()
            };
            let mut sim =
                CpuSim::<f32>::new(&strands, params, motion.head(0.0)).with_sdf(sdf.clone());
            let v = strands.vertices_per_strand as usize;
            let mut nearest = f64::MAX;
            for step in 0..30 {
                sim.step_frame(|t| motion.head(t));
                assert!(
                    sim.current.iter().all(|p| V3::is_finite(*p)),
                    "non-finite at step {step}: {:?}, {vertices} × {segment_length}",
                    sim.params
                );
                let to_model = motion.head(sim.time).inverse().as_mat4();
                let model: Vec<Vec3> = sim
                    .current
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| i % v != 0) // roots sit on the surface
                    .map(|(_, p)| to_model.transform_point3(p.to_vec3()))
                    .collect();
                let exact = fur::sim::sdf::exact_distances(&mesh, &model);
                nearest = exact.iter().fold(nearest, |m, d| m.min(f64::from(*d)));
            }
            nearest
        };
        for dt in [1e-4, 1.0 / 60.0, 0.1] {
            for stiffness in [(0.0, 0.0), (1.0, 1.0)] {
                for iterations in [1, 64] {
                    for force_scale in [1.0f32, 1000.0] {
                        let e_row = Extreme {
                            dt,
                            stiffness,
                            iterations,
                            force_scale,
                            segment_length,
                            vertices,
                        };
                        let params = e_row.params(1.0);
                        let nearest = clearance(&params, margin_fraction);
                        let margin = f64::from(margin_fraction * hair);
                        if is_resolved {
                            resolved += 1;
                            assert!(
                                nearest >= margin - e,
                                "{e_row:?}: a vertex {nearest:e} from the body, under the \
                                 margin {margin:e} less the field's error {e:e}"
                            );
                            if nearest < margin + e {
                                // In contact: the bound rejects a collider keeping half
                                // the margin.
                                touching += 1;
                                let half = clearance(&params, margin_fraction / 2.0);
                                assert!(
                                    half < margin - e,
                                    "{e_row:?}: half the margin ({half:e} out) passes the \
                                     bound {:e}",
                                    margin - e
                                );
                            }
                        } else if is_far {
                            far += 1;
                        } else {
                            limited += 1;
                            assert!(
                                nearest >= -e,
                                "{e_row:?}: a vertex {:e} inside the body, deeper than the \
                                 field's error {e:e}",
                                -nearest
                            );
                        }
                        rows += 1;
                    }
                }
            }
        }
        println!(
            "{vertices} × {segment_length}: field cell {}, error {e:e}",
            sdf.cell
        );
    }
    assert_eq!((rows, resolved, limited, far), (120, 24, 48, 48));
    println!("{touching} of the {resolved} resolved rows touch the body");
    assert!(
        touching >= 8,
        "only {touching} resolved rows touch the body"
    );
}

/// `StepConstants::new` feeds the CPU reference and the compute shaders alike, so no
/// parity test can find an error in it: here it is held to values derived by hand from
/// the parameters' documented meaning and the seed's equations.
#[test]
fn step_constants_are_the_seed_equations() {
    let params = SimParams {
        dt: 1.0 / 50.0,
        substeps: 4,
        gravity: Vec3::new(1.0, -9.82, 0.5),
        damping: 0.3,
        wind: Vec3::new(3.0, -1.0, 2.0),
        wind_cone_deg: 25.0,
        ..SimParams::default()
    };
    // The substep, from the f32 frame time the parameters hold.
    let h = f64::from(1.0f32 / 50.0) / 4.0;
    let head = Motion {
        kind: MotionKind::Nod,
        amplitude: 30.0,
        rate: 0.7,
    };
    let strength = f64::from(params.wind.length());
    let d = params.wind.as_dvec3().normalize();
    let cone = 25f64.to_radians();
    // Over a whole period of the wind's magnitude, π/3 s, and a little more.
    for k in 0..=40 {
        let t = k as f64 * std::f64::consts::PI / 3.0 / 36.0;
        let c = StepConstants::new(&params, t, head.head(t));
        // Velocity kept per substep: (1 − damping)^(60 h) = 0.7^(1.2 / 4).
        assert!((60.0 * h - 0.3).abs() < 1e-8);
        let r = 0.7f64.powf(60.0 * h);
        assert_eq!(c.velocity_retention, r as f32, "retention at {t}");
        assert_eq!(c.velocity_retention, common::seed::retention(0.3, h) as f32);
        // Gravity times h², rounded once.
        assert_eq!(
            c.gravity_h2,
            (params.gravity.as_dvec3() * h * h).as_vec3(),
            "gravity h² at {t}"
        );
        // The head and its inverse.
        assert!(c.head.abs_diff_eq(head.head(t).as_mat4(), 1e-7));
        assert!((c.head * c.head_inverse).abs_diff_eq(glam::Mat4::IDENTITY, 1e-6));
        // Each of the four wind vectors: ½ |W| (sin²(3t) + 0.5) h² long, on the cone of
        // half-angle 25° about the wind's direction.
        let magnitude = (3.0 * t).sin().powi(2) + 0.5;
        assert!((magnitude - common::seed::wind_magnitude(t)).abs() < 1e-15);
        let length = 0.5 * strength * magnitude * h * h;
        let w = c.wind_h2.map(|w| w.as_dvec3());
        for (i, wi) in w.iter().enumerate() {
            assert!(
                (wi.length() / length - 1.0).abs() < 1e-6,
                "W{} at t = {t}: length {} instead of {length}",
                i + 1,
                wi.length()
            );
            let angle = wi.normalize().dot(d).clamp(-1.0, 1.0).acos();
            assert!(
                (angle - cone).abs() < 1e-5,
                "W{} at t = {t} is {}° off the wind, not 25°",
                i + 1,
                angle.to_degrees()
            );
        }
        // Spread in two opposite pairs about two perpendicular axes: W1 + W2 and
        // W3 + W4 along the wind, W1 − W2 perpendicular to W3 − W4.
        for (p, q) in [(0, 1), (2, 3)] {
            let sum = w[p] + w[q];
            assert!(
                sum.normalize().dot(d) > 1.0 - 1e-9,
                "W{} + W{}",
                p + 1,
                q + 1
            );
            assert!(
                ((w[p] - w[q]).length() / (2.0 * length * cone.sin()) - 1.0).abs() < 1e-5,
                "W{} and W{} are not ±25° apart",
                p + 1,
                q + 1
            );
        }
        assert!(
            (w[0] - w[1])
                .normalize()
                .dot((w[2] - w[3]).normalize())
                .abs()
                < 1e-5
        );
        // The blend every strand takes is as long as the equations alone say.
        for strand in [0usize, 7, 19, 20, 33] {
            let a = common::seed::blend_weight(strand);
            let blend = (w[0] + w[2]) * a + (w[1] + w[3]) * (1.0 - a);
            let expected = common::seed::strand_wind_length(strength, 25.0, h, t, strand);
            assert!((blend.length() / expected - 1.0).abs() < 1e-5);
        }
    }
    // The magnitude's extremes over the period: 0.5 at t = 0 and π/3, 1.5 at π/6.
    for (t, m) in [
        (0.0, 0.5),
        (std::f64::consts::PI / 6.0, 1.5),
        (std::f64::consts::PI / 3.0, 0.5),
    ] {
        let c = StepConstants::new(&params, t, DMat4::IDENTITY);
        let expected = 0.5 * strength * m * h * h;
        assert!((c.wind_h2[0].as_dvec3().length() / expected - 1.0).abs() < 1e-6);
    }
    // A cone of 0° puts all four on the wind, one of 90° all four across it; no wind,
    // no vectors.
    for (cone_deg, cos) in [(0.0f32, 1.0f64), (90.0, 0.0)] {
        let c = StepConstants::new(
            &SimParams {
                wind_cone_deg: cone_deg,
                ..params.clone()
            },
            0.3,
            DMat4::IDENTITY,
        );
        for w in c.wind_h2 {
            assert!(
                (w.as_dvec3().normalize().dot(d) - cos).abs() < 1e-6,
                "{cone_deg}°"
            );
        }
    }
    let calm = StepConstants::new(
        &SimParams {
            wind: Vec3::ZERO,
            ..params.clone()
        },
        0.3,
        DMat4::IDENTITY,
    );
    assert_eq!(calm.wind_h2, [Vec3::ZERO; 4]);
    // Without damping every bit of velocity is kept; with full damping none.
    for (damping, kept) in [(0.0, 1.0), (1.0, 0.0)] {
        let c = StepConstants::new(
            &SimParams {
                damping,
                ..params.clone()
            },
            0.3,
            DMat4::IDENTITY,
        );
        assert_eq!(c.velocity_retention, kept);
    }
}

/// Free fall: with every constraint, the wind and collision off, each vertex but the
/// root falls exactly the discrete Verlet sum (see `common::seed::free_fall`), with the
/// damping's retention (1 − damping)^(60 h) per substep; undamped that is
/// ½ g t² (1 + 1/n).
#[test]
fn an_unconstrained_vertex_falls_the_discrete_verlet_sum() {
    let s = strands(&GroomParams {
        segments: 3,
        ..Default::default()
    });
    // Gravity as the parameters hold it (f32).
    let g = Vec3::new(0.5, -9.82, -1.25).as_dvec3();
    for (damping, substeps, frames) in [(0.0f32, 1u32, 60usize), (0.08, 1, 60), (0.3, 4, 25)] {
        let params = SimParams {
            substeps,
            gravity: g.as_vec3(),
            damping,
            global_stiffness: 0.0,
            local_stiffness: 0.0,
            local_iterations: 0,
            length_iterations: 0,
            collision: false,
            ..SimParams::default()
        };
        let mut sim = CpuSim::<f64>::new(&s, params, DMat4::IDENTITY);
        let start = sim.current.clone();
        for _ in 0..frames {
            sim.step_frame(still);
        }
        let h = f64::from(1.0f32 / 60.0) / f64::from(substeps);
        let n = frames as u32 * substeps;
        // The clock: n substeps of h.
        assert!(
            (sim.time - h * f64::from(n)).abs() < 1e-12,
            "time {}",
            sim.time
        );
        // The constants the step runs on are rounded once to f32 (for the GPU's sake).
        let r = f64::from(common::seed::retention(f64::from(damping), h) as f32);
        let gh2 = (g * h * h).as_vec3().as_dvec3();
        let (fall, last_step) = common::seed::free_fall(r, n);
        if damping == 0.0 {
            let t = h * f64::from(n);
            let continuous = 0.5 * g.y * t * t * (1.0 + 1.0 / f64::from(n));
            assert!(((gh2.y * fall) / continuous - 1.0).abs() < 1e-6);
        }
        let v = sim.vertices_per_strand();
        for (i, (now, then)) in sim.current.iter().zip(&start).enumerate() {
            let d = *now - *then;
            let moved = glam::DVec3::new(d.0, d.1, d.2);
            if i % v == 0 {
                assert_eq!(moved, glam::DVec3::ZERO, "a root moved");
                continue;
            }
            let expected = gh2 * fall;
            assert!(
                (moved - expected).length() <= 1e-9 * expected.length(),
                "damping {damping}, {substeps} substeps: fell {moved} instead of {expected}"
            );
            let step = *now - sim.previous[i];
            let step = glam::DVec3::new(step.0, step.1, step.2);
            assert!((step - gh2 * last_step).length() <= 1e-9 * (gh2 * last_step).length());
        }
    }
}

/// `Motion::head` feeds both sides of every parity test: its three motions against
/// matrices written out by hand.
#[test]
fn head_motions_are_the_hand_written_matrices() {
    let close = |a: DMat4, b: DMat4, what: &str| {
        assert!(a.abs_diff_eq(b, 1e-12), "{what}:\n{a}\nexpected\n{b}");
    };
    let (s30, c30) = (0.5, 0.75f64.sqrt());
    let motion = |kind, amplitude, rate| Motion {
        kind,
        amplitude,
        rate,
    };
    // Still: nothing, at any time.
    close(
        motion(MotionKind::Still, 5.0, 3.0).head(1.234),
        DMat4::IDENTITY,
        "still",
    );
    // Shake by 0.2 at 2 Hz: x = 0.2 sin(4πt).
    let shake = motion(MotionKind::Shake, 0.2, 2.0);
    let moved = |x: f64| {
        DMat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, x, 0.0, 0.0, 1.0,
        ])
    };
    close(shake.head(0.0), DMat4::IDENTITY, "shake at 0");
    close(shake.head(0.125), moved(0.2), "shake at a quarter period");
    close(shake.head(1.0 / 24.0), moved(0.2 * s30), "shake at 30°");
    close(shake.head(0.375), moved(-0.2), "shake at three quarters");
    // Spin at a quarter turn per second: 90° about y after 1 s (x → −z, z → x), 30°
    // after 1/3 s.
    let spin = motion(MotionKind::Spin, 0.3, 0.25);
    close(
        spin.head(1.0),
        DMat4::from_cols_array(&[
            0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]),
        "spin, 90°",
    );
    close(
        spin.head(1.0 / 3.0),
        DMat4::from_cols_array(&[
            c30, 0.0, -s30, 0.0, 0.0, 1.0, 0.0, 0.0, s30, 0.0, c30, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]),
        "spin, 30°",
    );
    // Nod by 30° at 0.25 Hz: a tilt about x of 30° sin(πt/2): +30° at 1 s (y turns
    // towards z), −30° at 3 s, level at 2 s, 15° at 1/3 s.
    let nod = motion(MotionKind::Nod, 30.0, 0.25);
    let tilt = |c: f64, s: f64| {
        DMat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.0, c, s, 0.0, 0.0, -s, c, 0.0, 0.0, 0.0, 0.0, 1.0,
        ])
    };
    close(nod.head(1.0), tilt(c30, s30), "nod up");
    close(nod.head(3.0), tilt(c30, -s30), "nod down");
    close(nod.head(2.0), DMat4::IDENTITY, "nod level");
    let (s15, c15) = 15f64.to_radians().sin_cos();
    close(nod.head(1.0 / 3.0), tilt(c15, s15), "nod at 15°");
    assert!(
        (nod.head(1.0).transform_vector3(glam::DVec3::Y) - glam::DVec3::new(0.0, c30, s30))
            .length()
            < 1e-12
    );
}

/// Every parameter's documented range, at and just past its ends, and what the derived
/// quantities (substep, distance-field cells, global cutoff) are.
#[test]
fn parameters_outside_their_ranges_are_refused() {
    let ok = SimParams::default();
    ok.validate().unwrap();
    assert_eq!(
        SimParams::at_rest(),
        SimParams {
            gravity: Vec3::ZERO,
            ..SimParams::default()
        }
    );
    assert_ne!(SimParams::default().gravity, Vec3::ZERO);
    let refused = |p: SimParams, name: &str| {
        let error = p.validate().expect_err(name).to_string();
        assert!(error.contains(name), "`{error}` does not name {name}");
    };
    let accepted = |p: SimParams| p.validate().unwrap();
    // dt in (0, 0.1].
    for dt in [0.0, -0.01, 0.100_001, f32::NAN, f32::INFINITY] {
        refused(SimParams { dt, ..ok.clone() }, "dt");
    }
    for dt in [1e-6, 0.1] {
        accepted(SimParams { dt, ..ok.clone() });
    }
    // The [0, 1] fractions and the cone's [0, 90] degrees.
    type Set = fn(&mut SimParams, f32);
    let ranges: [(&str, Set, f32, f32); 7] = [
        ("damping", |p, v| p.damping = v, 0.0, 1.0),
        ("global stiffness", |p, v| p.global_stiffness = v, 0.0, 1.0),
        ("global range", |p, v| p.global_range = v, 0.0, 1.0),
        ("local stiffness", |p, v| p.local_stiffness = v, 0.0, 1.0),
        ("wind cone angle", |p, v| p.wind_cone_deg = v, 0.0, 90.0),
        ("collision margin", |p, v| p.collision_margin = v, 0.0, 1.0),
        ("friction", |p, v| p.friction = v, 0.0, 1.0),
    ];
    for (name, set, lo, hi) in ranges {
        for v in [lo, hi, 0.5 * (lo + hi)] {
            let mut p = ok.clone();
            set(&mut p, v);
            accepted(p);
        }
        for v in [lo - 1e-3, hi + 1e-3, f32::NAN, f32::INFINITY] {
            let mut p = ok.clone();
            set(&mut p, v);
            refused(p, name);
        }
    }
    // Counts: substeps 1..=64, iterations 0..=64.
    type Count = fn(&mut SimParams, u32);
    let counts: [(&str, Count, u32); 3] = [
        ("substeps", |p, v| p.substeps = v, 1),
        ("local iterations", |p, v| p.local_iterations = v, 0),
        ("length iterations", |p, v| p.length_iterations = v, 0),
    ];
    for (name, set, lo) in counts {
        for v in [lo, 64] {
            let mut p = ok.clone();
            set(&mut p, v);
            accepted(p);
        }
        let mut p = ok.clone();
        set(&mut p, 65);
        refused(p, name);
        if lo > 0 {
            let mut p = ok.clone();
            set(&mut p, lo - 1);
            refused(p, name);
        }
    }
    // The distance field: 0 (from the model) or 8..=128 cells.
    for cells in [0, 8, 128] {
        accepted(SimParams {
            sdf_resolution: cells,
            ..ok.clone()
        });
    }
    for cells in [1, 7, 129] {
        refused(
            SimParams {
                sdf_resolution: cells,
                ..ok.clone()
            },
            "resolution",
        );
    }
    // Forces: finite, at most 1e5.
    for (name, set) in [
        (
            "gravity",
            (|p, v| p.gravity = v) as fn(&mut SimParams, Vec3),
        ),
        ("wind", |p, v| p.wind = v),
    ] {
        for v in [Vec3::new(0.0, -1e5, 0.0), Vec3::new(6e4, 0.0, 8e4)] {
            let mut p = ok.clone();
            set(&mut p, v);
            accepted(p);
        }
        for v in [
            Vec3::new(0.0, -1.001e5, 0.0),
            Vec3::new(7e4, 0.0, 8e4),
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::new(0.0, 0.0, f32::INFINITY),
        ] {
            let mut p = ok.clone();
            set(&mut p, v);
            refused(p, name);
        }
    }
    // Derived quantities.
    let p = SimParams {
        dt: 0.02,
        substeps: 4,
        ..ok.clone()
    };
    assert_eq!(p.substep_dt(), f64::from(0.02f32) / 4.0);
    assert_eq!(ok.substep_dt(), f64::from(1.0f32 / 60.0));
    // Cells: as set, or on a rigid body ⌈3 × extent / hair⌉ clamped to 16..=128.
    assert_eq!(
        SimParams {
            sdf_resolution: 40,
            ..ok.clone()
        }
        .sdf_cells(2.0, 0.1, false),
        40
    );
    assert_eq!(ok.sdf_cells(2.0, 0.1, false), 60);
    assert_eq!(ok.sdf_cells(2.0, 0.13, false), 47);
    assert_eq!(ok.sdf_cells(2.0, 1.0, false), 16);
    assert_eq!(ok.sdf_cells(2.0, 0.001, false), 128);
    assert_eq!(ok.sdf_cells(2.0, 0.0, false), 128);
    // A skinned body: ⌈6 × extent / hair⌉, the set resolution still first.
    assert_eq!(ok.sdf_cells(2.0, 0.1, true), 120);
    assert_eq!(ok.sdf_cells(2.0, 0.2, true), 60);
    assert_eq!(ok.sdf_cells(2.0, 1.0, true), 16);
    assert_eq!(
        SimParams {
            sdf_resolution: 40,
            ..ok.clone()
        }
        .sdf_cells(2.0, 0.1, true),
        40
    );
    // Global cutoff: the first ⌊range × (V − 1)⌋ vertices after the root; none
    // without global stiffness.
    let cutoff = |stiffness: f32, range: f32, vertices: u32| {
        SimParams {
            global_stiffness: stiffness,
            global_range: range,
            ..ok.clone()
        }
        .global_cutoff(vertices)
    };
    assert_eq!(cutoff(0.2, 1.0, 17), 16);
    assert_eq!(cutoff(0.2, 0.5, 17), 8);
    assert_eq!(cutoff(0.2, 0.3, 11), 3);
    assert_eq!(cutoff(0.2, 0.0, 17), 0);
    assert_eq!(cutoff(0.0, 1.0, 17), 0);
    assert_eq!(cutoff(1.0, 1.0, 2), 1);
    // Wind: on exactly when not zero.
    assert!(!ok.wind_enabled());
    assert!(SimParams {
        wind: Vec3::new(0.0, 0.0, 1e-6),
        ..ok
    }
    .wind_enabled());
}

/// The reference's small linear algebra against values worked out by hand: it runs
/// both sides of every parity test (the f64 oracle included), so nothing else can.
#[test]
fn the_reference_maths_is_the_textbook_maths() {
    use fur::sim::{M3, V3};
    let a = V3::<f64>(1.0, -2.0, 3.0);
    let b = V3::<f64>(-4.0, 0.5, 2.0);
    assert_eq!(a + b, V3(-3.0, -1.5, 5.0));
    assert_eq!(a - b, V3(5.0, -2.5, 1.0));
    assert_eq!(a.dot(b), -4.0 - 1.0 + 6.0);
    assert_eq!(a.scale(-2.0), V3(-2.0, 4.0, -6.0));
    assert_eq!(V3::<f64>(2.0, 3.0, 6.0).length(), 7.0);
    assert_eq!(V3::<f32>(2.0, 3.0, 6.0).length(), 7.0);
    assert_eq!(V3::<f64>::ZERO, V3(0.0, 0.0, 0.0));
    assert!(a.is_finite());
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(!V3(1.0, bad, 0.0).is_finite());
        assert!(!V3(bad, 0.0, 0.0).is_finite());
        assert!(!V3(0.0, 0.0, bad).is_finite());
        assert!(!V3::<f32>(0.0, 0.0, bad as f32).is_finite());
    }
    assert_eq!(
        V3::<f32>::from_vec3(Vec3::new(0.5, 1.5, -2.0)),
        V3(0.5, 1.5, -2.0)
    );
    assert_eq!(V3::<f64>(0.1, 0.2, 0.3).to_vec3(), Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(V3::<f64>::from_vec3(Vec3::X).to_vec3(), Vec3::X);
    assert_eq!(<f32 as Real>::from_f64(0.1), 0.1f32);
    assert_eq!(<f64 as Real>::from_f32(0.1), f64::from(0.1f32));
    assert_eq!(<f64 as Real>::from_f64(0.1), 0.1);
    assert_eq!(<f32 as Real>::from_f32(0.1), 0.1);
    assert_eq!(Real::to_f64(0.25f32), 0.25);
    assert_eq!(Real::to_f64(0.25f64), 0.25);
    assert_eq!(Real::sqrt(2.25f32), 1.5);
    assert_eq!(Real::sqrt(2.25f64), 1.5);
    // A matrix by columns: m = [[1, 2, 3], [4, 5, 6], [7, 8, 10]] (rows).
    let m = M3::<f64>([V3(1.0, 4.0, 7.0), V3(2.0, 5.0, 8.0), V3(3.0, 6.0, 10.0)]);
    let v = V3(1.0, -1.0, 2.0);
    assert_eq!(
        m.mul_vec(v),
        V3(1.0 - 2.0 + 6.0, 4.0 - 5.0 + 12.0, 7.0 - 8.0 + 20.0)
    );
    assert_eq!(
        m.transpose_mul_vec(v),
        V3(1.0 - 4.0 + 14.0, 2.0 - 5.0 + 16.0, 3.0 - 6.0 + 20.0)
    );
    let n = M3::<f64>([V3(0.0, 1.0, 0.0), V3(-1.0, 0.0, 0.0), V3(0.0, 0.0, 2.0)]);
    // (m n) e_j = m (n e_j).
    let mn = m.mul_mat(&n);
    for (column, e) in [V3(1.0, 0.0, 0.0), V3(0.0, 1.0, 0.0), V3(0.0, 0.0, 1.0)]
        .into_iter()
        .enumerate()
    {
        assert_eq!(mn.0[column], m.mul_vec(n.mul_vec(e)));
    }
    assert_eq!(mn.0[0], V3(2.0, 5.0, 8.0));
    assert_eq!(mn.0[1], V3(-1.0, -4.0, -7.0));
    assert_eq!(mn.0[2], V3(6.0, 12.0, 20.0));
    // The rotation taking x to u along the shortest arc: x ↦ u, the axis x × u fixed,
    // orthonormal with determinant 1; a half turn about z for u = −x.
    for u in [
        V3(0.0, 1.0, 0.0),
        V3(0.0, 0.0, -1.0),
        V3(0.6, 0.0, 0.8),
        V3(0.36, 0.48, 0.8),
        V3(-0.6, -0.8, 0.0),
        V3(-0.9998, 0.02, 0.0),
        V3(1.0, 0.0, 0.0),
    ] {
        let u = u.scale(1.0 / u.length());
        let r = M3::<f64>::rotation_from_x(u);
        let x = r.mul_vec(V3(1.0, 0.0, 0.0));
        assert!((x - u).length() < 1e-9, "{u:?}: x goes to {x:?}");
        let axis = V3(0.0, -u.2, u.1);
        if axis.length() > 1e-9 {
            assert!(
                (r.mul_vec(axis) - axis).length() < 1e-9,
                "{u:?}: the axis moves"
            );
        }
        let [c0, c1, c2] = r.0;
        for (p, q, want) in [
            (c0, c0, 1.0),
            (c1, c1, 1.0),
            (c2, c2, 1.0),
            (c0, c1, 0.0),
            (c0, c2, 0.0),
            (c1, c2, 0.0),
        ] {
            assert!((p.dot(q) - want).abs() < 1e-9, "{u:?}: not orthonormal");
        }
        let cross = V3(
            c0.1 * c1.2 - c0.2 * c1.1,
            c0.2 * c1.0 - c0.0 * c1.2,
            c0.0 * c1.1 - c0.1 * c1.0,
        );
        assert!((cross - c2).length() < 1e-9, "{u:?}: a reflection");
    }
    let half = M3::<f64>::rotation_from_x(V3(-1.0, 0.0, 0.0));
    assert_eq!(
        half,
        M3([V3(-1.0, 0.0, 0.0), V3(0.0, -1.0, 0.0), V3(0.0, 0.0, 1.0)])
    );
    // Just inside the half-turn branch's threshold: still exact.
    let near = M3::<f32>::rotation_from_x(V3(-0.999_95, 0.01, 0.0));
    assert_eq!(near.0[0], V3(-1.0, 0.0, 0.0));
}

/// Three bent strands of four segments of 0.1 each, rooted apart (written by hand, so a
/// wrong strand or vertex index lands on a different point).
fn bent_strands() -> Strands {
    let mut positions = Vec::new();
    for s in 0..3 {
        let s = s as f32;
        let mut p = Vec3::new(0.3 * s, -0.2 * s, 0.1 * s);
        positions.push(p);
        for k in 0..4 {
            p += 0.1 * Vec3::new(0.2 * k as f32, 1.0, 0.1 * s).normalize();
            positions.push(p);
        }
    }
    Strands {
        vertices_per_strand: 5,
        positions,
    }
}

/// Every strand's root pose at rest: no turn, the root where it grew.
fn held_roots(strands: &Strands) -> Vec<RootPose> {
    (0..strands.count())
        .map(|s| RootPose {
            rotation: glam::Mat3::IDENTITY,
            root: strands.strand(s)[0],
        })
        .collect()
}

/// A posed body of `roots` and `capsules`, whose bind-pose capsules are `rest`.
fn posed_from(
    roots: Vec<RootPose>,
    capsules: Vec<[glam::Vec4; 2]>,
    rest: Vec<[glam::Vec4; 2]>,
) -> Posed {
    Posed {
        positions: Vec::new(),
        normals: Vec::new(),
        roots,
        capsules,
        rest_capsules: rest,
    }
}

/// A posed body of `roots` and `capsules` that moved far (10 units along z) from the
/// bind pose, relative to every root: each capsule at its full radius.
fn posed(roots: Vec<RootPose>, capsules: Vec<[glam::Vec4; 2]>) -> Posed {
    let rest = capsules
        .iter()
        .map(|c| c.map(|p| p - glam::Vec4::new(0.0, 0.0, 10.0, 0.0)))
        .collect();
    posed_from(roots, capsules, rest)
}

/// Every strand turning about its own root at its own rate about a fixed axis while its
/// root travels at (3, 0, −1) per second: at `t` = 0 the rest pose.
fn turning(strands: &Strands, t: f64) -> Posed {
    let axis = Vec3::new(1.0, 2.0, 2.0) / 3.0;
    let roots = (0..strands.count())
        .map(|s| RootPose {
            rotation: glam::Mat3::from_axis_angle(axis, (20.0 * t) as f32 * (1 + s) as f32),
            root: strands.strand(s)[0] + Vec3::new(3.0, 0.0, -1.0) * t as f32,
        })
        .collect();
    posed(roots, Vec::new())
}

/// A simulation position as a glam vector, with no rounding.
fn dvec(p: V3<f64>) -> glam::DVec3 {
    glam::DVec3::new(p.0, p.1, p.2)
}

/// `x ↦ rotation · (x − rest root) + root`, in f64 from the pose's f32 numbers.
fn carried(pose: &RootPose, rest_root: Vec3, x: Vec3) -> glam::DVec3 {
    pose.rotation.as_dmat3() * (x.as_dvec3() - rest_root.as_dvec3()) + pose.root.as_dvec3()
}

/// On a skinned body whose strands' root poses turn and travel fast (a third of a radian
/// and 5 cm a frame, with hair 0.4 long), weightless hair at rest rides along with its
/// pose: every vertex stays on its carried rest position (within 1e-5 of the hair
/// length), with no lag from the motion; the poses are asked for at the end of every
/// substep, `n h` after the start, and the simulation's clock says the same.
#[test]
fn resting_hair_rides_along_with_a_moving_skinned_body() {
    let strands = bent_strands();
    let params = SimParams {
        substeps: 3,
        gravity: Vec3::ZERO,
        collision: false,
        ..SimParams::default()
    };
    let h = params.substep_dt();
    let asked = RefCell::new(Vec::new());
    let poses_at = |t: f64| {
        asked.borrow_mut().push(t);
        turning(&strands, t)
    };
    let mut sim = CpuSim::<f64>::new(&strands, params.clone(), DMat4::IDENTITY);
    sim.place(DMat4::IDENTITY, Some(&turning(&strands, 0.0).roots));
    let length = f64::from(strands.hair_length());
    let v = 5;
    let (mut time, mut times) = (0.0f64, Vec::new());
    for frame in 1..=12 {
        sim.step_frame_posed(still, poses_at);
        for _ in 0..params.substeps {
            time += h;
            times.push(time);
        }
        assert_eq!(*asked.borrow(), times, "frame {frame}: the substeps' times");
        assert_eq!(sim.time, time, "frame {frame}: the clock");
        let pose = turning(&strands, time);
        for s in 0..strands.count() {
            let rest = strands.strand(s);
            for i in 0..v {
                let want = carried(&pose.roots[s], rest[0], rest[i]);
                let error = (dvec(sim.current[s * v + i]) - want).length();
                assert!(
                    error <= 1e-5 * length,
                    "frame {frame}, strand {s}, vertex {i}: {error} off its carried rest position"
                );
            }
        }
    }
    // The body really moved: every tip travelled more than half the hair's length.
    for s in 0..strands.count() {
        let travelled =
            (dvec(sim.current[s * v + v - 1]) - strands.strand(s)[4].as_dvec3()).length();
        assert!(
            travelled > 0.5 * length,
            "strand {s}: the tip moved {travelled}"
        );
    }
}

/// A skinned body held at its rest pose (every root pose the identity about its own rest
/// root) simulates exactly as the rigid body does, under gravity and wind, without a
/// placement first (the first posed substep starts from the poses it is given).
#[test]
fn a_skinned_body_held_at_rest_simulates_as_the_rigid_body() {
    let strands = bent_strands();
    let params = SimParams {
        substeps: 2,
        wind: Vec3::new(2.0, 0.0, 1.0),
        collision: false,
        ..SimParams::default()
    };
    let held = posed(held_roots(&strands), Vec::new());
    let mut rigid = CpuSim::<f64>::new(&strands, params.clone(), DMat4::IDENTITY);
    let mut skinned = CpuSim::<f64>::new(&strands, params, DMat4::IDENTITY);
    let length = f64::from(strands.hair_length());
    for frame in 0..20 {
        rigid.step_frame(still);
        skinned.step_frame_posed(still, |_| held.clone());
        for (what, a, b) in [
            ("current", &rigid.current, &skinned.current),
            ("previous", &rigid.previous, &skinned.previous),
        ] {
            for (i, (a, b)) in a.iter().zip(b).enumerate() {
                let error = (*a - *b).length();
                assert!(
                    error <= 1e-12 * length,
                    "frame {frame}, {what} vertex {i}: {error}"
                );
            }
        }
    }
    let fell = (rigid.current[4] - V3::from_vec3(strands.positions[4])).length();
    assert!(fell > 1e-3 * length, "nothing moved ({fell})");
}

/// Placing puts every vertex (root included) of every strand on its rest position
/// carried by its own root pose and then the head transform, not moving; without poses,
/// on its rest position carried by the head transform.
#[test]
fn placing_puts_every_strand_on_its_posed_rest_shape() {
    let strands = bent_strands();
    let mut sim = CpuSim::<f64>::new(&strands, SimParams::default(), DMat4::IDENTITY);
    let head = DMat4::from_rotation_translation(
        glam::DQuat::from_rotation_z(0.4),
        glam::DVec3::new(0.5, -1.0, 2.0),
    );
    // The simulation holds the head transform in f32.
    let head32 = head.as_mat4().as_dmat4();
    let poses: Vec<RootPose> = (0..strands.count())
        .map(|s| RootPose {
            rotation: glam::Mat3::from_axis_angle(Vec3::new(0.0, 0.6, 0.8), 0.5 + 0.7 * s as f32),
            root: Vec3::new(1.0 + s as f32, 2.0, -(s as f32)),
        })
        .collect();
    let v = 5;
    let check = |sim: &CpuSim<f64>, want: &dyn Fn(usize, usize) -> glam::DVec3, what: &str| {
        for s in 0..strands.count() {
            for i in 0..v {
                let at = dvec(sim.current[s * v + i]);
                let error = (at - want(s, i)).length();
                assert!(
                    error < 1e-9,
                    "{what}: strand {s}, vertex {i} off by {error}"
                );
                assert_eq!(
                    sim.previous[s * v + i],
                    sim.current[s * v + i],
                    "{what}: moving"
                );
            }
        }
    };
    sim.place(head, Some(&poses));
    check(
        &sim,
        &|s, i| {
            let rest = strands.strand(s);
            head32.transform_point3(carried(&poses[s], rest[0], rest[i]))
        },
        "posed",
    );
    assert_eq!(sim.last_poses, poses);
    sim.place(head, None);
    check(
        &sim,
        &|s, i| head32.transform_point3(strands.strand(s)[i].as_dvec3()),
        "rigid",
    );
}

/// The field of the half-space y < 0 (distance y, gradient +y) on a grid over [−2, 2]³:
/// sampled exactly, so the collision step's result can be written down.
fn floor_field() -> Sdf {
    let n = 17u32;
    let cell = 0.25f32;
    let mut values = Vec::new();
    for _z in 0..n {
        for y in 0..n {
            for _x in 0..n {
                values.push(-2.0 + cell * y as f32);
            }
        }
    }
    Sdf {
        dims: [n; 3],
        origin: Vec3::splat(-2.0),
        cell,
        gradients: vec![Vec3::Y; values.len()],
        values,
    }
}

/// Two straight upright strands, 0.4 and 0.2 long (four segments each), rooted at
/// (0, 0.5, 0) and (0.5, 0.5, 0.5).
fn upright_strands() -> Strands {
    let mut positions = Vec::new();
    for (root, segment) in [(Vec3::new(0.0, 0.5, 0.0), 0.1), (Vec3::splat(0.5), 0.05)] {
        for k in 0..5 {
            positions.push(root + Vec3::Y * (segment * k as f32));
        }
    }
    Strands {
        vertices_per_strand: 5,
        positions,
    }
}

/// Parameters under which a substep moves nothing but by collision: no gravity, no
/// constraint, no wind, no friction.
fn collision_only(margin: f32) -> SimParams {
    SimParams {
        gravity: Vec3::ZERO,
        global_stiffness: 0.0,
        local_stiffness: 0.0,
        local_iterations: 0,
        length_iterations: 0,
        collision: true,
        collision_margin: margin,
        friction: 0.0,
        ..SimParams::default()
    }
}

/// The collision margin is the fraction `collision_margin` of each strand's own rest
/// length: vertices below it (inside the body or too close to it) end exactly on it
/// (0.25 × 0.4 = 0.1 for one strand, 0.25 × 0.2 = 0.05 for the other), straight out
/// along the field's gradient; a vertex farther out does not move.
#[test]
fn collision_pushes_vertices_to_a_margin_of_each_strands_own_length() {
    let strands = upright_strands();
    let mut sim = CpuSim::<f64>::new(&strands, collision_only(0.25), DMat4::IDENTITY)
        .with_sdf(Arc::new(floor_field()));
    // Strand by strand, vertices 1 to 4: inside, inside, within the margin, far out.
    let placed = |x: f64, z: f64| {
        [
            (0.1, -0.3, 0.0),
            (0.2, -0.02, 0.1),
            (-0.1, 0.04, 0.2),
            (0.3, 0.3, -0.1),
        ]
        .map(|(dx, y, dz)| V3(x + dx, y, z + dz))
    };
    let v = 5;
    for (s, (x, z)) in [(0.0, 0.0), (0.5, 0.5)].into_iter().enumerate() {
        for (k, p) in placed(x, z).into_iter().enumerate() {
            sim.current[s * v + 1 + k] = p;
            sim.previous[s * v + 1 + k] = p;
        }
    }
    sim.step_frame(still);
    for (s, ((x, z), margin)) in [((0.0, 0.0), 0.1), ((0.5, 0.5), 0.05)]
        .into_iter()
        .enumerate()
    {
        for (k, p) in placed(x, z).into_iter().enumerate() {
            let want = if k == 3 { p } else { V3(p.0, margin, p.2) };
            let got = sim.current[s * v + 1 + k];
            assert!(
                // The strands' lengths are sums of f32 segments.
                (got - want).length() < 1e-6,
                "strand {s}, vertex {}: {got:?}, not {want:?}",
                k + 1
            );
        }
    }
}

/// Axis along z through (0.65, 0.5), radius 0.2: its surface is 0.45 from the root of the
/// first upright strand, between the strand's length less its margin and its length
/// plus it.
const CAPSULE: [glam::Vec4; 2] = [
    glam::Vec4::new(0.65, 0.5, -1.0, 0.2),
    // No child capsule.
    glam::Vec4::new(0.65, 0.5, 1.0, -1.0),
];

/// The first upright strand alone (0.4 long), laid along −x but for its tip, 0.05 from
/// [`CAPSULE`]'s axis, over a floor field far below, stepped one frame on the body
/// `held` with only collision (margin 0.25 of the length): its positions before, and
/// after.
fn capsule_step(held: impl Fn(&Strands) -> Posed) -> (Vec<V3<f64>>, Vec<V3<f64>>) {
    let strands = Strands {
        vertices_per_strand: 5,
        positions: upright_strands().positions[..5].to_vec(),
    };
    let mut sim = CpuSim::<f64>::new(&strands, collision_only(0.25), DMat4::IDENTITY)
        .with_sdf(Arc::new(floor_field()));
    let placed = [
        V3(-0.1, 0.5, 0.0),
        V3(-0.2, 0.5, 0.0),
        V3(-0.3, 0.5, 0.0),
        V3(0.7, 0.5, 0.0),
    ];
    for (k, p) in placed.into_iter().enumerate() {
        sim.current[1 + k] = p;
        sim.previous[1 + k] = p;
    }
    let before = sim.current.clone();
    let held = held(&strands);
    sim.step_frame_posed(still, |_| held.clone());
    (before, sim.current)
}

/// On a skinned body, a strand collides with a bone's capsule whose surface lies within
/// its length plus its margin of its root: a capsule 0.45 from the root of a strand 0.4
/// long with a margin of 0.1 pushes a vertex inside it out radially to 0.1 off its
/// surface; the distance field (far below) moves nothing.
#[test]
fn a_capsule_within_reach_of_the_root_pushes_vertices_out() {
    let (before, after) = capsule_step(|strands| posed(held_roots(strands), vec![CAPSULE]));
    for (i, (got, was)) in after.iter().zip(&before).enumerate() {
        let want = if i == 4 {
            // Out along +x to the radius plus the margin (in f32, as the capsule is).
            V3(f64::from(0.65f32) + f64::from(0.2f32) + 0.1, 0.5, 0.0)
        } else {
            *was
        };
        assert!(
            (*got - want).length() < 1e-7,
            "vertex {i}: {got:?}, not {want:?}"
        );
    }
}

/// A capsule counts only as far as its bone moved relative to the strand's root pose
/// (the rest field carried by that pose holds the rest): [`CAPSULE`], with the strand's
/// tip vertex inside it, leaves the strand alone where it sits at its bind-pose place,
/// and pushes the tip out to 4/5 of its radius plus the margin when it moved by a fifth
/// of the strand's length (4/5 of the way to its full radius, reached at a quarter).
#[test]
fn a_capsule_counts_as_far_as_its_bone_moved_relative_to_the_root() {
    let length = 0.4;
    // The bind-pose capsule, carried by the held roots (the identity), lies `shift` along
    // +x of where the capsule is now (along its own axis would not move it).
    let tip = |shift: f32| {
        let rest = vec![CAPSULE.map(|p| p + glam::Vec4::new(shift, 0.0, 0.0, 0.0))];
        capsule_step(|strands| posed_from(held_roots(strands), vec![CAPSULE], rest.clone())).1[4]
    };
    let unmoved = tip(0.0);
    assert!(
        (unmoved - V3(0.7, 0.5, 0.0)).length() < 1e-7,
        "a capsule where the root pose carries it pushed the tip to {unmoved:?}"
    );
    let most = tip(0.2 * length as f32);
    // 4/5 of the radius plus the margin (0.25 × 0.4) off the axis at x = 0.65.
    let want = f64::from(0.65f32) + 0.8 * f64::from(0.2f32) + 0.25 * length;
    assert!(
        (most.0 - want).abs() < 1e-6 && (most.1 - 0.5).abs() < 1e-7,
        "capsule moved by a fifth of the length: tip at {most:?}, not x = {want}"
    );
}

/// The skin at a capsule's far end bends with its child bone, so the child's motion
/// counts for it: [`CAPSULE`] where the root pose carries it, its tip vertex inside,
/// pushes the tip out to its full radius plus the margin once its child (a capsule out
/// of the strand's reach) moved by half the strand's length, and leaves it alone
/// without that link.
#[test]
fn a_capsule_counts_as_far_as_its_child_bone_moved() {
    let far = [
        glam::Vec4::new(50.0, 0.5, -1.0, 0.2),
        glam::Vec4::new(50.0, 0.5, 1.0, -1.0),
    ];
    let moved = far.map(|p| p + glam::Vec4::new(0.2, 0.0, 0.0, 0.0));
    let tip = |child: f32| {
        let mut capsule = CAPSULE;
        capsule[1].w = child;
        let (posed, rest) = (vec![capsule, moved], vec![capsule, far]);
        capsule_step(|strands| posed_from(held_roots(strands), posed.clone(), rest.clone())).1[4]
    };
    let linked = tip(1.0);
    let want = f64::from(0.65f32) + f64::from(0.2f32) + 0.1;
    assert!(
        (linked.0 - want).abs() < 1e-6 && (linked.1 - 0.5).abs() < 1e-7,
        "the child moved: tip at {linked:?}, not x = {want}"
    );
    let alone = tip(-1.0);
    assert!(
        (alone - V3(0.7, 0.5, 0.0)).length() < 1e-7,
        "without the child the tip moved to {alone:?}"
    );
}

/// A capsule pushes a vertex `s` along the hair from its root no farther from its axis
/// than the root's distance plus `s`, as far as the vertex can get while attached: with
/// the root 0.15 inside a capsule of radius 0.3, the first vertex (0.1 along) goes out
/// to 0.15 + 0.1 plus the margin, the second (0.2 along) to the full radius plus the
/// margin, and the tip, out of reach, stays.
#[test]
fn a_capsule_holding_the_root_pushes_the_first_vertices_only_as_far_as_they_reach() {
    let capsule = [
        glam::Vec4::new(-0.15, 0.5, -1.0, 0.3),
        glam::Vec4::new(-0.15, 0.5, 1.0, -1.0),
    ];
    let (before, after) = capsule_step(|strands| posed(held_roots(strands), vec![capsule]));
    let axis = f64::from(-0.15f32);
    let first = axis + (-axis + 0.1) + 0.1;
    let full = axis - f64::from(0.3f32) - 0.1;
    for (i, want) in [(1, first), (2, full), (3, full), (4, before[4].0)] {
        assert!(
            (after[i].0 - want).abs() < 1e-6 && (after[i].1 - 0.5).abs() < 1e-7,
            "vertex {i} at {:?}, not x = {want}",
            after[i]
        );
    }
}

/// Parameters under which a substep moves nothing but by the local shape constraint,
/// at `stiffness` with `passes` walks.
fn local_only(stiffness: f32, passes: u32) -> SimParams {
    SimParams {
        gravity: Vec3::ZERO,
        global_stiffness: 0.0,
        local_stiffness: stiffness,
        local_iterations: passes,
        length_iterations: 0,
        collision: false,
        // No velocity is kept from one substep to the next.
        damping: 1.0,
        ..SimParams::default()
    }
}

/// A turned and moved head: 0.7 rad about (1, 2, 2)/3, then (0.3, −0.2, 0.5).
fn turned_head() -> DMat4 {
    DMat4::from_rotation_translation(
        glam::DQuat::from_axis_angle(glam::DVec3::new(1.0, 2.0, 2.0) / 3.0, 0.7),
        glam::DVec3::new(0.3, -0.2, 0.5),
    )
}

/// The local shape constraint alone, at full stiffness and walked often enough (and
/// with no velocity kept), returns bent strands pushed out of shape to their rest shape carried by the (turned
/// and moved) head, each segment in its parent's frame as at rest; the roots do not
/// move.
#[test]
fn the_local_constraint_restores_the_rest_shape_in_the_heads_frame() {
    let strands = bent_strands();
    let head = turned_head();
    let mut sim = CpuSim::<f64>::new(&strands, local_only(1.0, 64), head);
    let v = 5;
    for (i, (x, p)) in sim.current.iter_mut().zip(&mut sim.previous).enumerate() {
        if i % v != 0 {
            let k = i as f64;
            *x = *x
                + V3(
                    0.03 * k.sin(),
                    0.05 * (k * 1.3).cos(),
                    -0.04 * (k * 0.7).sin(),
                );
            *p = *x;
        }
    }
    // The walk converges geometrically (by about 0.87 a pass here): 640 passes.
    for _ in 0..10 {
        sim.step_frame(|_| head);
    }
    // Down to the rounding of the head transform, held in f32.
    let head32 = head.as_mat4().as_dmat4();
    for (i, x) in sim.current.iter().enumerate() {
        let want = head32.transform_point3(strands.positions[i].as_dvec3());
        let error = (dvec(*x) - want).length();
        assert!(
            error < 1e-7,
            "strand {}, vertex {}: {error} from its rest position",
            i / v,
            i % v
        );
    }
}

/// One walk at half stiffness over a strand of one segment moves its tip exactly
/// halfway from where it is to its rest position carried by the head.
#[test]
fn half_local_stiffness_moves_a_segment_halfway_to_rest() {
    let rest = [Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.15, 0.3, 0.25)];
    let strands = Strands {
        vertices_per_strand: 2,
        positions: rest.to_vec(),
    };
    let head = turned_head();
    let mut sim = CpuSim::<f64>::new(&strands, local_only(0.5, 1), head);
    let pushed = sim.current[1] + V3(0.02, -0.03, 0.01);
    sim.current[1] = pushed;
    sim.previous[1] = pushed;
    sim.step_frame(|_| head);
    let head32 = head.as_mat4().as_dmat4();
    let at_rest = head32.transform_point3(rest[1].as_dvec3());
    let want = 0.5 * (dvec(pushed) + at_rest);
    let error = (dvec(sim.current[1]) - want).length();
    // Within the rounding of the head transform, held in f32.
    assert!(error < 1e-8, "{error}");
    let root = head32.transform_point3(rest[0].as_dvec3());
    assert!((dvec(sim.current[0]) - root).length() < 1e-12);
}

/// The local shape constraint keeps each segment's shape relative to its parent: a
/// straight strand turned rigidly by 90° about its root (so its shape is intact, only
/// its direction is off) is pulled back by one walk at half stiffness with its segments
/// still nearly in line (every bend under 20°; each segment follows its parent's new
/// direction), not each segment turned on its own towards its rest direction (which
/// bends it by some 40°).
#[test]
fn the_local_constraint_keeps_shape_relative_to_the_parent_segment() {
    let strands = Strands {
        vertices_per_strand: 4,
        positions: (0..4).map(|k| Vec3::X * (0.1 * k as f32)).collect(),
    };
    let mut sim = CpuSim::<f64>::new(&strands, local_only(0.5, 1), DMat4::IDENTITY);
    for k in 1..4 {
        sim.current[k] = V3(0.0, 0.1 * k as f64, 0.0);
        sim.previous[k] = sim.current[k];
    }
    sim.step_frame(still);
    let x: Vec<glam::DVec3> = sim.current.iter().map(|p| dvec(*p)).collect();
    // It did turn back towards +x (16° at the root).
    assert!(x[1].x > 0.01, "{x:?}");
    for k in 1..3 {
        let bend = (x[k] - x[k - 1])
            .angle_between(x[k + 1] - x[k])
            .to_degrees();
        assert!(bend < 20.0, "bent by {bend}° at vertex {k}: {x:?}");
    }
}
