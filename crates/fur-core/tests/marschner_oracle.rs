//! The Marschner twin (`render::marschner`, which the shader is checked against)
//! against its oracle, the port of pbrt-v3's hair BSDF (`render::hair_oracle`), lobe by
//! lobe. CPU only.

use fur_core::render::hair_oracle::{self, lobes_over_width};
use fur_core::render::marschner::{lobes, sigma_a_from_color};
use fur_core::render::Fibre;
use glam::Vec3;

const COLOR: Vec3 = Vec3::new(0.8, 0.45, 0.2);

fn fibre(tilt_deg: f32) -> Fibre {
    rough_fibre(tilt_deg, 0.2)
}

fn rough_fibre(tilt_deg: f32, beta_m: f32) -> Fibre {
    Fibre {
        longitudinal_roughness: beta_m,
        azimuthal_roughness: 0.3,
        cuticle_tilt_deg: tilt_deg,
        ior: 1.55,
        direction_spread: fur_core::render::DIRECTION_SPREAD,
    }
}

fn oracle_fibre(f: &Fibre, color: Vec3) -> hair_oracle::Fibre {
    let sigma_a = sigma_a_from_color(color, f.azimuthal_roughness);
    hair_oracle::Fibre {
        sigma_a: sigma_a.to_array().map(f64::from),
        beta_m: f64::from(f.longitudinal_roughness),
        beta_n: f64::from(f.azimuthal_roughness),
        alpha: f64::from(f.cuticle_tilt_deg).to_radians(),
        eta: f64::from(f.ior),
    }
}

/// A direction at elevation `theta_deg` from the plane across the hair (positive towards
/// the tip, the hair along x) and azimuth `phi` about it.
fn direction(theta_deg: f64, phi: f64) -> [f64; 3] {
    let t = theta_deg.to_radians();
    [t.sin(), t.cos() * phi.cos(), t.cos() * phi.sin()]
}

fn vec3(d: [f64; 3]) -> Vec3 {
    Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32)
}

/// The outgoing elevation (degrees, to a quarter degree) at which lobe `p` peaks for
/// light arriving at elevation `theta_i` and relative azimuth `phi`, in the oracle and
/// in the twin (green channel).
fn peaks(p: usize, theta_i: f64, phi: f64, f: &Fibre) -> (f64, f64) {
    let wi = direction(theta_i, 0.0);
    let oracle = oracle_fibre(f, COLOR);
    let (mut best_oracle, mut best_twin) = ((f64::MIN, 0.0), (f32::MIN, 0.0));
    for k in -320..=320 {
        let theta_o = f64::from(k) * 0.25;
        let wo = direction(theta_o, phi);
        let o = lobes_over_width(wo, wi, &oracle, 64)[p][1];
        let t = lobes(Vec3::X, vec3(wi), vec3(wo), COLOR, f)[p].y;
        if o > best_oracle.0 {
            best_oracle = (o, theta_o);
        }
        if t > best_twin.0 {
            best_twin = (t, theta_o);
        }
    }
    (best_oracle.1, best_twin.1)
}

/// The cuticle tilt α moves each lobe's longitudinal peak the same way in the twin as in
/// the oracle: R by +2α, TT by −α, TRT by −4α. Measured at α = 6°, θi = 20° on smooth
/// fibres (β_m = 0.1, narrow lobes): the oracle moves R by +12°, TT by −6° and TRT by
/// −21° (not −24°: its wide TRT lobe is weighted by Fresnel and absorption that change
/// across θo), the twin by +12°, −6° and −24.25° (its closed form shifts by the
/// nominal −4α: 15.5 % more than the exact model, a twin error this measures). Both must
/// be within 20 % of the model's shift, and the twin within 20 % of the oracle's (1.5° at
/// the least: the scan's quarter-degree steps); a lobe's shift of the wrong sign, or
/// TRT's at 2α or α, is 40 % or more off.
#[test]
fn the_tilt_shifts_each_lobe_as_the_oracle_does() {
    let alpha = 6.0;
    let fibre = |tilt| rough_fibre(tilt, 0.1);
    let theta_i = 20.0;
    // R and TRT come back towards the light (φ = 0), TT goes through (φ = π).
    for (p, phi, shift) in [
        (0, 0.0, 2.0 * alpha),
        (1, std::f64::consts::PI, -alpha),
        (2, 0.0, -4.0 * alpha),
    ] {
        let (oracle_flat, twin_flat) = peaks(p, theta_i, phi, &fibre(0.0));
        let (oracle_tilted, twin_tilted) = peaks(p, theta_i, phi, &fibre(alpha as f32));
        let oracle_shift = oracle_tilted - oracle_flat;
        let twin_shift = twin_tilted - twin_flat;
        println!(
            "lobe {p}: oracle peaks at {oracle_flat}° → {oracle_tilted}°, twin {twin_flat}° → {twin_tilted}°"
        );
        let near = |a: f64, b: f64| (a - b).abs() <= (0.2 * b.abs()).max(1.5);
        assert!(
            near(oracle_shift, shift),
            "lobe {p}: the oracle moves {oracle_shift}°, the model says {shift}°"
        );
        assert!(
            near(twin_shift, oracle_shift),
            "lobe {p}: the twin moves {twin_shift}°, the oracle {oracle_shift}°"
        );
    }
}

