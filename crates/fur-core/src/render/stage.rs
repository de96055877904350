//! The stage views (`--show`): which stage of the pipeline an image shows, and the CPU
//! twins of what the views colour by, so tests and legends read a view's colours the
//! way its shaders write them.

use glam::Vec3;

use crate::sim::SimStep;

/// Which stage of the pipeline an image shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Stage {
    /// The final image: the interpolated hairs, lit.
    #[default]
    Lit,
    /// Only the master hairs, as lines coloured by master index, with the body: what
    /// the simulation moves and the tessellation interpolates between.
    Masters,
    /// Every interpolated hair, unlit, in a flat colour per source triangle: the
    /// interpolation between each triangle's three master hairs made visible.
    Interpolated,
    /// The body as the tessellator divides it: each triangle in the colour of its inner
    /// tessellation level ([`level_colour`]), the generated triangles outlined (their
    /// corners are the hair roots), the triangles the control stage culls hatched grey.
    Density,
    /// Every interpolated hair coloured by the levels of detail: its hue by the share
    /// of its segments the vertex LOD keeps, its brightness by the density LOD's
    /// thinning with distance.
    Lod,
    /// The master hairs coloured by how far the simulation has moved each vertex from
    /// its rest shape carried by the body ([`displacement_colour`]), the vertices the
    /// collision pushed this frame in white.
    Simulation,
    /// Every interpolated hair by the self-shadowing term alone: under Kajiya–Kay in
    /// grey, the fraction of the light the deep-shadow map lets through to each point
    /// (white: lit, black: deep in the fur); under the Marschner model the light the
    /// coat's layers let through, in the fibres' colour. The shadow pass runs whatever
    /// the scene's shadow setting.
    Shadow,
    /// Every interpolated hair in the colour of the triangle that draws it, by where
    /// its point lies: dim inside the triangle, bright on an edge (a shared edge's
    /// points are drawn by its owner only), white at a corner (drawn by one owner
    /// among the triangles around it).
    Ownership,
    /// The compute rasteriser's binning: each screen tile in the colour of how many
    /// segments it lists ([`tile_colour`]); the strands are drawn in compute whatever
    /// the scene's rasteriser.
    Tiles,
}

impl Stage {
    /// Every stage view, in the order the viewer's number keys and the docs list them.
    pub const ALL: [Stage; 9] = [
        Stage::Lit,
        Stage::Masters,
        Stage::Interpolated,
        Stage::Density,
        Stage::Lod,
        Stage::Simulation,
        Stage::Shadow,
        Stage::Ownership,
        Stage::Tiles,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Lit => "lit",
            Self::Masters => "masters",
            Self::Interpolated => "interpolated",
            Self::Density => "density",
            Self::Lod => "lod",
            Self::Simulation => "simulation",
            Self::Shadow => "shadow",
            Self::Ownership => "ownership",
            Self::Tiles => "tiles",
        }
    }

    /// The shaders' `STAGE_VIEW` define for this view (0: lit; the numbers of
    /// `shaders/common.glsl`).
    pub fn code(self) -> u32 {
        match self {
            Self::Lit => 0,
            Self::Interpolated => 1,
            Self::Lod => 2,
            Self::Shadow => 3,
            Self::Ownership => 4,
            Self::Masters => 5,
            Self::Density => 6,
            Self::Simulation => 7,
            Self::Tiles => 8,
        }
    }

    /// The `STAGE_VIEW` the fur pass is built with in this view: the tiles view's
    /// strands are lit (its colours are the composite's).
    pub fn fur_code(self) -> u32 {
        match self {
            Self::Tiles => Self::Lit.code(),
            stage => stage.code(),
        }
    }

    /// Whether the view draws the strands with the compute passes whatever the scene's
    /// rasteriser.
    pub fn needs_compute(self) -> bool {
        self == Self::Tiles
    }

    /// Whether the fur pass draws the interpolated hairs in this view.
    pub fn draws_fur(self) -> bool {
        !matches!(self, Self::Masters | Self::Density | Self::Simulation)
    }

    /// Whether the view's colours come from the lighting model, so its caption names the
    /// model: the lit frame, and the shadow view (the Marschner model colours the light
    /// that crosses the coat's layers; Kajiya–Kay's is grey).
    pub fn shows_lighting(self) -> bool {
        matches!(self, Self::Lit | Self::Shadow)
    }

    /// Whether the view draws the master hairs alone, as lines.
    pub fn draws_masters(self) -> bool {
        matches!(self, Self::Masters | Self::Simulation)
    }
}

impl std::str::FromStr for Stage {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|stage| stage.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|stage| stage.name()).collect();
                format!("expected one of {}, got `{s}`", names.join(", "))
            })
    }
}

