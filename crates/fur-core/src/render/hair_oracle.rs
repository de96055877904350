//! The oracle for the Marschner twin: a plain-Rust port, in f64, of pbrt-v3's hair BSDF
//! (Chiang, Bitterli, Tappan and Burley 2016, "A Practical and Controllable Hair and
//! Fur Model for Production Path Tracing"; pbrt-v3 `src/materials/hair.cpp`), the model
//! Mitsuba 3's `hair` plugin, and so the path-traced truth, also follows.
//!
//! The fibre's frame: x along the hair (from root to tip), y and z across it. A ray
//! meets the fibre at offset h ∈ [−1, 1] across its width; lobes p = 0 (R), 1 (TT),
//! 2 (TRT) and the sum of the higher orders (p = 3), each M_p(θi, θo) · A_p · N_p(φ):
//! - M_p: the longitudinal scattering of d'Eon et al. 2011 (a von Mises–Fisher
//!   distribution on the sphere, with Bessel I0), variance v_p from β_m (v, v/4, 4v, 4v),
//!   θo rotated by the cuticle tilt (−2α, α, 4α as pbrt writes them: the lobes peak at
//!   θo = −θi + 2α, −θi − α, −θi − 4α);
//! - A_p: Fresnel at the entry angle and the absorption e^(−σa · 2 cos γt / cos θt) along
//!   each chord, with the higher orders summed as a geometric series;
//! - N_p: a trimmed logistic in φ around the exact deflection Φ(p, h), scale s from β_n.
//!
//! The oracle the fast, closed-form twin (`super::marschner`) is checked against (and
//! checks itself: a white furnace), and the model the dual-scattering table
//! (`super::dual_scattering`) averages.

use std::f64::consts::PI;

/// Lobes the sum runs over explicitly (R, TT, TRT); the rest are summed in one.
pub const P_MAX: usize = 3;

/// A fibre: absorption per unit radius (RGB), longitudinal and azimuthal roughness,
/// cuticle tilt (radians), index of refraction.
#[derive(Clone, Copy, Debug)]
pub struct Fibre {
    pub sigma_a: [f64; 3],
    pub beta_m: f64,
    pub beta_n: f64,
    pub alpha: f64,
    pub eta: f64,
}

fn bessel_i0(x: f64) -> f64 {
    let (mut value, mut x2i, mut factorial, mut four_i) = (0.0, 1.0, 1.0f64, 1.0);
    for i in 0..10 {
        if i > 1 {
            factorial *= f64::from(i);
        }
        value += x2i / (four_i * factorial * factorial);
        x2i *= x * x;
        four_i *= 4.0;
    }
    value
}

fn log_i0(x: f64) -> f64 {
    if x > 12.0 {
        x + 0.5 * (-(2.0 * PI).ln() + (1.0 / x).ln() + 1.0 / (8.0 * x))
    } else {
        bessel_i0(x).ln()
    }
}

/// The longitudinal term for variance `v`.
fn m_p(cos_i: f64, cos_o: f64, sin_i: f64, sin_o: f64, v: f64) -> f64 {
    let a = cos_i * cos_o / v;
    let b = sin_i * sin_o / v;
    if v <= 0.1 {
        (log_i0(a) - b - 1.0 / v + std::f64::consts::LN_2 + (1.0 / (2.0 * v)).ln()).exp()
    } else {
        (-b).exp() * bessel_i0(a) / ((1.0 / v).sinh() * 2.0 * v)
    }
}

/// Fresnel reflectance of a dielectric for light arriving at cosine `cos_i` from a
/// medium of index 1 onto index `eta`.
fn fresnel_dielectric(cos_i: f64, eta: f64) -> f64 {
    let (mut cos_i, mut eta_i, mut eta_t) = (cos_i.clamp(-1.0, 1.0), 1.0, eta);
    if cos_i < 0.0 {
        std::mem::swap(&mut eta_i, &mut eta_t);
        cos_i = -cos_i;
    }
    let sin_t = eta_i / eta_t * (1.0 - cos_i * cos_i).max(0.0).sqrt();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
    let parallel = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    let perpendicular = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    0.5 * (parallel * parallel + perpendicular * perpendicular)
}

fn logistic(x: f64, s: f64) -> f64 {
    let x = x.abs();
    (-x / s).exp() / (s * (1.0 + (-x / s).exp()).powi(2))
}

fn logistic_cdf(x: f64, s: f64) -> f64 {
    1.0 / (1.0 + (-x / s).exp())
}

/// The azimuthal term of lobe `p` at relative azimuth `phi`.
fn n_p(phi: f64, p: usize, s: f64, gamma_o: f64, gamma_t: f64) -> f64 {
    let deflection = 2.0 * p as f64 * gamma_t - 2.0 * gamma_o + p as f64 * PI;
    let mut d = phi - deflection;
    while d > PI {
        d -= 2.0 * PI;
    }
    while d < -PI {
        d += 2.0 * PI;
    }
    logistic(d, s) / (logistic_cdf(PI, s) - logistic_cdf(-PI, s))
}