/// Backlit (light behind the fibre, seen through it: φ = π), light fur glows: TT is the
/// largest lobe in the oracle and in the twin. Darker fur (a larger σa by the same
/// colour mapping) dims TT by the same factor in both, within 20 % per channel (the
/// twin's chord through the fibre is Karis's fit of the oracle's 2 cos γt / cos θt),
/// while R, which never enters the fibre, keeps its value.
#[test]
fn backlit_light_fur_glows_through_tt_in_both() {
    let f = fibre(3.0);
    let wi = direction(10.0, 0.0);
    let wo = direction(-10.0, std::f64::consts::PI);
    let light = Vec3::new(0.9, 0.8, 0.6);
    let dark = Vec3::new(0.02, 0.01, 0.005);
    let oracle = |c| lobes_over_width(wo, wi, &oracle_fibre(&f, c), 64);
    let twin = |c| lobes(Vec3::X, vec3(wi), vec3(wo), c, &f);
    let (o_light, o_dark) = (oracle(light), oracle(dark));
    let (t_light, t_dark) = (twin(light), twin(dark));
    assert!(o_light[1][1] > o_light[0][1] && o_light[1][1] > o_light[2][1]);
    assert!(t_light[1].y > t_light[0].y && t_light[1].y > t_light[2].y);
    assert_eq!(t_light[0], t_dark[0], "R is the same for any colour");
    for c in 0..3 {
        let oracle_dims = o_dark[1][c] / o_light[1][c];
        let twin_dims = f64::from(t_dark[1][c] / t_light[1][c]);
        println!("channel {c}: TT dark/light, oracle {oracle_dims:.4}, twin {twin_dims:.4}");
        assert!(oracle_dims < 0.5, "channel {c}: the dark fur is not dark");
        assert!(
            (twin_dims / oracle_dims - 1.0).abs() < 0.2,
            "channel {c}: TT dims by {twin_dims} in the twin, {oracle_dims} in the oracle"
        );
    }
}

/// The twin's R lobe at its peak has the oracle's size: both are Fresnel at the cuticle
/// times a normalised longitudinal and azimuthal spread, so they agree within the twin's
/// approximations (Schlick's Fresnel, a Gaussian for the von Mises–Fisher lobe, Karis's
/// cos(φ/2)/4 for the h-averaged logistic), which this bounds at 35 %.
#[test]
fn the_twins_r_lobe_has_the_oracles_size() {
    let f = fibre(3.0);
    for theta_i in [0.0, 20.0, 40.0] {
        let (peak, _) = peaks(0, theta_i, 0.0, &f);
        let wi = direction(theta_i, 0.0);
        let wo = direction(peak, 0.0);
        let o = lobes_over_width(wo, wi, &oracle_fibre(&f, COLOR), 256)[0][1];
        let t = f64::from(lobes(Vec3::X, vec3(wi), vec3(wo), COLOR, &f)[0].y);
        println!(
            "θi {theta_i}°: R at its peak, oracle {o:.4}, twin {t:.4}, ratio {:.3}",
            t / o
        );
        assert!(
            (t / o - 1.0).abs() < 0.35,
            "θi {theta_i}°: twin {t}, oracle {o}"
        );
    }
}