/// Which step of the simulation the `simulation` view draws as arrows: the correction
/// that step made to each master-hair vertex in the frame's last substep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Arrows {
    #[default]
    None,
    Step(SimStep),
}

impl Arrows {
    /// Every choice, `none` first, then the steps in the order a substep runs them.
    pub fn all() -> impl Iterator<Item = Arrows> {
        std::iter::once(Arrows::None).chain(SimStep::ALL.into_iter().map(Arrows::Step))
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Step(step) => step.key(),
        }
    }

    /// The step, if any.
    pub fn step(self) -> Option<SimStep> {
        match self {
            Self::None => None,
            Self::Step(step) => Some(step),
        }
    }
}

impl std::str::FromStr for Arrows {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::all().find(|a| a.name() == s).ok_or_else(|| {
            let names: Vec<&str> = Self::all().map(Arrows::name).collect();
            format!("expected one of {}, got `{s}`", names.join(", "))
        })
    }
}

/// The stage views' defines for the shaders: `STAGE_MASTERS`, `STAGE_DENSITY`, … as
/// [`Stage::code`] numbers them (plain integers, for `#if`), and the simulation view's
/// full scale.
pub fn stage_defines() -> Vec<(&'static str, String)> {
    let mut defines: Vec<(&'static str, String)> = Stage::ALL
        .iter()
        .filter(|stage| **stage != Stage::Lit)
        .map(|stage| {
            let name = match stage {
                Stage::Lit => unreachable!(),
                Stage::Masters => "STAGE_MASTERS",
                Stage::Interpolated => "STAGE_INTERPOLATED",
                Stage::Density => "STAGE_DENSITY",
                Stage::Lod => "STAGE_LOD",
                Stage::Simulation => "STAGE_SIMULATION",
                Stage::Shadow => "STAGE_SHADOW",
                Stage::Ownership => "STAGE_OWNERSHIP",
                Stage::Tiles => "STAGE_TILES",
            };
            (name, stage.code().to_string())
        })
        .collect();
    defines.push((
        "DISPLACEMENT_FULL_SCALE",
        format!("{:?}", DISPLACEMENT_FULL_SCALE),
    ));
    defines.push((
        "TILE_ENTRIES_FULL_SCALE",
        format!("{:?}", TILE_ENTRIES_FULL_SCALE),
    ));
    defines.push(("EMPTY_TILE", format!("{:?}", EMPTY_TILE)));
    defines
}

/// The tiles view's colour for a tile that lists `entries` segments: dark grey for
/// none, then blue at one through green to red at [`TILE_ENTRIES_FULL_SCALE`] or more,
/// evenly in log₂ (`tile_colour` of `shaders/strand_composite.comp`).
pub fn tile_colour(entries: u32) -> Vec3 {
    if entries == 0 {
        return Vec3::splat(EMPTY_TILE);
    }
    let t = ((entries as f32).log2() / TILE_ENTRIES_FULL_SCALE.log2()).clamp(0.0, 1.0);
    hue((1.0 - t) * (2.0 / 3.0))
}

/// The entries a tile lists that the tiles view's scale reaches red at.
pub const TILE_ENTRIES_FULL_SCALE: f32 = 4096.0;

/// The tiles view's grey (linear) for a tile that lists nothing.
pub const EMPTY_TILE: f32 = 0.02;

/// The entries the tiles view's legend labels: the powers of four up to the full scale.
pub fn legend_entries() -> Vec<u32> {
    (0..)
        .map(|k| 1u32 << (2 * k))
        .take_while(|&n| n as f32 <= TILE_ENTRIES_FULL_SCALE)
        .collect()
}

/// A saturated colour for hue `h` in [0, 1): `hue()` of `shaders/common.glsl`.
pub fn hue(h: f32) -> Vec3 {
    let channel = |offset: f32| {
        let m = (h * 6.0 + offset).rem_euclid(6.0);
        ((m - 3.0).abs() - 1.0).clamp(0.0, 1.0)
    };
    Vec3::new(channel(0.0), channel(4.0), channel(2.0))
}

/// The density view's colour of inner tessellation level `level` on a device whose
/// largest level is `max_level`: blue at 1 through green to red at the largest, evenly
/// in log₂ of the level (`level_colour` of `shaders/density.geom`).
pub fn level_colour(level: f32, max_level: f32) -> Vec3 {
    let t = (level.max(1.0).log2() / max_level.max(2.0).log2()).clamp(0.0, 1.0);
    hue((1.0 - t) * (2.0 / 3.0))
}

/// The levels the density view's legend labels: the powers of two up to `max_level`.
pub fn legend_levels(max_level: f32) -> Vec<u32> {
    (0..)
        .map(|k| 1u32 << k)
        .take_while(|&l| l as f32 <= max_level)
        .collect()
}

/// The tessellation control stage's inner level (`shaders/fur.tesc`) for a triangle of
/// `area` with `density` hairs per unit area at full density, thinned by the density
/// LOD to `lod` (1 up to the full-density distance, (D/d)² beyond), on a device whose
/// largest level is `max_level`: n = ⌈√(4/3 · A · density · lod)⌉ clamped to
/// [1, max_level], so the ~3n²/4 points of the triangle match its share of hairs.
pub fn inner_level(area: f32, density: f32, lod: f32, max_level: f32) -> f32 {
    (area * density * lod * 4.0 / 3.0)
        .sqrt()
        .ceil()
        .clamp(1.0, max_level)
}

/// The simulation view's colour for a vertex moved `displacement` from its rest shape,
/// as a fraction of its strand's length: blue at rest, through green, to red at a
/// quarter of the length or more (`displacement_colour` of `shaders/masters.vert`).
pub fn displacement_colour(displacement: f32) -> Vec3 {
    let t = (displacement / DISPLACEMENT_FULL_SCALE).clamp(0.0, 1.0);
    hue((1.0 - t) * (2.0 / 3.0))
}

/// The displacement (a fraction of the strand's length) the simulation view's colour
/// scale reaches red at.
pub const DISPLACEMENT_FULL_SCALE: f32 = 0.25;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_reads_back_by_name_and_has_its_own_code() {
        for stage in Stage::ALL {
            assert_eq!(stage.name().parse::<Stage>(), Ok(stage));
            let same = Stage::ALL.iter().filter(|s| s.code() == stage.code());
            assert_eq!(same.count(), 1, "{stage:?}");
        }
        let err = "fluffy".parse::<Stage>().unwrap_err();
        assert!(err.contains("density") && err.contains("fluffy"), "{err}");
    }

    #[test]
    fn every_arrow_choice_reads_back_by_name() {
        for a in Arrows::all() {
            assert_eq!(a.name().parse::<Arrows>(), Ok(a));
        }
        assert_eq!(Arrows::all().next(), Some(Arrows::None));
        assert!("shape".parse::<Arrows>().is_err());
    }

    #[test]
    fn the_level_scale_runs_blue_to_red_and_tells_levels_apart() {
        assert_eq!(level_colour(1.0, 64.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(level_colour(64.0, 64.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(level_colour(128.0, 64.0), Vec3::new(1.0, 0.0, 0.0));
        // Neighbouring powers of two differ by a visible step.
        let levels = legend_levels(64.0);
        assert_eq!(levels, vec![1, 2, 4, 8, 16, 32, 64]);
        for pair in levels.windows(2) {
            let (a, b) = (pair[0] as f32, pair[1] as f32);
            let step = (level_colour(a, 64.0) - level_colour(b, 64.0))
                .abs()
                .max_element();
            assert!(step > 0.3, "{a} vs {b}: {step}");
        }
    }

    /// Seen failing against a scale in entries rather than their log (every tile of a
    /// few hundred entries blue).
    #[test]
    fn the_tile_scale_runs_blue_to_red_in_powers_of_four() {
        assert_eq!(tile_colour(0), Vec3::splat(EMPTY_TILE));
        assert_eq!(tile_colour(1), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(tile_colour(4096), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(tile_colour(100_000), Vec3::new(1.0, 0.0, 0.0));
        let ticks = legend_entries();
        assert_eq!(ticks, vec![1, 4, 16, 64, 256, 1024, 4096]);
        for pair in ticks.windows(2) {
            let step = (tile_colour(pair[0]) - tile_colour(pair[1]))
                .abs()
                .max_element();
            assert!(step > 0.3, "{pair:?}: {step}");
        }
    }

    #[test]
    fn the_inner_level_matches_the_hairs_a_triangle_is_owed() {
        // 3n²/4 points for inner level n: a triangle owed 300 hairs gets n = 20.
        assert_eq!(inner_level(1.0, 300.0, 1.0, 64.0), 20.0);
        assert_eq!(inner_level(1.0, 301.0, 1.0, 64.0), 21.0);
        // Thinned by distance, clamped at both ends.
        assert_eq!(inner_level(1.0, 300.0, 0.25, 64.0), 10.0);
        assert_eq!(inner_level(1e-9, 1.0, 1.0, 64.0), 1.0);
        assert_eq!(inner_level(1e6, 1e6, 1.0, 64.0), 64.0);
    }

    #[test]
    fn hue_matches_the_shaders_primaries() {
        assert_eq!(hue(0.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(hue(1.0 / 3.0), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(hue(2.0 / 3.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(displacement_colour(0.0), Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(displacement_colour(1.0), Vec3::new(1.0, 0.0, 0.0));
    }
}
