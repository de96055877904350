//! Light and material: the lighting models (the Marschner model by default,
//! Kajiya–Kay with an optional second, shifted and tinted highlight as the seed has it),
//! and self-shadowing from a light-space depth map of the fur. The CPU twins of the
//! shading models, [`kajiya_kay`] and [`super::marschner::marschner`], are what the
//! tests check the shaders against.

use glam::Vec3;

use crate::error::{Error, Result};

/// The two shifted specular lobes of Scheuermann's hair model on top of Kajiya–Kay:
/// the primary (white, sharp) shifted toward the tip, the secondary (tinted by the
/// hair colour, wider) toward the root.
///
/// A lobe shifted by β peaks where the angle between the tangent and the view
/// direction (eye to point) equals the angle between the tangent and the light plus β:
/// positive shifts move a highlight toward the tip, negative ones toward the root.
#[derive(Clone, Debug, PartialEq)]
pub struct Highlights {
    /// Off: one unshifted white lobe (plain Kajiya–Kay).
    pub secondary: bool,
    /// Shift of the primary lobe, degrees (positive: toward the tip).
    pub primary_shift_deg: f32,
    /// Shift of the secondary lobe, degrees (negative: toward the root).
    pub secondary_shift_deg: f32,
    /// Specular exponent of the secondary lobe (lower than the primary's: wider).
    pub secondary_shininess: f32,
    /// Strength of the secondary lobe (its colour is the hair's).
    pub secondary_strength: f32,
}

impl Default for Highlights {
    fn default() -> Self {
        Self {
            secondary: true,
            primary_shift_deg: 5.0,
            secondary_shift_deg: -10.0,
            secondary_shininess: 10.0,
            secondary_strength: 0.6,
        }
    }
}

/// Self-shadowing: the fur is drawn from the light into a depth map of the nearest
/// hair; a point `Δz` deeper than it along the light is attenuated by
/// `(1 − opacity)^(Δz / spacing)`, one factor per hair layer in front of it
/// (TressFX's approximate deep shadow map).
#[derive(Clone, Debug, PartialEq)]
pub struct Shadows {
    pub enabled: bool,
    /// Side of the square light-space depth map, texels.
    pub resolution: u32,
    /// Light a single hair layer stops, 0..1.
    pub opacity: f32,
    /// Depth of one hair layer in scene units; 0 takes the spacing of the hairs at
    /// full density, 1 / sqrt(density).
    pub spacing: f32,
}

impl Default for Shadows {
    fn default() -> Self {
        Self {
            enabled: false,
            resolution: 512,
            // Tuned (docs/testing.md, "Tuned constants").
            opacity: 0.35,
            spacing: 0.0,
        }
    }
}

impl Shadows {
    pub const MAX_RESOLUTION: u32 = 8192;

    /// Hair layers per unit of depth along the light: 1 / `spacing`, or with spacing 0
    /// the spacing of hairs at `density` hairs per unit area, √density.
    pub fn layers_per_unit(&self, density: f32) -> f32 {
        if self.spacing > 0.0 {
            1.0 / self.spacing
        } else {
            density.sqrt()
        }
    }
}

/// A hair fibre's physical parameters as Chiang et al. 2016 define them: what the path
/// tracer's hair model (and a physically based real-time model) takes besides the
/// colour; and how the fibres of a coat lie to each other, which the real-time model's
/// multiple scattering takes (the path tracer has the hairs themselves).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fibre {
    /// Longitudinal roughness β_m, 0..1 (the width of the highlights along the hair).
    pub longitudinal_roughness: f32,
    /// Azimuthal roughness β_n, 0..1 (how much light spreads around the fibre).
    pub azimuthal_roughness: f32,
    /// Cuticle scale tilt α in degrees (shifts the highlights along the hair).
    pub cuticle_tilt_deg: f32,
    /// Index of refraction η of the fibre.
    pub ior: f32,
    /// The mean squared angle between neighbouring hairs' directions, rad²: the coat's
    /// hairs are not parallel, so light scattered from one fibre to the next is turned
    /// along the hair by a random share of it. Dual scattering's lobes widen by half of
    /// it at each scattering (`render::dual_scattering::node`).
    pub direction_spread: f32,
}

/// The default [`Fibre::direction_spread`]: the default blob's drawn hairs at rest,
/// measured (docs/lighting.md).
pub const DIRECTION_SPREAD: f32 = 0.09;

impl Default for Fibre {
    /// Chiang et al.'s defaults, which pbrt and Mitsuba share, and the default blob's
    /// direction spread.
    fn default() -> Self {
        Self {
            longitudinal_roughness: 0.3,
            azimuthal_roughness: 0.3,
            cuticle_tilt_deg: 2.0,
            ior: 1.55,
            direction_spread: DIRECTION_SPREAD,
        }
    }
}