/// Light through fibres (dual scattering's layers): black ones give the grey
/// deep-shadow term within a percent or so, unabsorbing ones pass all but what they
/// scatter back, and through blond fibres red goes deepest — each layer multiplies in
/// the same per-channel factor, so ln T red / ln T blue does not change with depth.
#[test]
fn light_through_fibres_is_grey_for_black_and_coloured_for_light_fibres() {
    use fur_core::render::dual_scattering::{cached_table, fibre_averages};
    use fur_core::render::marschner::Layers;
    use fur_core::render::FurPreset;
    let fibre = Fibre::default();
    let table = cached_table(&fibre);
    let a_f =
        |c: Vec3| fibre_averages(&table, 0.3, Vec3::from_array(c.to_array().map(f32::ln))).a_f;
    let opacity = 0.4;
    let grey = |n: f32| (1.0f32 - opacity).powf(n);
    let black = a_f(FurPreset::Black
        .colour(0.3)
        .unwrap()
        .max(Vec3::splat(1e-30)));
    let white = a_f(Vec3::ONE);
    for count in [1.0, 4.0, 16.0] {
        let layers = Layers { count, opacity };
        let (direct, t) = layers.through(black);
        assert_eq!(direct, grey(count));
        // A black fibre passes forward only what its surface reflects on (a few %).
        assert!(
            (t / grey(count) - Vec3::ONE).abs().max_element() < 0.05 * count,
            "{t}"
        );
        let (_, clear) = layers.through(white);
        assert!(clear.x > 1.5 * grey(count) && clear.x < 1.0, "{clear}");
    }
    let blond = a_f(FurPreset::Blond.colour(0.3).unwrap());
    let ratio = |count: f32| {
        let (_, t) = Layers { count, opacity }.through(blond);
        assert!(t.x > t.y && t.y > t.z, "{t}");
        t.x.ln() / t.z.ln()
    };
    assert!((ratio(2.0) - ratio(20.0)).abs() < 1e-4);
    assert!(ratio(2.0) < 0.8, "{}", ratio(2.0));
}

/// The coat's layer count on flat skin, against a count done by hand: a coat of
/// vertical fibres in even layers `1 / per_unit` apart, above a point at `height`,
/// crossed by a ray to the light at elevation `e`: the ray meets the layers above the
/// point, one each time it rises by a layer, so (coat − height) · per_unit of them,
/// more by 1 / sin e (its path is longer by that); none at the tip; the skin stops light
/// from below its plane; the count stops at the shadow map's cap.
#[test]
fn the_coat_counts_the_layers_above_the_point_along_the_light() {
    use fur_core::render::marschner::{coat_layers, MAX_LAYERS};
    let n = Vec3::new(0.0, 0.0, 1.0);
    let (coat, per_unit) = (0.3f32, 40.0);
    for elevation in [90.0f32, 60.0, 30.0, 10.0] {
        let e = elevation.to_radians();
        let l = Vec3::new(e.cos(), 0.0, e.sin());
        for height in [0.0f32, 0.1, 0.25, 0.3] {
            // Layers at heights coat − (i + ½)/per_unit above the point, counted.
            let crossed = (0..1000)
                .map(|i| coat - (i as f32 + 0.5) / per_unit)
                .filter(|&z| z > height)
                .count() as f32;
            let expected = (crossed / e.sin()).min(MAX_LAYERS);
            let got = coat_layers(n, l, coat, height, 0.0, per_unit);
            // The count by hand is whole layers; the estimate is continuous.
            assert!(
                (got - expected).abs() <= 0.5 / e.sin() + 1e-3,
                "elevation {elevation}, height {height}: {got} against {expected}"
            );
        }
        assert_eq!(
            coat_layers(n, l, coat, coat, 0.0, per_unit),
            0.0,
            "the tip is lit"
        );
    }
    for below in [-0.01f32, -0.5, -1.0] {
        let l = Vec3::new((1.0 - below * below).sqrt(), 0.0, below);
        assert_eq!(coat_layers(n, l, coat, coat, 0.0, per_unit), MAX_LAYERS);
    }
    // A thicker coat, or denser, counts more; the count is capped.
    let l = Vec3::new(0.6, 0.0, 0.8);
    assert!(
        coat_layers(n, l, 0.4, 0.1, 0.0, per_unit) > coat_layers(n, l, 0.3, 0.1, 0.0, per_unit)
    );
    assert!(coat_layers(n, l, coat, 0.1, 0.0, 80.0) > coat_layers(n, l, coat, 0.1, 0.0, per_unit));
    assert_eq!(coat_layers(n, l, 100.0, 0.0, 0.0, per_unit), MAX_LAYERS);
}

