//! Fur colours a fur user recognises, as melanin: each preset is a pair of pigment
//! concentrations, turned into the fibre's absorption σa the way pbrt-v3 does for
//! Chiang et al. 2016's model (eumelanin (0.419, 0.697, 1.37) and pheomelanin
//! (0.187, 0.4, 1.05) per unit concentration), and into the hair colour whose σa under
//! Chiang's colour mapping is exactly that — so the real-time models, the export and
//! the path tracer all see the same fibre.

use glam::Vec3;

use super::marschner::chiang_colour_scale;

/// A named fur colour (`--fur-preset`, `[light] fur_preset`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FurPreset {
    /// The scene's own root and tip colours.
    #[default]
    None,
    White,
    Blond,
    Ginger,
    Brown,
    Black,
}

/// σa per unit eumelanin concentration (pbrt-v3's `SigmaAFromConcentration`).
pub const EUMELANIN_SIGMA_A: Vec3 = Vec3::new(0.419, 0.697, 1.37);
/// σa per unit pheomelanin concentration.
pub const PHEOMELANIN_SIGMA_A: Vec3 = Vec3::new(0.187, 0.4, 1.05);

impl FurPreset {
    pub const ALL: [Self; 6] = [
        Self::None,
        Self::White,
        Self::Blond,
        Self::Ginger,
        Self::Brown,
        Self::Black,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::White => "white",
            Self::Blond => "blond",
            Self::Ginger => "ginger",
            Self::Brown => "brown",
            Self::Black => "black",
        }
    }

    /// (eumelanin, pheomelanin) concentrations; None for [`FurPreset::None`]. Blond,
    /// brown and black are the eumelanin values pbrt-v3's documentation gives for
    /// those hair colours (0.3, 1.3, 8); ginger is mostly pheomelanin, the red
    /// pigment; white has none (Chiang's mapping is steep near zero: a trace of 0.02
    /// pheomelanin already gives a cream of (0.70, 0.59, 0.43)).
    pub fn melanin(self) -> Option<(f32, f32)> {
        match self {
            Self::None => None,
            Self::White => Some((0.0, 0.0)),
            Self::Blond => Some((0.3, 0.0)),
            Self::Ginger => Some((0.05, 0.4)),
            Self::Brown => Some((1.3, 0.0)),
            Self::Black => Some((8.0, 0.0)),
        }
    }

    /// The fibre's absorption σa (per unit fibre radius).
    pub fn sigma_a(self) -> Option<Vec3> {
        self.melanin()
            .map(|(eu, pheo)| eu * EUMELANIN_SIGMA_A + pheo * PHEOMELANIN_SIGMA_A)
    }

    /// The hair colour (linear RGB) whose absorption under Chiang's colour mapping at
    /// azimuthal roughness `beta_n` is [`FurPreset::sigma_a`]: c = exp(−√σa · d(β_n)).
    pub fn colour(self, beta_n: f32) -> Option<Vec3> {
        let d = chiang_colour_scale(beta_n);
        self.sigma_a()
            .map(|s| Vec3::from_array(s.to_array().map(|x| (-x.sqrt() * d).exp())))
    }
}

impl std::str::FromStr for FurPreset {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| format!("`{s}` is not a fur preset"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::marschner::sigma_a_from_color;

    /// The preset's colour maps back to its absorption through the same mapping the
    /// shader and the path tracer use, at any azimuthal roughness.
    #[test]
    fn a_presets_colour_means_its_melanin() {
        for preset in FurPreset::ALL.into_iter().skip(1) {
            for beta_n in [0.1, 0.3, 0.7] {
                let c = preset.colour(beta_n).unwrap();
                let back = sigma_a_from_color(c, beta_n);
                let want = preset.sigma_a().unwrap();
                // The mapping clamps colours at 1e-4: black's blue is far below it.
                if c.min_element() > 1e-4 {
                    assert!(
                        (back - want).abs().max_element() < 1e-3 * want.max_element().max(1.0),
                        "{} at β_n {beta_n}: {back} vs {want}",
                        preset.name()
                    );
                }
            }
        }
        assert_eq!(FurPreset::None.colour(0.3), None);
        // The colours docs/design.md quotes (linear RGB at β_n = 0.3).
        for (preset, quoted) in [
            (FurPreset::Blond, Vec3::new(0.124, 0.068, 0.023)),
            (FurPreset::Ginger, Vec3::new(0.162, 0.074, 0.016)),
            (FurPreset::Brown, Vec3::new(0.013, 0.0037, 0.00039)),
        ] {
            let c = preset.colour(0.3).unwrap();
            assert!(
                ((c - quoted) / quoted).abs().max_element() < 0.03,
                "{}: {c}",
                preset.name()
            );
        }
    }

    /// White is white and the lightest, then blond and ginger, brown, black the
    /// darkest; ginger is redder than blond (a larger share of red), as its
    /// pheomelanin makes it.
    #[test]
    fn presets_are_ordered_and_ginger_is_red() {
        let luma = |p: FurPreset| {
            p.colour(0.3)
                .unwrap()
                .dot(Vec3::new(0.2126, 0.7152, 0.0722))
        };
        for light in [FurPreset::Blond, FurPreset::Ginger] {
            assert!(luma(FurPreset::White) > luma(light));
            assert!(luma(light) > luma(FurPreset::Brown));
        }
        assert!(luma(FurPreset::Brown) > luma(FurPreset::Black));
        let redness = |p: FurPreset| {
            let c = p.colour(0.3).unwrap();
            c.x / c.element_sum()
        };
        for p in [FurPreset::White, FurPreset::Blond] {
            assert!(redness(FurPreset::Ginger) > redness(p));
        }
        assert_eq!(FurPreset::White.colour(0.3).unwrap(), Vec3::ONE);
    }

    /// Each preset's name reads back as that preset, every name differs (the scene
    /// files and `--fur-preset` spell them), and a name that is none is refused.
    #[test]
    fn every_preset_reads_back_from_its_name() {
        for preset in FurPreset::ALL {
            assert_eq!(preset.name().parse::<FurPreset>(), Ok(preset));
        }
        let names: std::collections::HashSet<&str> =
            FurPreset::ALL.iter().map(|p| p.name()).collect();
        assert_eq!(names.len(), FurPreset::ALL.len());
        assert!(names.contains("blond") && names.contains("none"));
        let err = "auburn".parse::<FurPreset>().unwrap_err();
        assert!(err.contains("`auburn`"), "{err}");
    }
}
