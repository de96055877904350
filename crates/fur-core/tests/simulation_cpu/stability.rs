//! Numerical stability across a matrix of extreme parameters, collision included.

use super::*;

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
        let (sdf, _) = fur_core::sim::Sdf::build(&mesh, 128, hair.min(0.5)).unwrap();
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
                let exact = fur_core::sim::sdf::exact_distances(&mesh, &model);
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