/// On curved skin the coat is a shell around a sphere: the count against a ray marched
/// from the point through the shell in small steps (the path inside it until the ray
/// leaves it, or none if the ray enters the body) — over the lit side, the terminator
/// and the dark side, where a tip can still see the light past the skin's horizon.
/// Flat skin's formula (1 / cos) would count the terminator's grazing light as blocked
/// or endless; the marched count is finite there.
#[test]
fn on_curved_skin_the_coat_is_a_shell_the_light_crosses() {
    use fur_core::render::marschner::{coat_layers, MAX_LAYERS};
    let (radius, coat, per_unit) = (1.0f32, 0.25f32, 20.0f32);
    let n = Vec3::Z;
    let marched = |l: Vec3, height: f32| -> f32 {
        let centre = -radius * n;
        let mut x = (height) * n;
        let step = 1e-4;
        let mut path = 0.0;
        for _ in 0..200_000 {
            let r = (x - centre).length();
            if r < radius {
                return MAX_LAYERS;
            }
            if r > radius + coat {
                break;
            }
            path += step;
            x += step * l;
        }
        (path * per_unit).min(MAX_LAYERS)
    };
    let mut checked = 0;
    for angle in [0.0f32, 40.0, 70.0, 85.0, 90.0, 95.0, 100.0, 110.0, 140.0] {
        let a = angle.to_radians();
        let l = Vec3::new(a.sin(), 0.0, a.cos());
        for height in [0.0f32, 0.05, 0.12, 0.2, 0.24] {
            let got = coat_layers(n, l, coat, height, 1.0 / radius, per_unit);
            let want = marched(l, height);
            assert!(
                (got - want).abs() < 0.01 * want.max(1.0),
                "light {angle}° off the normal, height {height}: {got} against {want} marched"
            );
            if want < MAX_LAYERS && angle > 90.0 {
                checked += 1;
            }
        }
    }
    // Some points past the horizon do see the light (their tips rise above the skin).
    assert!(
        checked >= 2,
        "only {checked} points past the horizon are lit"
    );
}

/// The skin's curvature from a triangle's master roots and directions: 1 / R on a
/// sphere of radius R wherever the triangle lies and however large it is, 0 on a plane
/// in any orientation, 0 inside a hollow sphere, by hand on a cylinder (curved one way);
/// masters combed alike (turned by one rotation) lower it.
#[test]
fn the_skins_curvature_comes_from_how_the_masters_turn() {
    use fur_core::render::marschner::skin_curvature;
    let on_sphere = |radius: f32, centre: Vec3, points: [Vec3; 3]| {
        let roots = points.map(|p| centre + radius * p.normalize());
        let dirs = points.map(|p| p.normalize());
        (roots, dirs)
    };
    let triangles = [
        [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(1.0, 0.0, 0.1),
        ],
        [
            Vec3::new(0.2, 1.0, -0.3),
            Vec3::new(-0.4, 0.8, 0.1),
            Vec3::new(0.1, 0.7, 0.6),
        ],
    ];
    for radius in [0.5f32, 2.0, 40.0] {
        for t in triangles {
            let (roots, dirs) = on_sphere(radius, Vec3::new(3.0, -1.0, 2.0), t);
            let k = skin_curvature(roots, dirs);
            assert!(
                (k * radius - 1.0).abs() < 1e-4,
                "radius {radius}: curvature {k}, not {}",
                1.0 / radius
            );
            let hollow = skin_curvature(roots, dirs.map(|d| -d));
            assert_eq!(hollow, 0.0, "hollow skin counts as flat");
        }
    }
    let n = Vec3::new(0.3, 0.9, -0.2).normalize();
    let plane = [
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ]
    .map(|p| p - n * n.dot(p));
    assert_eq!(skin_curvature(plane, [n; 3]), 0.0);
    // A cylinder of radius 2 along z curves one way only: on the triangle with an edge
    // around it (angle θ, squared length s = R²(2 − 2 cos θ)), an edge along it (length
    // L, no turn) and the edge between, Σ Δd·Δr = 2s / R and Σ |Δr|² = 2s + 2L², so the
    // estimate is s / (R (s + L²)): every edge counts.
    let (r, theta, l) = (2.0f32, 0.2f32, 0.3f32);
    let roots = [
        Vec3::new(r, 0.0, 0.0),
        Vec3::new(r * theta.cos(), r * theta.sin(), 0.0),
        Vec3::new(r, 0.0, l),
    ];
    let dirs = [Vec3::X, Vec3::new(theta.cos(), theta.sin(), 0.0), Vec3::X];
    let s = r * r * (2.0 - 2.0 * theta.cos());
    let expected = s / (r * (s + l * l));
    let got = skin_curvature(roots, dirs);
    assert!(
        (got - expected).abs() < 1e-5,
        "cylinder: {got}, not {expected}"
    );
    // Combed: every direction turned by 40° about one axis.
    let (roots, dirs) = on_sphere(2.0, Vec3::ZERO, triangles[0]);
    let comb = glam::Quat::from_axis_angle(Vec3::Y, 40f32.to_radians());
    let combed = skin_curvature(roots, dirs.map(|d| comb * d));
    assert!(combed > 0.0 && combed < 0.5, "{combed}");
}

