//! The Marschner-family fibre model, on the CPU: the twin of `marschner` in
//! `shaders/shading.glsl`, which the tests check the shaders against.
//!
//! Three lobes of light through a fibre (Marschner et al. 2003): R (reflected at the
//! cuticle), TT (through the fibre) and TRT (one internal reflection), each a product
//! of a longitudinal term M_p, an azimuthal term N_p and an attenuation A_p:
//! - M_p: a Gaussian in θi + θo − s_p with the cuticle tilt's shifts s = (2α, −α, −4α)
//!   (pbrt's and Mitsuba's convention) and standard deviations (σ, σ/2, 2σ), σ² being
//!   Chiang et al. 2016's variance for the longitudinal roughness β_m;
//! - N_p and A_p: Karis 2016's closed forms (Unreal's hair shading): N_R = cos(φ/2)/4,
//!   N_TT = exp(−3.65 cos φ − 3.98), N_TRT = exp(17 cos φ − 16.78) (fitted to an
//!   azimuthal roughness near 0.3), Schlick's Fresnel at each lobe's angle, and
//!   absorption along each lobe's path through the fibre, from σa;
//! - σa from the hair's colour by Chiang et al.'s mapping with the azimuthal roughness
//!   β_n, the same the path tracer is given, so a colour means one material to both.
//!
//! Multiple scattering between fibres, which makes light fur bright and soft, is dual
//! scattering (Zinke et al. 2008; [`super::dual_scattering`], whose table of the
//! fibre's averages is taken from the path tracer's own model): of the light that
//! reaches a point through the hair layers in front, the part no fibre scattered lights
//! it directly (the lobes above), the part the fibres in front scattered forward comes
//! in their colour and spread along the fibre (global multiple scattering), and the
//! fibres around it scatter some of both back (local multiple scattering).
//!
//! The hair layers in front are the shadow map's count when shadows are on; otherwise
//! the coat's own estimate ([`coat_layers`]): the part of the coat above the point along
//! the light, at the layer spacing the shadow map assumes, and none from behind the
//! skin — the fibre count in front that dual scattering takes from a deep shadow map,
//! here from the coat's geometry at no cost of a pass.
//!
//! The environment (uniform, as the path tracer's) lights a fibre through the coat
//! above it ([`environment`]).
//!
//! The lobes and dual scattering are radiance per unit irradiance; the renderer scales
//! them by the light's irradiance (π · intensity, as the export gives the path tracer)
//! and adds the environment's light.

use glam::Vec3;

use super::dual_scattering::{self as ds, FibreAverages};
use super::lighting::Fibre;

/// Chiang et al. 2016's absorption σa (per unit fibre radius) for a fibre of roughly
/// `color` (linear RGB) with azimuthal roughness `beta_n`.
pub fn sigma_a_from_color(color: Vec3, beta_n: f32) -> Vec3 {
    let d = chiang_colour_scale(beta_n);
    let l = color
        .clamp(Vec3::splat(1e-4), Vec3::ONE)
        .to_array()
        .map(f32::ln);
    Vec3::from_array(l.map(|x| (x / d) * (x / d)))
}

/// The polynomial in β_n of Chiang et al.'s colour mapping: σa = (ln c / d(β_n))².
pub fn chiang_colour_scale(beta_n: f32) -> f32 {
    let b = beta_n;
    5.969 - 0.215 * b + 2.532 * b.powi(2) - 10.73 * b.powi(3)
        + 5.574 * b.powi(4)
        + 0.245 * b.powi(5)
}

/// Chiang et al.'s longitudinal variance for roughness `beta_m`.
pub fn longitudinal_variance(beta_m: f32) -> f32 {
    let b = beta_m;
    (0.726 * b + 0.812 * b * b + 3.7 * b.powi(20)).powi(2)
}

