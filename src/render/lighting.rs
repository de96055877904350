//! Light and material: Kajiya–Kay with an optional second, shifted and tinted
//! highlight, and self-shadowing from a light-space depth map of the fur. The CPU twin
//! of the shading model, [`kajiya_kay`], is what the tests check the shaders against.

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
            opacity: 0.35,
            spacing: 0.0,
        }
    }
}

impl Shadows {
    pub const MAX_RESOLUTION: u32 = 8192;
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
    /// How much darker hair is at the root than at the tip, 0..1 (cheap self-shadowing).
    pub root_occlusion: f32,
    pub highlights: Highlights,
    pub shadows: Shadows,
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
        }
    }
}

fn check_range(name: &str, v: f32, lo: f32, hi: f32) -> Result<()> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(Error::Parameter(format!(
            "{name} must be in [{lo}, {hi}], got {v}"
        )))
    }
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
        for (name, v, lo, hi) in [
            ("light intensity", self.intensity, 0.0, 1e3),
            ("Kd", self.kd, 0.0, 1e3),
            ("Ks", self.ks, 0.0, 1e3),
            ("ambient", self.ambient, 0.0, 1e3),
            ("root occlusion", self.root_occlusion, 0.0, 1.0),
            ("the specular exponent", self.shininess, 1.0, 1e4),
            (
                "the primary highlight's shift (degrees)",
                h.primary_shift_deg,
                -45.0,
                45.0,
            ),
            (
                "the secondary highlight's shift (degrees)",
                h.secondary_shift_deg,
                -45.0,
                45.0,
            ),
            (
                "the secondary highlight's exponent",
                h.secondary_shininess,
                1.0,
                1e4,
            ),
            (
                "the secondary highlight's strength",
                h.secondary_strength,
                0.0,
                1e3,
            ),
            ("shadow opacity", s.opacity, 0.0, 1.0),
            ("shadow spacing", s.spacing, 0.0, f32::MAX),
        ] {
            check_range(name, v, lo, hi)?;
        }
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
            if !c.is_finite() || c.min_element() < 0.0 || c.max_element() > 1e3 {
                return Err(Error::Parameter(format!(
                    "{name} must have components in [0, 1000], got {c}"
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
mod tests {
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
        let lobe = |shift: f32, view: f32, p: f32| {
            (60.0 + shift - view).to_radians().cos().max(0.0).powf(p)
        };
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
}
