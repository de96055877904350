//! Dual scattering (Zinke, Yuksel, Weber and Keyser 2008, "Dual Scattering
//! Approximation for Fast Multiple Scattering in Hair"): the light that reaches a fibre
//! after scattering through the fibres in front of it, and the light its neighbours
//! scatter back, from a few averages of the single fibre's scattering taken over the
//! sphere. Those averages are taken here from the oracle of the fibre model
//! ([`super::hair_oracle`], the path tracer's model), per longitudinal angle and hair
//! colour, into the table the shaders read (`frame.fibre_table` of
//! `shaders/common.glsl`); [`fibre_averages`] is the CPU twin of the shader's read of it,
//! and [`super::marschner`] of its use.
//!
//! For light arriving at longitudinal angle θ (its angle to the fibre's normal plane),
//! the fibre sends a fraction a_f(θ) forward (azimuths more than 90° from the light's
//! way back) and a_b(θ) backward; each part leaves at longitudinal angle θ' with
//! θ + θ' spread around a mean shift α_f, α_b (the cuticle tilt's lobe shifts, weighted
//! by what each lobe carries) with variance β_f², β_b². Through n fibres in front the
//! forward-scattered light is d_f · a_f^n and its spread n β_f² (global multiple
//! scattering); the fibres around a point send back Ā_b of it, shifted by Δ_b and
//! spread by σ_b² (local multiple scattering), summed over the paths of one and three
//! backward scatterings (Zinke et al.'s equations, as Sadeghi et al. 2010 and Unity's
//! HDRP also use them). d_f = d_b = 0.7 are the paper's density factors. The fibres
//! around a point are not parallel in a coat: each scattering's lobes widen by half
//! the coat's direction spread ([`node`]).

use glam::{Vec3, Vec4};

use super::hair_oracle::{self, azimuthal_scale, variances, Crossing, P_MAX};
use super::lighting::Fibre;
use super::marschner::sigma_a_from_color;

/// Nodes of the table along |sin θ|, 0 (light square to the fibre) to 1 (along it).
pub const ANGLE_NODES: usize = 8;
/// Nodes of the table along the hair's colour, each channel looked up alone: evenly
/// spaced in ln c from colour 1 to 10⁻⁴ (the colour mapping's clamp, black), that is in
/// √σa, which spreads the nodes where absorption changes what a fibre passes on (a
/// blond fibre's blue, 0.023, is a fifth of the way).
pub const COLOUR_NODES: usize = 16;

/// ln of the darkest colour the colour mapping tells apart (`LN_MIN_COLOR` in the
/// shaders).
pub const LN_MIN_COLOUR: f32 = -9.210_340_4;
/// vec4s per node.
pub const NODE_VEC4S: usize = 2;
/// The table's vec4s, as the uniform block holds them.
pub const TABLE_VEC4S: usize = ANGLE_NODES * COLOUR_NODES * NODE_VEC4S;

/// Zinke et al.'s forward and backward density factors.
pub const DENSITY_FORWARD: f32 = 0.7;
pub const DENSITY_BACKWARD: f32 = 0.7;

/// Offsets across the fibre, azimuths and longitudinal angles the averages integrate
/// over (midpoints).
const WIDTH_STEPS: usize = 48;
const AZIMUTH_STEPS: usize = 192;
const ANGLE_STEPS: usize = 160;

/// The single fibre's scattering averaged over the sphere, for light arriving at one
/// longitudinal angle, one colour channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Averages {
    /// The fractions of the light scattered forward and backward.
    pub a_f: f64,
    pub a_b: f64,
    /// The mean of θ + θ' (radians) over each part, and over both.
    pub alpha_f: f64,
    pub alpha_b: f64,
    pub alpha: f64,
    /// Its variance over each part, and over both.
    pub beta_f2: f64,
    pub beta_b2: f64,
    pub beta2: f64,
}

