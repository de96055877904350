//! Parameter ranges and the reference's small linear algebra against hand-worked values.

use super::*;

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
    use fur_core::sim::{M3, V3};
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