/// The Marschner model's per-frame constants, as the shaders take them (`frame.fibre`
/// of `shaders/common.glsl`), so that no fragment or strand vertex works them out again:
/// the R lobe's Gaussian exponent scale −1 / (2 sd²) and normalisation
/// 1 / (√(2π) sd) (the TT and TRT lobes, of widths sd / 2 and 2 sd, scale these by 4
/// and 2, and by 1/4 and 1/2), the fibre's normal-incidence reflectance F0, and
/// 1 / d(β_n) of the colour mapping ([`chiang_colour_scale`]).
pub fn shader_terms(fibre: &Fibre) -> [f32; 4] {
    let sd = longitudinal_variance(fibre.longitudinal_roughness).sqrt();
    [
        -0.5 / (sd * sd),
        1.0 / ((2.0 * std::f32::consts::PI).sqrt() * sd),
        fresnel(1.0, fibre.ior),
        1.0 / chiang_colour_scale(fibre.azimuthal_roughness),
    ]
}

fn gaussian(sd: f32, x: f32) -> f32 {
    (-0.5 * x * x / (sd * sd)).exp() / ((2.0 * std::f32::consts::PI).sqrt() * sd)
}

fn fresnel(cos_theta: f32, eta: f32) -> f32 {
    let f0 = ((1.0 - eta) / (1.0 + eta)).powi(2);
    f0 + (1.0 - f0) * (1.0 - cos_theta.clamp(0.0, 1.0)).powi(5)
}

/// The hair in front of a point on the way to the light (or the sky): how many hair
/// layers, each stopping `opacity` of the light ([`super::Shadows::opacity`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layers {
    pub count: f32,
    pub opacity: f32,
}

impl Layers {
    /// No hair in front.
    pub fn none(opacity: f32) -> Self {
        Self {
            count: 0.0,
            opacity,
        }
    }

    /// What the layers pass on of the light: the fraction no fibre scattered (grey),
    /// and all that comes through, colour by colour, the forward-scattered part in the
    /// fibres' colour — each layer passes 1 − α unscattered and α · a_f forward (the
    /// shaders' `light_through_layers`).
    pub fn through(self, a_f: Vec3) -> (f32, Vec3) {
        let alpha = self.opacity;
        let direct = (1.0 - alpha).powf(self.count);
        let all = (Vec3::splat(1.0 - alpha) + alpha * a_f).powf(self.count);
        (direct, all)
    }
}

/// The fibre's single scattering (R + TT + TRT) and its multiple scattering, per unit
/// irradiance, for unit tangent `t`, unit `l` towards the light, unit `v` towards the
/// eye, colour `base` and `front` the hair layers between it and the light.
pub fn marschner(t: Vec3, l: Vec3, v: Vec3, base: Vec3, fibre: &Fibre, front: Layers) -> Vec3 {
    marschner_of(Lobes::ALL, t, l, v, base, fibre, front)
}

/// Which terms of the model are summed: all of them when drawing; the truth
/// benchmark drops one at a time to say what part of the distance to the path tracer
/// each explains (the shader's `FLAG_NO_*` bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lobes {
    pub r: bool,
    pub tt: bool,
    pub trt: bool,
    /// The multiple-scattering term.
    pub multiple: bool,
    /// Without a shadow map, the hair layers of the coat in front of the point, towards
    /// the light and the sky ([`coat_layers`]); off, every point is fully lit and sees
    /// the whole sky.
    pub coat: bool,
}

impl Lobes {
    pub const ALL: Self = Self {
        r: true,
        tt: true,
        trt: true,
        multiple: true,
        coat: true,
    };