/// The averages of a fibre of absorption `sigma_a` (per unit radius, one channel each)
/// for light arriving at longitudinal sine `sin_theta`, integrated from the oracle:
/// over the fibre's width, the azimuth and the outgoing longitudinal angle.
pub fn averages(fibre: &hair_oracle::Fibre, sin_theta: f64) -> [Averages; 3] {
    let v = variances(fibre.beta_m);
    let s = azimuthal_scale(fibre.beta_n);
    let theta = sin_theta.asin();
    // Per lobe: the forward and backward energy (RGB), over the width and azimuth.
    let mut forward = [[0.0f64; 3]; P_MAX + 1];
    let mut backward = [[0.0f64; 3]; P_MAX + 1];
    for k in 0..WIDTH_STEPS {
        let h = -1.0 + (2.0 * k as f64 + 1.0) / WIDTH_STEPS as f64;
        let crossing = Crossing::new(sin_theta, h, fibre);
        for p in 0..=P_MAX {
            let mut ahead = 0.0;
            for j in 0..AZIMUTH_STEPS {
                let phi = -std::f64::consts::PI
                    + (2.0 * j as f64 + 1.0) * std::f64::consts::PI / AZIMUTH_STEPS as f64;
                if phi.cos() < 0.0 {
                    ahead += crossing.azimuthal(p, phi, s);
                }
            }
            let ahead = ahead * 2.0 * std::f64::consts::PI / AZIMUTH_STEPS as f64;
            for c in 0..3 {
                let a = crossing.attenuation[p][c] / WIDTH_STEPS as f64;
                forward[p][c] += a * ahead;
                backward[p][c] += a * (1.0 - ahead);
            }
        }
    }
    // Per lobe: the longitudinal term's mass and the mean and second moment of θ + θ'
    // (over z = sin θ', uniform in solid angle). The term depends on θ only (through
    // the tilted angles), so one crossing at h = 0 gives it.
    let crossing = Crossing::new(sin_theta, 0.0, fibre);
    let mut moments = [[0.0f64; 3]; P_MAX + 1];
    for (p, m) in moments.iter_mut().enumerate() {
        for i in 0..ANGLE_STEPS {
            let z = -1.0 + (2.0 * i as f64 + 1.0) / ANGLE_STEPS as f64;
            let x = theta + z.asin();
            let w = crossing.longitudinal(p, z, &v) * 2.0 / ANGLE_STEPS as f64;
            m[0] += w;
            m[1] += w * x;
            m[2] += w * x * x;
        }
    }
    [0, 1, 2].map(|c| {
        // Each part's energy, mean and second moment summed over the lobes.
        let part = |energy: &[[f64; 3]; P_MAX + 1]| {
            let (mut e, mut mean, mut second) = (0.0, 0.0, 0.0);
            for p in 0..=P_MAX {
                let w = energy[p][c] * moments[p][0];
                let (mu, m2) = (moments[p][1] / moments[p][0], moments[p][2] / moments[p][0]);
                e += w;
                mean += w * mu;
                second += w * m2;
            }
            (e, mean, second)
        };
        let (a_f, mean_f, second_f) = part(&forward);
        let (a_b, mean_b, second_b) = part(&backward);
        let moments_of = |e: f64, mean: f64, second: f64| {
            if e > 1e-300 {
                let mu = mean / e;
                (mu, (second / e - mu * mu).max(0.0))
            } else {
                (0.0, 0.0)
            }
        };
        let (alpha_f, beta_f2) = moments_of(a_f, mean_f, second_f);
        let (alpha_b, beta_b2) = moments_of(a_b, mean_b, second_b);
        let (alpha, beta2) = moments_of(a_f + a_b, mean_f + mean_b, second_f + second_b);
        Averages {
            a_f,
            a_b,
            alpha_f,
            alpha_b,
            alpha,
            beta_f2,
            beta_b2,
            beta2,
        }
    })
}