impl Fibre {
    /// Checks every parameter against its range, naming the first one out of it.
    pub fn validate(&self) -> Result<()> {
        for (name, v, span) in [
            (
                "the longitudinal roughness",
                self.longitudinal_roughness,
                spans::ROUGHNESS,
            ),
            (
                "the azimuthal roughness",
                self.azimuthal_roughness,
                spans::ROUGHNESS,
            ),
            (
                "the cuticle tilt (degrees)",
                self.cuticle_tilt_deg,
                spans::CUTICLE_TILT_DEG,
            ),
            ("the index of refraction", self.ior, spans::IOR),
            (
                "the direction spread (rad²)",
                self.direction_spread,
                spans::DIRECTION_SPREAD,
            ),
        ] {
            span.require(name, v)?;
        }
        Ok(())
    }
}

/// How the fur is lit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LightingModel {
    /// Kajiya & Kay 1989 with Scheuermann's shifted highlights: the seed's model, one
    /// flag away (`--lighting-model kajiya-kay`), and what the original's scene keeps.
    KajiyaKay,
    /// A Marschner-family fibre model (R, TT and TRT lobes in Karis 2016's closed
    /// forms) on the fibre's physical parameters, with dual scattering between fibres
    /// (Zinke et al. 2008) on averages taken from the path tracer's fibre model (see
    /// `shaders/shading.glsl` and [`super::marschner::marschner`]). The default: the
    /// truth benchmark measures it within half of Kajiya–Kay's distance from the
    /// path-traced reference on every scene and fur (`docs/ground-truth.md`).
    #[default]
    Marschner,
}

impl LightingModel {
    /// The name on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Self::KajiyaKay => "kajiya-kay",
            Self::Marschner => "marschner",
        }
    }

    /// The name in prose and tables.
    pub fn label(self) -> &'static str {
        match self {
            Self::KajiyaKay => "Kajiya–Kay",
            Self::Marschner => "Marschner",
        }
    }
}

impl std::str::FromStr for LightingModel {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "kajiya-kay" => Ok(Self::KajiyaKay),
            "marschner" => Ok(Self::Marschner),
            _ => Err(format!("expected kajiya-kay or marschner, got `{s}`")),
        }
    }
}

/// Light and material.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Direction towards the light (normalised when used).
    pub light_direction: Vec3,
    pub intensity: f32,
    /// Kajiya–Kay diffuse coefficient K_d.
    pub kd: f32,
    /// Kajiya–Kay specular coefficient K_s (the primary lobe).
    pub ks: f32,
    /// Specular exponent p of the primary lobe.
    pub shininess: f32,
    pub ambient: f32,
    pub root_color: Vec3,
    pub tip_color: Vec3,
    pub skin_color: Vec3,
    /// How much darker hair is at the root than at the tip, 0..1 (cheap self-shadowing;
    /// Kajiya–Kay only: the Marschner model darkens deep hair by the coat's layers).
    pub root_occlusion: f32,
    pub highlights: Highlights,
    pub shadows: Shadows,
    /// The hair fibre's physical parameters (the Marschner model's, and the path
    /// tracer's).
    pub fibre: Fibre,
    /// The hair's lighting model.
    pub model: LightingModel,
    /// A named fur colour that replaces the root and tip colours (see
    /// [`super::FurPreset`]).
    pub preset: super::FurPreset,
    /// The Marschner model's terms that are summed: all, except where the truth
    /// benchmark drops one to measure what it contributes (not a scene setting).
    pub lobes: super::marschner::Lobes,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            light_direction: Vec3::new(0.5, 0.8, 0.6),
            intensity: 1.0,
            kd: 0.8,
            ks: 0.35,
            shininess: 40.0,
            ambient: 0.12,
            root_color: Vec3::new(0.16, 0.08, 0.035),
            tip_color: Vec3::new(0.85, 0.6, 0.35),
            skin_color: Vec3::new(0.12, 0.07, 0.05),
            root_occlusion: 0.6,
            highlights: Highlights::default(),
            shadows: Shadows::default(),
            fibre: Fibre::default(),
            model: LightingModel::default(),
            preset: super::FurPreset::None,
            lobes: super::marschner::Lobes::ALL,
        }
    }
}

/// The values each number of the lighting accepts (the scene's settings take their
/// ranges from these, `scene_file/keys/looks.rs`).
pub mod spans {
    use crate::span::Span;

    /// Intensity, K_d, K_s, the ambient term and the secondary highlight's strength.
    pub const WEIGHT: Span = Span::within(0.0, 1e3);
    /// Root occlusion and the shadow map's opacity.
    pub const FRACTION: Span = Span::within(0.0, 1.0);
    /// The primary and secondary highlights' specular exponents.
    pub const EXPONENT: Span = Span::within(1.0, 1e4);
    /// The highlights' shifts, degrees.
    pub const SHIFT_DEG: Span = Span::within(-45.0, 45.0);
    /// The fibre's longitudinal and azimuthal roughness.
    pub const ROUGHNESS: Span = Span::within(0.01, 1.0);
    pub const CUTICLE_TILT_DEG: Span = Span::within(-10.0, 10.0);
    pub const IOR: Span = Span::within(1.0, 3.0);
    /// The coat's direction spread, rad²: unsigned angles are at most π/2, so a measured
    /// spread is at most π²/4 (hairs in random directions measure π − 2).
    pub const DIRECTION_SPREAD: Span = Span::within(0.0, 2.5);
    /// The shadow map's hair spacing (0: the hair spacing).
    pub const SPACING: Span = Span::non_negative();
    /// The largest channel of a colour (root, tip, skin).
    pub const COLOUR_MAX: f64 = 1e3;
}