    /// Each term alone switched off, with its name: R, TT, TRT, multiple scattering,
    /// the coat's light.
    pub fn each_dropped() -> [(&'static str, Self); 5] {
        let all = Self::ALL;
        [
            ("R", Self { r: false, ..all }),
            ("TT", Self { tt: false, ..all }),
            ("TRT", Self { trt: false, ..all }),
            (
                "multiple scattering",
                Self {
                    multiple: false,
                    ..all
                },
            ),
            ("the coat's light", Self { coat: false, ..all }),
        ]
    }
}

impl Default for Lobes {
    fn default() -> Self {
        Self::ALL
    }
}

/// [`marschner`] summing only the terms `lobes` keeps (the coat's switch is the
/// caller's: it chooses the layers in front).
pub fn marschner_of(
    lobes: Lobes,
    t: Vec3,
    l: Vec3,
    v: Vec3,
    base: Vec3,
    fibre: &Fibre,
    front: Layers,
) -> Vec3 {
    let [r, tt, trt] = self::lobes(t, l, v, base, fibre);
    let keep = |on: bool, x: Vec3| if on { x } else { Vec3::ZERO };
    let single = keep(lobes.r, r) + keep(lobes.tt, tt) + keep(lobes.trt, trt);
    let sin_i = t.dot(l).clamp(-1.0, 1.0);
    let sum = sin_i.asin() + t.dot(v).clamp(-1.0, 1.0).asin();
    let f = ds::fibre_averages(&ds::cached_table(fibre), sin_i.abs(), ln_colour(base));
    let (direct, through) = front.through(f.a_f);
    let mut radiance = direct * single;
    if lobes.multiple {
        radiance += multiple(&f, sum, front, direct, through);
    }
    radiance
}

/// ln c of a colour, channel by channel (of 1e-30 for black), as the shaders'
/// `log_color`.
fn ln_colour(c: Vec3) -> Vec3 {
    Vec3::from_array(c.max(Vec3::splat(1e-30)).to_array().map(f32::ln))
}

/// A unit-area Gaussian of variance `var` at `x`, channel by channel.
fn gaussian3(x: Vec3, var: Vec3) -> Vec3 {
    let two_pi = 2.0 * std::f32::consts::PI;
    Vec3::from_array(
        [0, 1, 2].map(|c| (-0.5 * x[c] * x[c] / var[c]).exp() / (two_pi * var[c]).sqrt()),
    )
}

/// Dual scattering's multiple scattering at θi + θo = `sum`, behind `front` of which
/// `direct` comes through unscattered and `through` in all: what the fibres around
/// scatter back of the direct light (its spread σ_b²), and of the forward-scattered
/// light (`through` − `direct`, spread further by α · layers · β_f²) the fibre's
/// response as if from every azimuth (its whole albedo a_f + a_b over 2π, spread by
/// β²) and the neighbours' back-scattering; d_f and d_b Zinke et al.'s density
/// factors. The shaders' `marschner_terms`.
fn multiple(f: &FibreAverages, sum: f32, front: Layers, direct: f32, through: Vec3) -> Vec3 {
    let pi = std::f32::consts::PI;
    let x = Vec3::splat(sum);
    let back = f.a_back * gaussian3(x - f.shift_b, f.sigma_b2) / pi;
    let scattered = (through - Vec3::splat(direct)).max(Vec3::ZERO);
    let spread = front.opacity * front.count * f.beta_f2;
    let global = (f.a_f + f.a_b) * gaussian3(x - f.alpha, f.beta2 + spread) * (0.5 / pi);
    let back_spread = f.a_back * gaussian3(x - f.shift_b, f.sigma_b2 + spread) / pi;
    direct * ds::DENSITY_BACKWARD * back
        + scattered * ds::DENSITY_FORWARD * (global + ds::DENSITY_BACKWARD * back_spread)
}

/// The radiance the uniform environment of radiance `radiance` (ambient / Kd, as the
/// export gives the path tracer) sends to the eye (unit `v`) off a fibre of tangent `t`
/// and colour `base` under `above`, the hair layers between it and the sky (along the
/// skin's normal): the sky it sees through them, (1 − α)^layers, lights it as a lone
/// fibre — its whole albedo a_f + a_b (at θo, by reciprocity) of the sky above and of
/// the coat's glow c below, (1 + c) / 2 on average; the coat around it sends the rest
/// back in c, what Chiang et al.'s colour means (the colour dense fibres of that
/// absorption take under uniform light). The shaders' `environment`.
pub fn environment(
    t: Vec3,
    v: Vec3,
    base: Vec3,
    fibre: &Fibre,
    above: Layers,
    radiance: f32,
) -> Vec3 {
    let u_o = t.dot(v).abs();
    let f = ds::fibre_averages(&ds::cached_table(fibre), u_o, ln_colour(base));
    let sky = (1.0 - above.opacity).powf(above.count);
    let c = base.clamp(Vec3::ZERO, Vec3::ONE);
    radiance * (sky * 0.5 * (f.a_f + f.a_b) * (Vec3::ONE + c) + (1.0 - sky) * c)
}

/// The single-scattering lobes R, TT and TRT per unit irradiance (unshadowed), as
/// [`marschner`] sums them: what the tests compare with the oracle lobe by lobe.
pub fn lobes(t: Vec3, l: Vec3, v: Vec3, base: Vec3, fibre: &Fibre) -> [Vec3; 3] {
    let sin_i = t.dot(l).clamp(-1.0, 1.0);
    let sin_o = t.dot(v).clamp(-1.0, 1.0);
    let (theta_i, theta_o) = (sin_i.asin(), sin_o.asin());
    let cos_d = (0.5 * (theta_o - theta_i)).cos();
    let (lp, vp) = (l - sin_i * t, v - sin_o * t);
    let cos_phi = lp.dot(vp) / (lp.length_squared() * vp.length_squared() + 1e-4).sqrt();
    let cos_half_phi = (0.5 + 0.5 * cos_phi).clamp(0.0, 1.0).sqrt();
    let eta = fibre.ior;
    let alpha = fibre.cuticle_tilt_deg.to_radians();
    let sd = longitudinal_variance(fibre.longitudinal_roughness).sqrt();
    let sum = theta_i + theta_o;
    let sigma_a = sigma_a_from_color(base, fibre.azimuthal_roughness);
    // R: reflected at the cuticle, white.
    let m_r = gaussian(sd, sum - 2.0 * alpha);
    let a_r = fresnel((0.5 + 0.5 * l.dot(v)).clamp(0.0, 1.0).sqrt(), eta);
    let r = m_r * 0.25 * cos_half_phi * a_r;
    // TT: through the fibre, coloured by the path's absorption.
    let n_prime = 1.19 / cos_d + 0.36 * cos_d;
    let a = 1.0 / n_prime;
    let h = cos_half_phi * (1.0 + a * (0.6 - 0.8 * cos_phi));
    let f_tt = fresnel(cos_d * (1.0 - h * h).clamp(0.0, 1.0).sqrt(), eta);
    let path_tt = 2.0 * (1.0 - (h * a).powi(2)).clamp(0.0, 1.0).sqrt() / cos_d;
    let t_tt = (-sigma_a * path_tt).exp();
    let m_tt = gaussian(0.5 * sd, sum + alpha);
    let tt = t_tt * (m_tt * (-3.65 * cos_phi - 3.98).exp() * (1.0 - f_tt).powi(2));
    // TRT: one internal reflection.
    let f_trt = fresnel(0.5 * cos_d, eta);
    let t_trt = (-sigma_a * (3.2 / cos_d)).exp();
    let m_trt = gaussian(2.0 * sd, sum + 4.0 * alpha);
    let trt = t_trt * (m_trt * (17.0 * cos_phi - 16.78).exp() * (1.0 - f_trt).powi(2) * f_trt);
    [Vec3::splat(r), tt, trt]
}

/// The most hair layers counted in front of a point, by the shadow map and the coat.
pub const MAX_LAYERS: f32 = 64.0;

/// The coat's estimate of the hair layers between a point and the light, which the
/// Marschner model uses without a shadow map (`fur.geom`'s `coat_layers`): the length
/// of the light's path out of the coat, at `per_unit` layers per unit of path (the
/// spacing the shadow map assumes, [`super::Shadows::layers_per_unit`]), capped at
/// [`MAX_LAYERS`].
///
/// The coat is a shell `coat_height` thick on a skin of curvature `curvature` (1 / its
/// radius R; 0 for flat skin) whose unit outward normal under the hair is `n`; the
/// point is `height` above the skin. From the sphere's centre the point is at
/// ρ = R + height and the coat ends at R + coat_height, so the path along `l` (with
/// c = n · l) is the root of |ρ n + t l| = R + coat_height:
/// t = −ρc + √(ρ²c² + (R + H)² − ρ²). In the curvature, with a = 1 + κ·height and
/// q = (H − height)(2 + κ(H + height)) (that is ((R + H)² − ρ²) / R), and multiplied
/// through by its conjugate so that a flat skin (κ = 0) gives no 0/0:
/// t = q / (a c + √(a² c² + κ q)); flat, (H − height) / c. The skin stops the light
/// when the path goes through it: c < 0 and its nearest approach to the centre,
/// ρ √(1 − c²), is inside R (a² (1 − c²) < 1), which on flat skin is all light from
/// below its plane.
pub fn coat_layers(
    n: Vec3,
    l: Vec3,
    coat_height: f32,
    height: f32,
    curvature: f32,
    per_unit: f32,
) -> f32 {
    let c = n.dot(l);
    let a = 1.0 + curvature * height;
    if c < 0.0 && a * a * (1.0 - c * c) < 1.0 {
        return MAX_LAYERS;
    }
    let q = (coat_height - height).max(0.0) * (2.0 + curvature * (coat_height + height));
    let path = q / (a * c + (a * a * c * c + curvature * q).sqrt()).max(1e-12);
    (path * per_unit).min(MAX_LAYERS)
}

/// The skin's curvature under a hair, 1 / its radius, as the geometry stage estimates it
/// for [`coat_layers`] (`fur.geom`'s `find_coat`): from its triangle's three master
/// roots `roots` and their unit first-segment directions `dirs` (the skin's normals, as
/// the masters leave it). Across a sphere of radius R the normals differ by the roots'
/// offsets over R, so Σ Δd · Δr / Σ |Δr|² over the triangle's edges is 1 / R; flat skin
/// gives 0, and hollow skin (normals converging) counts as flat. Masters combed alike
/// turn every direction by one rotation, which lowers the estimate (by the angle's
/// cosine for offsets square to its axis).
pub fn skin_curvature(roots: [Vec3; 3], dirs: [Vec3; 3]) -> f32 {
    let (mut turn, mut spread) = (0.0, 0.0);
    for i in 0..3 {
        let j = (i + 1) % 3;
        let dr = roots[j] - roots[i];
        turn += (dirs[j] - dirs[i]).dot(dr);
        spread += dr.length_squared();
    }
    if spread > 0.0 {
        (turn / spread).max(0.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fibre() -> Fibre {
        Fibre {
            longitudinal_roughness: 0.3,
            azimuthal_roughness: 0.4,
            cuticle_tilt_deg: 2.0,
            ior: 1.55,
            direction_spread: crate::render::DIRECTION_SPREAD,
        }
    }

    // The shaders' lobes are k·x² and the normalisation, scaled for the TT (sd / 2)
    // and TRT (2 sd) widths: each must be the Gaussian of its width.
    #[test]
    fn the_shader_terms_are_each_lobes_gaussian() {
        let f = fibre();
        let [k, norm, f0, inv_d] = shader_terms(&f);
        let sd = longitudinal_variance(f.longitudinal_roughness).sqrt();
        for x in [0.0f32, 0.1, -0.3, 0.7] {
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * b.abs().max(1e-3);
            assert!(close(norm * (k * x * x).exp(), gaussian(sd, x)), "R at {x}");
            let tt = 2.0 * norm * (4.0 * k * x * x).exp();
            assert!(close(tt, gaussian(0.5 * sd, x)), "TT at {x}");
            let trt = 0.5 * norm * (0.25 * k * x * x).exp();
            assert!(close(trt, gaussian(2.0 * sd, x)), "TRT at {x}");
        }
        // F0 at η = 1.55: (0.55 / 2.55)² = 0.046521.
        assert!((f0 - 0.046_521).abs() < 1e-6, "{f0}");
        let c = Vec3::new(0.6, 0.4, 0.2);
        let ln = c.to_array().map(f32::ln);
        let sigma = Vec3::from_array(ln.map(|l| (l * inv_d) * (l * inv_d)));
        assert!(
            (sigma - sigma_a_from_color(c, f.azimuthal_roughness))
                .abs()
                .max_element()
                < 1e-6
        );
    }
}