/// The local multiple scattering of Zinke et al. from a fibre's averages: the light
/// the neighbourhood sends back, Ā_b, its mean shift Δ_b and its variance σ_b², summed
/// over the paths with one and three backward scatterings among any number of forward
/// ones (their equations for A_1 + A_3, Δ_b and σ_b).
pub fn backscatter(a: &Averages) -> (f64, f64, f64) {
    let (af2, ab) = (a.a_f * a.a_f, a.a_b);
    let ab3 = ab * ab * ab;
    let rest = (1.0 - af2).max(1e-6);
    let a_back = ab * af2 / rest + ab3 * af2 / rest.powi(3);
    let shift = a.alpha_b * (1.0 - 2.0 * ab * ab / (rest * rest))
        + a.alpha_f * (2.0 * rest * rest + 4.0 * af2 * ab * ab) / rest.powi(3);
    let (bf, bb) = (a.beta_f2.sqrt(), a.beta_b2.sqrt());
    let spread = (1.0 + f64::from(DENSITY_BACKWARD) * af2)
        * (ab * (2.0 * a.beta_f2 + a.beta_b2).sqrt()
            + ab3 * (2.0 * a.beta_f2 + 3.0 * a.beta_b2).sqrt())
        / (ab + ab3 * (2.0 * bf + 3.0 * bb)).max(1e-12);
    (a_back, shift, spread * spread)
}

/// One node of the table: `[a_f, β_f², Ā_b, Δ_b]`, `[σ_b², a_b, α, β²]`, among
/// fibres whose directions differ by a mean squared angle `direction_spread`. Light
/// scattered from one fibre to a neighbour turned by δ about a random axis across it
/// leaves at a longitudinal angle turned by δ cos ψ (ψ uniform), variance δ²/2: each
/// scattering's lobes widen by half the spread, so the one scattering's spread β² and
/// the forward spread a layer β_f² each grow by it, and the local back-scattering's σ_b²
/// is Zinke et al.'s formula ([`backscatter`]) on the widened β_f² and β_b².
pub fn node(a: &Averages, direction_spread: f64) -> [Vec4; 2] {
    let turn = 0.5 * direction_spread;
    let a = &Averages {
        beta_f2: a.beta_f2 + turn,
        beta_b2: a.beta_b2 + turn,
        beta2: a.beta2 + turn,
        ..*a
    };
    let (a_back, shift, spread2) = backscatter(a);
    [
        Vec4::new(a.a_f as f32, a.beta_f2 as f32, a_back as f32, shift as f32),
        Vec4::new(spread2 as f32, a.a_b as f32, a.alpha as f32, a.beta2 as f32),
    ]
}

/// The colour of node `j` along the colour axis: 1 at node 0, 10⁻⁴ at the last.
pub fn node_colour(j: usize) -> f32 {
    (LN_MIN_COLOUR * j as f32 / (COLOUR_NODES - 1) as f32).exp()
}

/// Where colour `c` lies along the colour axis, 0 (white) to 1 (black).
pub fn colour_coordinate(c: f32) -> f32 {
    (c.max(1e-30).ln() / LN_MIN_COLOUR).clamp(0.0, 1.0)
}

/// The |sin θ| of node `i` along the angle axis.
pub fn node_angle(i: usize) -> f32 {
    i as f32 / (ANGLE_NODES - 1) as f32
}

/// [`table`] of `fibre`, worked out once per fibre and process (a few recent fibres are
/// kept: the viewer's panel changes them).
pub fn cached_table(fibre: &Fibre) -> std::sync::Arc<[Vec4; TABLE_VEC4S]> {
    use std::sync::{Arc, Mutex};
    type Cache = Vec<([u32; 5], Arc<[Vec4; TABLE_VEC4S]>)>;
    static CACHE: Mutex<Cache> = Mutex::new(Vec::new());
    const KEPT: usize = 8;
    let key = [
        fibre.longitudinal_roughness,
        fibre.azimuthal_roughness,
        fibre.cuticle_tilt_deg,
        fibre.ior,
        fibre.direction_spread,
    ]
    .map(f32::to_bits);
    let found = CACHE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|(k, _)| *k == key)
        .map(|(_, t)| Arc::clone(t));
    if let Some(t) = found {
        return t;
    }
    let mut array = [Vec4::ZERO; TABLE_VEC4S];
    array.copy_from_slice(&table(fibre));
    let t = Arc::new(array);
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if cache.len() >= KEPT {
        cache.remove(0);
    }
    cache.push((key, Arc::clone(&t)));
    t
}

