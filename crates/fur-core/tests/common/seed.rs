//! The seed's equations written out again, by hand, for the tests to hold the shared
//! code (`StepConstants`, the wind blend and push, the integrator) to: nothing here
//! calls the simulation's own arithmetic.

use glam::{DVec3, Mat4, Vec3};

/// The wind magnitude of seed eq. 7, `sin²(frame · 0.05) + 0.5`, at 60 frames per
/// second: `sin²(3t) + 0.5` for `t` in seconds. The code documents this form (the
/// frame count of the seed is simulated seconds × 60, whatever the time step).
pub fn wind_magnitude(t: f64) -> f64 {
    (3.0 * t).sin().powi(2) + 0.5
}

/// The per-strand blend weight of seed eq. 8: `a = (strand mod 20) / 20`, a GPU
/// float (the reference takes it in f32 too, so that both sides blend alike).
pub fn blend_weight(strand: usize) -> f64 {
    f64::from((strand % 20) as f32 / 20.0)
}

/// Length of strand `strand`'s wind displacement per substep at time `t`, from the
/// equations alone: the four vectors `W₁…W₄` lie on the cone of half-angle `α` about
/// the wind, tilted ±α towards two orthonormal axes `u`, `v`, each `½|W| m(t) h²` long
/// (two of the four are summed with weight `a`, two with `b = 1 − a`), so the blend is
/// `½|W| m h² (2d cos α + (a − b)(u + v) sin α)`, of length
/// `½|W| m h² √(4cos²α + 2(a − b)² sin²α)` whatever the axes.
pub fn strand_wind_length(wind: f64, cone_deg: f64, h: f64, t: f64, strand: usize) -> f64 {
    let a = blend_weight(strand);
    let (s, c) = cone_deg.to_radians().sin_cos();
    0.5 * wind
        * wind_magnitude(t)
        * h
        * h
        * (4.0 * c * c + 2.0 * (2.0 * a - 1.0).powi(2) * s * s).sqrt()
}

/// The velocity a Verlet step keeps: `(1 − damping)^(60 h)` (damping is the fraction
/// lost per 1/60 s).
pub fn retention(damping: f64, h: f64) -> f64 {
    (1.0 - damping).powf(60.0 * h)
}

/// How far a vertex that starts at rest falls in `n` Verlet substeps
/// `x₊ = x + r (x − x₋) + g h²` with nothing else acting, in units of `g h²`: the step
/// `dₖ = xₖ − xₖ₋₁` obeys `dₖ = r dₖ₋₁ + g h²`, `d₀ = 0`, so
/// `dₖ = g h² (1 − rᵏ) / (1 − r)` and `xₙ − x₀ = Σₖ₌₁ⁿ dₖ
/// = g h² (n − r (1 − rⁿ) / (1 − r)) / (1 − r)`; without damping (r = 1) that is
/// `g h² n (n + 1) / 2 = ½ g t² (1 + 1/n)`. Returns (fall, last step), both over `g h²`.
pub fn free_fall(r: f64, n: u32) -> (f64, f64) {
    let n_f = f64::from(n);
    if r == 1.0 {
        return (n_f * (n_f + 1.0) / 2.0, n_f);
    }
    let rn = r.powi(n as i32);
    (
        (n_f - r * (1.0 - rn) / (1.0 - r)) / (1.0 - r),
        (1.0 - rn) / (1.0 - r),
    )
}

/// Positions after a substep of a simulation with full global stiffness (S_G = 1 over
/// the whole strand), which puts every vertex on the rigidly moved rest pose before the
/// wind acts: the rest pose moved by `head`, each vertex but the root then pushed by
/// the part of its strand's wind perpendicular to the hair there, `(t × W) × t` with
/// `t` the direction of the vertex's own segment (its previous one at the tip; no push
/// along a segment of zero length). `wind` are the substep's four vectors W₁…W₄
/// (already scaled by the magnitude and h²), blended per strand by eq. 8.
pub fn rest_pose_pushed_by_wind(
    rest: &[Vec3],
    vertices: usize,
    head: Mat4,
    wind: Option<[Vec3; 4]>,
) -> Vec<DVec3> {
    let head = head.as_dmat4();
    let placed: Vec<DVec3> = rest
        .iter()
        .map(|p| head.transform_point3(p.as_dvec3()))
        .collect();
    let Some(w) = wind else {
        return placed;
    };
    let w = w.map(|v| v.as_dvec3());
    let mut out = placed.clone();
    for (s, strand) in placed.chunks(vertices).enumerate() {
        let a = blend_weight(s);
        let blend = (w[0] + w[2]) * a + (w[1] + w[3]) * (1.0 - a);
        for i in 1..vertices {
            let t = if i + 1 < vertices {
                strand[i] - strand[i + 1]
            } else {
                strand[i - 1] - strand[i]
            };
            if t.length() > 1e-20 {
                let t = t.normalize();
                out[s * vertices + i] += blend - t * blend.dot(t);
            }
        }
    }
    out
}

/// Largest |segment / rest − 1| of positions laid out strand after strand.
pub fn stretch(positions: &[DVec3], rest: &[Vec3], vertices: usize) -> f64 {
    let mut worst = 0.0f64;
    for (now, then) in positions.chunks(vertices).zip(rest.chunks(vertices)) {
        for i in 1..vertices {
            let r = (then[i] - then[i - 1]).as_dvec3().length();
            if r > 0.0 {
                worst = worst.max(((now[i] - now[i - 1]).length() / r - 1.0).abs());
            }
        }
    }
    worst
}
