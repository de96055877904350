use super::*;

#[test]
fn an_unshifted_lobe_is_plain_kajiya_kay() {
    let lighting = Lighting {
        highlights: Highlights {
            secondary: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let t = Vec3::new(0.2, 0.9, 0.1).normalize();
    let l = Vec3::new(0.6, 0.3, 0.7).normalize();
    let e = Vec3::new(-0.3, -0.2, -0.9).normalize();
    let s = kajiya_kay(t, l, e, &lighting);
    let (tl, te) = (t.dot(l), t.dot(e));
    let plain = (tl * te + (1.0 - tl * tl).sqrt() * (1.0 - te * te).sqrt()).powf(40.0);
    assert!((s.specular - 0.35 * plain).abs() < 1e-6);
    assert_eq!(s.tinted, 0.0);
}

#[test]
fn a_shifted_lobe_peaks_where_the_view_angle_is_the_light_angle_plus_the_shift() {
    let t = Vec3::Y;
    let l = Vec3::new(1.0, 1.0, 0.0).normalize(); // 45° from the tangent
    let shift = 10f32.to_radians();
    let best = (0..=1800)
        .map(|i| (i as f32 * 0.1).to_radians())
        .max_by(|a, b| {
            let at = |th: f32| {
                let e = Vec3::new(-th.sin(), th.cos(), 0.0);
                let te = t.dot(e);
                lobe(
                    t.dot(l),
                    0.5f32.sqrt(),
                    te,
                    (1.0 - te * te).sqrt(),
                    shift,
                    50.0,
                )
            };
            at(*a).total_cmp(&at(*b))
        })
        .unwrap();
    assert!(
        (best.to_degrees() - 55.0).abs() < 0.2,
        "{}",
        best.to_degrees()
    );
}

/// The unit vector at `degrees` from the tangent +y, in the x–y plane (the lobes
/// depend on the angles from the tangent alone).
fn at(degrees: f32) -> Vec3 {
    let a = degrees.to_radians();
    Vec3::new(a.sin(), a.cos(), 0.0)
}

fn close(a: f32, b: f32, what: &str) {
    assert!(
        (a - b).abs() <= 1e-5 * b.abs().max(1e-3),
        "{what}: {a}, not {b}"
    );
}

/// The diffuse term is K_d times the sine of the angle between tangent and light:
/// K_d across the hair, K_d / 2 at 30°, K_d · √3/2 at 120°, nothing along it.
#[test]
fn diffuse_is_kd_times_the_sine_of_the_light_angle() {
    let lighting = Lighting {
        kd: 0.7,
        ..Default::default()
    };
    for (degrees, sine) in [
        (90.0, 1.0),
        (30.0, 0.5),
        (120.0, 0.75f32.sqrt()),
        (0.0, 0.0),
    ] {
        let s = kajiya_kay(Vec3::Y, at(degrees), at(45.0), &lighting);
        close(s.diffuse, 0.7 * sine, &format!("diffuse at {degrees}°"));
    }
}

/// With the light 60° from the tangent, the primary lobe (shift 5°, exponent 40) is
/// K_s cos(65° − θ_e)⁴⁰ for the view at θ_e from the tangent: K_s at 65°, less either
/// side, nothing where the cosine is negative (not its even power); the secondary
/// (shift −10°, exponent 10, strength 0.6) is 0.6 cos(50° − θ_e)¹⁰.
#[test]
fn the_lobes_are_shifted_cosine_powers_of_the_angles() {
    let lighting = Lighting {
        ks: 0.35,
        shininess: 40.0,
        ..Default::default()
    };
    let l = at(60.0);
    let lobe =
        |shift: f32, view: f32, p: f32| (60.0 + shift - view).to_radians().cos().max(0.0).powf(p);
    for view in [65.0, 50.0, 80.0, 30.0, 100.0, 170.0] {
        let s = kajiya_kay(Vec3::Y, l, at(view), &lighting);
        close(
            s.specular,
            0.35 * lobe(5.0, view, 40.0),
            &format!("primary at {view}°"),
        );
        close(
            s.tinted,
            0.6 * lobe(-10.0, view, 10.0),
            &format!("secondary at {view}°"),
        );
    }
    close(
        kajiya_kay(Vec3::Y, l, at(65.0), &lighting).specular,
        0.35,
        "peak",
    );
    close(
        kajiya_kay(Vec3::Y, l, at(50.0), &lighting).tinted,
        0.6,
        "peak",
    );
    assert_eq!(kajiya_kay(Vec3::Y, l, at(170.0), &lighting).specular, 0.0);
}

/// Without the secondary highlight the primary lobe is not shifted (whatever its
/// shift says): it peaks where the view angle equals the light angle.
#[test]
fn without_the_secondary_the_primary_is_unshifted() {
    let lighting = Lighting {
        ks: 0.5,
        highlights: Highlights {
            secondary: false,
            primary_shift_deg: 20.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let s = kajiya_kay(Vec3::Y, at(40.0), at(40.0), &lighting);
    close(s.specular, 0.5, "unshifted peak");
    assert_eq!(s.tinted, 0.0);
}

/// Every lighting number is accepted at both ends of its range and refused just
/// past them, and when NaN or infinite; the light direction must be finite and not
/// (nearly) zero; the shadow map's side is 16..=8192; colours are in [0, 1000].
#[test]
fn lighting_numbers_are_checked_at_their_ends() {
    type Set = fn(&mut Lighting, f32);
    let fields: [(&str, Set, f32, f32); 12] = [
        ("intensity", |l, v| l.intensity = v, 0.0, 1e3),
        ("kd", |l, v| l.kd = v, 0.0, 1e3),
        ("ks", |l, v| l.ks = v, 0.0, 1e3),
        ("ambient", |l, v| l.ambient = v, 0.0, 1e3),
        ("root occlusion", |l, v| l.root_occlusion = v, 0.0, 1.0),
        ("shininess", |l, v| l.shininess = v, 1.0, 1e4),
        (
            "primary shift",
            |l, v| l.highlights.primary_shift_deg = v,
            -45.0,
            45.0,
        ),
        (
            "secondary shift",
            |l, v| l.highlights.secondary_shift_deg = v,
            -45.0,
            45.0,
        ),
        (
            "secondary shininess",
            |l, v| l.highlights.secondary_shininess = v,
            1.0,
            1e4,
        ),
        (
            "secondary strength",
            |l, v| l.highlights.secondary_strength = v,
            0.0,
            1e3,
        ),
        ("shadow opacity", |l, v| l.shadows.opacity = v, 0.0, 1.0),
        (
            "shadow spacing",
            |l, v| l.shadows.spacing = v,
            0.0,
            f32::MAX,
        ),
    ];
    let with = |set: Set, v: f32| {
        let mut l = Lighting::default();
        set(&mut l, v);
        l
    };
    Lighting::default().validate().unwrap();
    for (name, set, lo, hi) in fields {
        for v in [lo, hi] {
            with(set, v)
                .validate()
                .unwrap_or_else(|e| panic!("{name} = {v} refused: {e}"));
        }
        let below = lo - lo.abs().max(1.0) * 1e-3;
        let above = if hi == f32::MAX {
            f32::INFINITY
        } else {
            hi + hi.abs() * 1e-3
        };
        for v in [below, above, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert!(
                matches!(with(set, v).validate(), Err(Error::Parameter(_))),
                "{name} = {v} accepted"
            );
        }
    }
    let light = |d: Vec3| Lighting {
        light_direction: d,
        ..Default::default()
    };
    light(Vec3::new(0.0, 1e-5, 0.0)).validate().unwrap();
    for d in [
        Vec3::ZERO,
        Vec3::new(0.0, 1e-7, 0.0),
        Vec3::new(f32::NAN, 1.0, 0.0),
        Vec3::new(0.0, 1.0, f32::INFINITY),
    ] {
        assert!(light(d).validate().is_err(), "light direction {d} accepted");
    }
    let resolution = |r: u32| Lighting {
        shadows: Shadows {
            resolution: r,
            ..Default::default()
        },
        ..Default::default()
    };
    resolution(16).validate().unwrap();
    resolution(Shadows::MAX_RESOLUTION).validate().unwrap();
    assert!(resolution(15).validate().is_err());
    assert!(resolution(Shadows::MAX_RESOLUTION + 1).validate().is_err());
    type Colour = fn(&mut Lighting, Vec3);
    let colours: [(&str, Colour); 3] = [
        ("root", |l, c| l.root_color = c),
        ("tip", |l, c| l.tip_color = c),
        ("skin", |l, c| l.skin_color = c),
    ];
    for (name, set) in colours {
        let with = |c: Vec3| {
            let mut l = Lighting::default();
            set(&mut l, c);
            l.validate()
        };
        with(Vec3::ZERO).unwrap();
        with(Vec3::new(1e3, 0.5, 0.0)).unwrap();
        for c in [
            Vec3::new(-0.01, 0.5, 0.5),
            Vec3::new(0.5, 1000.5, 0.5),
            Vec3::new(0.5, 0.5, f32::NAN),
            Vec3::new(f32::INFINITY, 0.5, 0.5),
        ] {
            assert!(with(c).is_err(), "{name} colour {c} accepted");
        }
    }
}

/// Hair layers per unit of depth: 1 / spacing, or with spacing 0 the hairs' own
/// spacing at the density, √density.
#[test]
fn shadow_layers_come_from_the_spacing_or_the_density() {
    let with = |spacing| Shadows {
        spacing,
        ..Shadows::default()
    };
    assert_eq!(with(0.5).layers_per_unit(9.0), 2.0);
    assert_eq!(with(0.0).layers_per_unit(9.0), 3.0);
}

/// The fibre's defaults pass; each parameter just outside its range, or NaN, is refused
/// by name.
#[test]
fn a_fibre_out_of_range_is_refused_by_name() {
    assert!(Fibre::default().validate().is_ok());
    let edges = Fibre {
        longitudinal_roughness: 0.01,
        azimuthal_roughness: 1.0,
        cuticle_tilt_deg: -10.0,
        ior: 3.0,
        direction_spread: 2.5,
    };
    assert!(edges.validate().is_ok());
    type Set = fn(&mut Fibre, f32);
    let cases: [(&str, Set, [f32; 3]); 5] = [
        (
            "longitudinal roughness",
            |f, v| f.longitudinal_roughness = v,
            [0.009, 1.01, f32::NAN],
        ),
        (
            "azimuthal roughness",
            |f, v| f.azimuthal_roughness = v,
            [0.009, 1.01, f32::NAN],
        ),
        (
            "cuticle tilt",
            |f, v| f.cuticle_tilt_deg = v,
            [-10.1, 10.1, f32::NAN],
        ),
        (
            "index of refraction",
            |f, v| f.ior = v,
            [0.99, 3.01, f32::NAN],
        ),
        (
            "direction spread",
            |f, v| f.direction_spread = v,
            [-0.01, 2.51, f32::NAN],
        ),
    ];
    for (name, set, values) in cases {
        for v in values {
            let mut fibre = Fibre::default();
            set(&mut fibre, v);
            let e = fibre.validate().unwrap_err().to_string();
            assert!(e.contains(name), "{name} = {v}: {e}");
        }
    }
}

/// Each lighting model reads back from its name; its label is its name in prose; any
/// other name is refused, listing the two.
#[test]
fn lighting_models_read_back_from_their_names() {
    for (model, name, label) in [
        (LightingModel::KajiyaKay, "kajiya-kay", "Kajiya–Kay"),
        (LightingModel::Marschner, "marschner", "Marschner"),
    ] {
        assert_eq!(model.name(), name);
        assert_eq!(model.label(), label);
        assert_eq!(name.parse::<LightingModel>(), Ok(model));
    }
    let e = "phong".parse::<LightingModel>().unwrap_err();
    assert!(
        e.contains("kajiya-kay or marschner") && e.contains("phong"),
        "{e}"
    );
}