impl Lighting {
    pub fn validate(&self) -> Result<()> {
        if !self.light_direction.is_finite() || self.light_direction.length() < 1e-6 {
            return Err(Error::Parameter(format!(
                "the light direction must be a finite, non-zero vector, got {}",
                self.light_direction
            )));
        }
        let h = &self.highlights;
        let s = &self.shadows;
        for (name, v, span) in [
            ("light intensity", self.intensity, spans::WEIGHT),
            ("Kd", self.kd, spans::WEIGHT),
            ("Ks", self.ks, spans::WEIGHT),
            ("ambient", self.ambient, spans::WEIGHT),
            ("root occlusion", self.root_occlusion, spans::FRACTION),
            ("the specular exponent", self.shininess, spans::EXPONENT),
            (
                "the primary highlight's shift (degrees)",
                h.primary_shift_deg,
                spans::SHIFT_DEG,
            ),
            (
                "the secondary highlight's shift (degrees)",
                h.secondary_shift_deg,
                spans::SHIFT_DEG,
            ),
            (
                "the secondary highlight's exponent",
                h.secondary_shininess,
                spans::EXPONENT,
            ),
            (
                "the secondary highlight's strength",
                h.secondary_strength,
                spans::WEIGHT,
            ),
            ("shadow opacity", s.opacity, spans::FRACTION),
            ("shadow spacing", s.spacing, spans::SPACING),
        ] {
            span.require(name, v)?;
        }
        self.fibre.validate()?;
        if !(16..=Shadows::MAX_RESOLUTION).contains(&s.resolution) {
            return Err(Error::Parameter(format!(
                "the shadow map resolution must be in [16, {}], got {}",
                Shadows::MAX_RESOLUTION,
                s.resolution
            )));
        }
        for (name, c) in [
            ("root colour", self.root_color),
            ("tip colour", self.tip_color),
            ("skin colour", self.skin_color),
        ] {
            if !c.is_finite()
                || c.min_element() < 0.0
                || f64::from(c.max_element()) > spans::COLOUR_MAX
            {
                return Err(Error::Parameter(format!(
                    "{name} must have components in [0, {}], got {c}",
                    spans::COLOUR_MAX
                )));
            }
        }
        Ok(())
    }
}

/// The lighting terms of one point of a hair, before colour and intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shade {
    /// K_d · sin(t, l).
    pub diffuse: f32,
    /// The primary lobe: white.
    pub specular: f32,
    /// The secondary lobe: multiplied by the hair's colour.
    pub tinted: f32,
}

/// A specular lobe shifted by `shift` radians: `cos(θ_l + shift − θ_e)^p`, θ_l and
/// θ_e the angles from the tangent to the light and to the view direction.
fn lobe(tl: f32, sin_tl: f32, te: f32, sin_te: f32, shift: f32, p: f32) -> f32 {
    let (sin_b, cos_b) = shift.sin_cos();
    let cos_shifted = tl * cos_b - sin_tl * sin_b;
    let sin_shifted = sin_tl * cos_b + tl * sin_b;
    (cos_shifted * te + sin_shifted * sin_te).max(0.0).powf(p)
}

/// Kajiya–Kay with the highlights of `lighting`, on the CPU exactly as
/// `shaders/shading.glsl` evaluates it: `t` the unit tangent, `l` the unit direction
/// towards the light, `e` the unit direction from the eye to the point.
pub fn kajiya_kay(t: Vec3, l: Vec3, e: Vec3, lighting: &Lighting) -> Shade {
    let (tl, te) = (t.dot(l), t.dot(e));
    let sin_tl = (1.0 - tl * tl).max(0.0).sqrt();
    let sin_te = (1.0 - te * te).max(0.0).sqrt();
    let h = &lighting.highlights;
    let (primary_shift, tinted) = if h.secondary {
        let secondary = lobe(
            tl,
            sin_tl,
            te,
            sin_te,
            h.secondary_shift_deg.to_radians(),
            h.secondary_shininess,
        );
        (
            h.primary_shift_deg.to_radians(),
            h.secondary_strength * secondary,
        )
    } else {
        (0.0, 0.0)
    };
    Shade {
        diffuse: lighting.kd * sin_tl,
        specular: lighting.ks * lobe(tl, sin_tl, te, sin_te, primary_shift, lighting.shininess),
        tinted,
    }
}

#[cfg(test)]
mod tests;