/// The twin's single-scattering lobes are reciprocal (light and view swapped, the same
/// value: every term depends on θi + θo, |θo − θi|, the angle between the two and cos φ),
/// as the shader's are.
#[test]
fn the_twins_lobes_are_reciprocal() {
    let f = fibre(3.0);
    let mut twin_worst: f32 = 0.0;
    for (ti, pi, to, po) in [
        (-30.0, 0.3, 20.0, 2.0),
        (10.0, -1.0, 45.0, 0.5),
        (60.0, 2.5, -15.0, -2.9),
        (0.0, 0.0, 5.0, 3.0),
    ] {
        let (wi, wo) = (direction(ti, pi), direction(to, po));
        let a = lobes(Vec3::X, vec3(wi), vec3(wo), COLOR, &f);
        let b = lobes(Vec3::X, vec3(wo), vec3(wi), COLOR, &f);
        for p in 0..3 {
            let scale = a[p].max_element().max(1e-6);
            twin_worst = twin_worst.max((a[p] - b[p]).abs().max_element() / scale);
        }
    }
    assert!(
        twin_worst < 1e-4,
        "the twin is not reciprocal: {twin_worst}"
    );
}

/// Each lobe integrated over the azimuth (light and view at mirror elevations, where
/// the longitudinal terms are at their peak), twin against oracle, for a light fibre.
/// Measured: R 0.968, TT 1.001, TRT 0.830 of the oracle's — Karis's closed form for
/// TRT's azimuthal term keeps 17 % less of its energy; each bound is the measured value
/// with a margin that a changed exponent or constant in a lobe's closed form breaks.
#[test]
fn the_azimuthal_integrals_against_the_oracles() {
    let f = rough_fibre(0.0, 0.3);
    let colour = Vec3::splat(0.9);
    let oracle = oracle_fibre(&f, colour);
    let n = 720;
    let mut twin = [0.0f64; 3];
    let mut exact = [0.0f64; 3];
    let wi = direction(-10.0, 0.0);
    for k in 0..n {
        let phi = -std::f64::consts::PI + (k as f64 + 0.5) * std::f64::consts::TAU / n as f64;
        let wo = direction(10.0, phi);
        let t = lobes(Vec3::X, vec3(wi), vec3(wo), colour, &f);
        let o = lobes_over_width(wo, wi, &oracle, 32);
        for p in 0..3 {
            twin[p] += f64::from(t[p].y) / n as f64;
            exact[p] += o[p][1] / n as f64;
        }
    }
    let ratio: Vec<f64> = (0..3).map(|p| twin[p] / exact[p]).collect();
    eprintln!("azimuthal integrals, twin / oracle (R, TT, TRT): {ratio:.3?}");
    assert!((ratio[0] - 0.968).abs() < 0.05, "R: {ratio:?}");
    assert!((ratio[1] - 1.001).abs() < 0.05, "TT: {ratio:?}");
    assert!((ratio[2] - 0.830).abs() < 0.05, "TRT: {ratio:?}");
}
