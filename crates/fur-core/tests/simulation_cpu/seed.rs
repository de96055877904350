//! The step constants, free fall and head motions against the seed's equations and
//! hand-written values.

use super::*;

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