/// The lobes' variances of the longitudinal term for roughness `beta_m` (R, TT, TRT,
/// the higher orders).
pub fn variances(beta_m: f64) -> [f64; P_MAX + 1] {
    let v0 = (0.726 * beta_m + 0.812 * beta_m * beta_m + 3.7 * beta_m.powi(20)).powi(2);
    [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0]
}

/// The logistic's scale of the azimuthal term for roughness `beta_n`.
pub fn azimuthal_scale(beta_n: f64) -> f64 {
    (PI / 8.0).sqrt() * (0.265 * beta_n + 1.194 * beta_n * beta_n + 5.372 * beta_n.powi(22))
}

/// What light leaving (or, the model being reciprocal, arriving) at longitudinal sine
/// `sin_o` meets at offset `h` across the fibre (its azimuth does not matter: the
/// model depends on the azimuths' difference only): each lobe's attenuation A_p (RGB), the tilted angles
/// its longitudinal term is evaluated at, and the angles its azimuthal term deflects by.
pub struct Crossing {
    /// A_p for R, TT, TRT and the higher orders summed.
    pub attenuation: [[f64; 3]; P_MAX + 1],
    /// (sin, cos) of θo rotated by each lobe's cuticle tilt (R, TT, TRT), then untilted
    /// for the higher orders.
    pub tilted: [(f64, f64); P_MAX + 1],
    gamma_o: f64,
    gamma_t: f64,
}

impl Crossing {
    pub fn new(sin_o: f64, h: f64, fibre: &Fibre) -> Self {
        let Fibre {
            sigma_a,
            alpha,
            eta,
            ..
        } = *fibre;
        // sin and cos of 2^k α, k = 0, 1, 2.
        let mut sin_2k = [alpha.sin(), 0.0, 0.0];
        let mut cos_2k = [(1.0 - sin_2k[0] * sin_2k[0]).max(0.0).sqrt(), 0.0, 0.0];
        for k in 1..3 {
            sin_2k[k] = 2.0 * cos_2k[k - 1] * sin_2k[k - 1];
            cos_2k[k] = cos_2k[k - 1].powi(2) - sin_2k[k - 1].powi(2);
        }
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let sin_t = sin_o / eta;
        let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
        let etap = (eta * eta - sin_o * sin_o).sqrt() / cos_o;
        let sin_gamma_t = h / etap;
        let cos_gamma_t = (1.0 - sin_gamma_t * sin_gamma_t).max(0.0).sqrt();
        let transmittance = sigma_a.map(|a| (-a * (2.0 * cos_gamma_t / cos_t)).exp());

        // A_p: Fresnel at the entry, absorption along each internal chord.
        let f = fresnel_dielectric(cos_o * (1.0 - h * h).max(0.0).sqrt(), eta);
        let mut a = [[0.0; 3]; P_MAX + 1];
        a[0] = [f; 3];
        a[1] = transmittance.map(|t| (1.0 - f).powi(2) * t);
        for p in 2..P_MAX {
            a[p] = [0, 1, 2].map(|c| a[p - 1][c] * transmittance[c] * f);
        }
        a[P_MAX] = [0, 1, 2]
            .map(|c| a[P_MAX - 1][c] * f * transmittance[c] / (1.0 - transmittance[c] * f));
        Self {
            attenuation: a,
            tilted: [
                (
                    sin_o * cos_2k[1] - cos_o * sin_2k[1],
                    cos_o * cos_2k[1] + sin_o * sin_2k[1],
                ),
                (
                    sin_o * cos_2k[0] + cos_o * sin_2k[0],
                    cos_o * cos_2k[0] - sin_o * sin_2k[0],
                ),
                (
                    sin_o * cos_2k[2] + cos_o * sin_2k[2],
                    cos_o * cos_2k[2] - sin_o * sin_2k[2],
                ),
                (sin_o, cos_o),
            ],
            gamma_o: h.clamp(-1.0, 1.0).asin(),
            gamma_t: sin_gamma_t.clamp(-1.0, 1.0).asin(),
        }
    }

    /// The longitudinal term of lobe `p` towards a direction of longitudinal sine
    /// `sin_i`, for roughness variances `v` ([`variances`]).
    pub fn longitudinal(&self, p: usize, sin_i: f64, v: &[f64; P_MAX + 1]) -> f64 {
        let cos_i = (1.0 - sin_i * sin_i).max(0.0).sqrt();
        let (sin_op, cos_op) = self.tilted[p];
        m_p(cos_i, cos_op.abs(), sin_i, sin_op, v[p])
    }

    /// The azimuthal term of lobe `p` at relative azimuth `phi`, logistic scale `s`
    /// ([`azimuthal_scale`]); the higher orders are uniform.
    pub fn azimuthal(&self, p: usize, phi: f64, s: f64) -> f64 {
        if p == P_MAX {
            1.0 / (2.0 * PI)
        } else {
            n_p(phi, p, s, self.gamma_o, self.gamma_t)
        }
    }
}