/// The dual-scattering table of `fibre`, as the shaders read it: node (i, j) (angle i,
/// colour j) at vec4s `2 (i · COLOUR_NODES + j)` and the one after.
pub fn table(fibre: &Fibre) -> Vec<Vec4> {
    let mut out = vec![Vec4::ZERO; TABLE_VEC4S];
    for i in 0..ANGLE_NODES {
        // Three colours at a time, one per channel of the oracle's fibre.
        for first in (0..COLOUR_NODES).step_by(3) {
            let colours: [usize; 3] = [0, 1, 2].map(|k| (first + k).min(COLOUR_NODES - 1));
            let sigma = colours.map(|j| {
                f64::from(
                    sigma_a_from_color(Vec3::splat(node_colour(j)), fibre.azimuthal_roughness)[0],
                )
            });
            let oracle = hair_oracle::Fibre {
                sigma_a: sigma,
                beta_m: f64::from(fibre.longitudinal_roughness),
                beta_n: f64::from(fibre.azimuthal_roughness),
                alpha: f64::from(fibre.cuticle_tilt_deg).to_radians(),
                eta: f64::from(fibre.ior),
            };
            let a = averages(&oracle, f64::from(node_angle(i)).min(0.999));
            for (k, &j) in colours.iter().enumerate() {
                let [v0, v1] = node(&a[k], f64::from(fibre.direction_spread));
                let at = NODE_VEC4S * (i * COLOUR_NODES + j);
                out[at] = v0;
                out[at + 1] = v1;
            }
        }
    }
    out
}

/// The table's node bilinearly between the nodes around |sin θ| = `u` and colour
/// coordinate `w` ([`colour_coordinate`]), exactly as the shaders' `fibre_node` reads
/// it: `[a_f, β_f², Ā_b, Δ_b]`, `[σ_b², a_b, α, β²]`.
pub fn lookup(table: &[Vec4; TABLE_VEC4S], u: f32, w: f32) -> [Vec4; 2] {
    let x = u.clamp(0.0, 1.0) * (ANGLE_NODES - 1) as f32;
    let y = w.clamp(0.0, 1.0) * (COLOUR_NODES - 1) as f32;
    let i = (x as usize).min(ANGLE_NODES - 2);
    let j = (y as usize).min(COLOUR_NODES - 2);
    let (fx, fy) = (x - i as f32, y - j as f32);
    let a = NODE_VEC4S * (i * COLOUR_NODES + j);
    let b = a + NODE_VEC4S * COLOUR_NODES;
    [0, 1].map(|k| {
        let near = table[a + k].lerp(table[a + k + NODE_VEC4S], fy);
        let far = table[b + k].lerp(table[b + k + NODE_VEC4S], fy);
        near.lerp(far, fx)
    })
}

/// The averages of a fibre for light at |sin θ| = `u`, colour by colour (RGB), as the
/// shaders' `FibreAverages`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FibreAverages {
    pub a_f: Vec3,
    pub beta_f2: Vec3,
    /// Ā_b, Δ_b and σ_b² ([`backscatter`]).
    pub a_back: Vec3,
    pub shift_b: Vec3,
    pub sigma_b2: Vec3,
    pub a_b: Vec3,
    pub alpha: Vec3,
    pub beta2: Vec3,
}

/// [`FibreAverages`] of the colour of logarithm `ln_c` (per channel) from `table`.
pub fn fibre_averages(table: &[Vec4; TABLE_VEC4S], u: f32, ln_c: Vec3) -> FibreAverages {
    let w = ln_c / LN_MIN_COLOUR;
    let [r, g, b] = [w.x, w.y, w.z].map(|w| lookup(table, u, w));
    let pick = |k: usize, c: usize| Vec3::new(r[k][c], g[k][c], b[k][c]);
    FibreAverages {
        a_f: pick(0, 0),
        beta_f2: pick(0, 1),
        a_back: pick(0, 2),
        shift_b: pick(0, 3),
        sigma_b2: pick(1, 0),
        a_b: pick(1, 1),
        alpha: pick(1, 2),
        beta2: pick(1, 3),
    }
}