/// Each lobe's contribution (R, TT, TRT, the higher orders; RGB) to the BSDF times the
/// cosine, f · |cos θi|, for unit `wo` and `wi` in the fibre's frame and offset `h`:
/// what reflects towards `wo` per unit radiance arriving from `wi`, per unit solid
/// angle. pbrt-v3's `HairBSDF::f` is their sum divided by the cosine.
pub fn lobes(wo: [f64; 3], wi: [f64; 3], h: f64, fibre: &Fibre) -> [[f64; 3]; P_MAX + 1] {
    let v = variances(fibre.beta_m);
    let s = azimuthal_scale(fibre.beta_n);
    let crossing = Crossing::new(wo[0], h, fibre);
    let phi = wi[2].atan2(wi[1]) - wo[2].atan2(wo[1]);
    let mut out = [[0.0; 3]; P_MAX + 1];
    for (p, lobe) in out.iter_mut().enumerate() {
        let m = crossing.longitudinal(p, wi[0], &v);
        let n = crossing.azimuthal(p, phi, s);
        *lobe = crossing.attenuation[p].map(|ap| m * ap * n);
    }
    out
}

/// Each lobe averaged over the fibre's width (h uniform in [−1, 1], `samples` midpoints),
/// as a path tracer sees a fibre narrower than a pixel.
pub fn lobes_over_width(
    wo: [f64; 3],
    wi: [f64; 3],
    fibre: &Fibre,
    samples: usize,
) -> [[f64; 3]; P_MAX + 1] {
    let mut sum = [[0.0; 3]; P_MAX + 1];
    for k in 0..samples {
        let h = -1.0 + (2.0 * k as f64 + 1.0) / samples as f64;
        for (s, l) in sum.iter_mut().zip(lobes(wo, wi, h, fibre)) {
            for c in 0..3 {
                s[c] += l[c] / samples as f64;
            }
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (sin θ, φ) to a unit vector in the fibre's frame.
    fn direction(sin_theta: f64, phi: f64) -> [f64; 3] {
        let cos_theta = (1.0 - sin_theta * sin_theta).max(0.0).sqrt();
        [sin_theta, cos_theta * phi.cos(), cos_theta * phi.sin()]
    }

    /// White furnace (pbrt-v3's own test of this model): without absorption, what a
    /// fibre scatters out of uniform incident light, over the whole sphere and averaged
    /// over its width, is the light that arrived, within 5 %, at every roughness.
    #[test]
    fn a_white_fibre_scatters_all_the_light_it_receives() {
        let (nz, nphi, nh) = (64, 64, 16);
        for beta_m in [0.2, 0.4, 0.7] {
            for beta_n in [0.2, 0.4, 0.7] {
                let fibre = Fibre {
                    sigma_a: [0.0; 3],
                    beta_m,
                    beta_n,
                    alpha: 2f64.to_radians(),
                    eta: 1.55,
                };
                let wo = direction(0.3, 0.7);
                let mut total = 0.0;
                // Stratified over the sphere: z = sin θ uniform (equal areas), φ uniform.
                for i in 0..nz {
                    let sin_theta = -1.0 + (2.0 * i as f64 + 1.0) / nz as f64;
                    for j in 0..nphi {
                        let phi = -PI + (2.0 * j as f64 + 1.0) * PI / nphi as f64;
                        let wi = direction(sin_theta, phi);
                        let l = lobes_over_width(wo, wi, &fibre, nh);
                        total += l.iter().map(|c| c[1]).sum::<f64>();
                    }
                }
                let integral = total * 4.0 * PI / (nz * nphi) as f64;
                assert!(
                    (0.95..=1.05).contains(&integral),
                    "β_m {beta_m}, β_n {beta_n}: ∫ f cos = {integral}"
                );
            }
        }
    }

    /// Absorption only takes light away, and takes all of the transmitted lobes as it
    /// grows: R stays white and unchanged.
    #[test]
    fn absorption_darkens_the_transmitted_lobes_only() {
        let clear = Fibre {
            sigma_a: [0.0; 3],
            beta_m: 0.3,
            beta_n: 0.3,
            alpha: 0.0,
            eta: 1.55,
        };
        let dark = Fibre {
            sigma_a: [0.5, 2.0, 20.0],
            ..clear
        };
        let (wo, wi) = (direction(0.2, 0.3), direction(-0.25, 2.9));
        let (a, b) = (
            lobes_over_width(wo, wi, &clear, 32),
            lobes_over_width(wo, wi, &dark, 32),
        );
        assert_eq!(a[0], b[0], "R does not enter the fibre");
        assert!(a[0][0] == a[0][1] && a[0][1] == a[0][2], "R is colourless");
        for p in 1..=P_MAX {
            for c in 0..3 {
                assert!(b[p][c] < a[p][c], "lobe {p}, channel {c}");
            }
            assert!(b[p][2] < 1e-6 * a[p][2], "lobe {p} through σa 20");
        }
    }
}
