//! Simulation parameters with their units and valid ranges, and the per-substep
//! constants derived from them (shared by the CPU reference and the compute shaders so
//! both start from bit-identical inputs).

use glam::{DMat4, DVec3, Vec3};

use crate::error::{Error, Result};

/// Cells along the longest axis a body's distance field may have, at least and at most.
pub use crate::geometry::sdf::RESOLUTION_RANGE as SDF_RESOLUTION_RANGE;

/// The values each number of the simulation accepts (the scene's settings take their
/// ranges from these, `scene_file/keys/simulation.rs`).
pub mod spans {
    use crate::span::Span;

    /// The frame's time step, seconds.
    pub const DT: Span = Span {
        min: 0.0,
        max: 0.1,
        min_open: true,
    };
    /// Damping, the shape constraints' stiffness and the global one's range, the
    /// collision margin and friction.
    pub const FRACTION: Span = Span::within(0.0, 1.0);
    /// The wind's cone, degrees.
    pub const WIND_CONE_DEG: Span = Span::within(0.0, 90.0);
}

/// The most substeps, local-shape and length-constraint iterations a frame runs.
pub const MAX_PASSES: u32 = 64;

/// The largest gravity or wind, m/s².
pub const MAX_ACCELERATION: f64 = 1e5;

/// The distance field's cells per hair length on a rigid body: the deepest vertex of the
/// benchmark's pressing case stays within half a percent of the hair length.
/// Tuned (docs/testing.md, "Tuned constants").
pub const CELLS_PER_HAIR: f32 = 3.0;
/// The same on a skinned body, whose thin parts (ears, paws) the field carried by each
/// root pose must resolve: on the walking critter, ear hair no longer ends up inside
/// the ear as it does at 3 cells per hair, and the mean depth falls (the benchmark's
/// collision section, docs/benchmark.md, measures the depths at this resolution).
/// Tuned (docs/testing.md, "Tuned constants").
pub const CELLS_PER_HAIR_SKINNED: f32 = 6.0;

/// Han & Harada strand simulation parameters. Units: metres, seconds.
#[derive(Clone, Debug, PartialEq)]
pub struct SimParams {
    /// Simulation time per frame in seconds, (0, 0.1]. Default 1/60.
    pub dt: f32,
    /// Substeps per frame, 1..=64; each advances `dt / substeps`.
    pub substeps: u32,
    /// Gravity in m/s² (any finite vector; |g| ≤ 1e5).
    pub gravity: Vec3,
    /// Fraction of velocity lost per 1/60 s, [0, 1]. 0 keeps all momentum.
    pub damping: f32,
    /// Global shape stiffness S_G, [0, 1]: pull towards the rigidly moved rest pose.
    pub global_stiffness: f32,
    /// Fraction of each strand (from the root) the global constraint covers, [0, 1].
    pub global_range: f32,
    /// Local shape stiffness S_L, [0, 1]: pull towards the rest shape in local frames.
    pub local_stiffness: f32,
    /// Local shape passes per substep, 0..=64.
    pub local_iterations: u32,
    /// Edge-length passes (even + odd segments) per substep, 0..=64.
    pub length_iterations: u32,
    /// Wind: direction times strength in m/s² (|wind| ≤ 1e5). Zero switches wind off.
    pub wind: Vec3,
    /// Half-angle of the cone the four wind vectors spread over, in degrees, [0, 90].
    pub wind_cone_deg: f32,
    /// Keep strands out of the body (needs the body's distance field).
    pub collision: bool,
    /// Strand vertices are kept at least this far outside the surface, as a fraction
    /// of each strand's own rest length, [0, 1].
    pub collision_margin: f32,
    /// Fraction of a colliding vertex's tangential velocity removed per substep, [0, 1].
    pub friction: f32,
    /// Distance-field cells along the model's longest axis; 0 chooses from the hair
    /// length (a cell about a third of it, 16..=128 cells).
    pub sdf_resolution: u32,
    /// On a skinned body, carry the outer strand vertices back to the rest field through
    /// the skin's own blend of bones near them (see [`crate::skinning::blend`]), and
    /// the first ones by the heaviest bone of the skin at their root, instead of their
    /// root pose alone: hair stays out where the skin bends between bones and where it
    /// folds over a crease (docs/benchmark.md). `None` (the default): on where its grid fits the device
    /// (see [`crate::skinning::blend::misfit`]; the session turns it off with a warning
    /// where not); `Some(true)`: on, refused where it does not fit; `Some(false)`: off.
    pub skin_blend: Option<bool>,
}

impl Default for SimParams {
    fn default() -> Self {
        Self {
            dt: 1.0 / 60.0,
            substeps: 1,
            gravity: Vec3::new(0.0, -9.82, 0.0),
            damping: 0.08,
            global_stiffness: 0.2,
            global_range: 1.0,
            local_stiffness: 0.9,
            local_iterations: 2,
            length_iterations: 2,
            wind: Vec3::ZERO,
            wind_cone_deg: 40.0,
            collision: true,
            collision_margin: 0.02,
            friction: 0.1,
            sdf_resolution: 0,
            skin_blend: None,
        }
    }
}

impl SimParams {
    /// Whether a skinned body's collision goes through the skin's blend (see
    /// [`SimParams::skin_blend`]).
    pub fn blends(&self) -> bool {
        self.skin_blend != Some(false)
    }

    /// Parameters under which nothing moves: no gravity, no wind.
    pub fn at_rest() -> Self {
        Self {
            gravity: Vec3::ZERO,
            ..Self::default()
        }
    }

    /// Checks every parameter against its range ([`spans`], [`MAX_PASSES`]).
    pub fn validate(&self) -> Result<()> {
        for (name, v, span) in [
            ("dt (seconds)", self.dt, spans::DT),
            ("damping", self.damping, spans::FRACTION),
            ("global stiffness", self.global_stiffness, spans::FRACTION),
            ("global range", self.global_range, spans::FRACTION),
            ("local stiffness", self.local_stiffness, spans::FRACTION),
            ("wind cone angle", self.wind_cone_deg, spans::WIND_CONE_DEG),
            ("collision margin", self.collision_margin, spans::FRACTION),
            ("friction", self.friction, spans::FRACTION),
        ] {
            span.require(name, v)?;
        }
        let (lo, hi) = SDF_RESOLUTION_RANGE;
        if self.sdf_resolution != 0 && !(lo..=hi).contains(&self.sdf_resolution) {
            return Err(Error::Parameter(format!(
                "the distance field's resolution must be 0 (from the model) or {lo}..={hi}, got {}",
                self.sdf_resolution
            )));
        }
        for (name, v) in [
            ("substeps", self.substeps),
            ("local iterations", self.local_iterations),
            ("length iterations", self.length_iterations),
        ] {
            let lo = u32::from(name == "substeps");
            if !(lo..=MAX_PASSES).contains(&v) {
                return Err(Error::Parameter(format!(
                    "{name} must be in {lo}..={MAX_PASSES}, got {v}"
                )));
            }
        }
        for (name, v) in [("gravity", self.gravity), ("wind", self.wind)] {
            if !v.is_finite() || f64::from(v.length()) > MAX_ACCELERATION {
                return Err(Error::Parameter(format!(
                    "{name} must be finite with magnitude ≤ {MAX_ACCELERATION:e}, got {v}"
                )));
            }
        }
        Ok(())
    }

    /// The distance field's resolution for hairs of `hair_length` on a model whose
    /// padded bounding box is `extent` long on its longest axis: `CELLS_PER_HAIR`
    /// cells per hair length on a rigid body, `CELLS_PER_HAIR_SKINNED` on a skinned
    /// one.
    pub fn sdf_cells(&self, extent: f32, hair_length: f32, skinned: bool) -> u32 {
        if self.sdf_resolution > 0 {
            return self.sdf_resolution;
        }
        let per_hair = if skinned {
            CELLS_PER_HAIR_SKINNED
        } else {
            CELLS_PER_HAIR
        };
        let cells = (per_hair * extent / hair_length.max(1e-12)).ceil();
        (cells.min(1e6) as u32).clamp(16, 128)
    }

    /// Seconds per substep.
    pub fn substep_dt(&self) -> f64 {
        f64::from(self.dt) / f64::from(self.substeps)
    }

    /// Vertices `1..=cutoff` of a strand of `vertices` get the global constraint.
    pub fn global_cutoff(&self, vertices: u32) -> u32 {
        if self.global_stiffness == 0.0 {
            return 0;
        }
        (self.global_range * (vertices - 1) as f32).floor() as u32
    }

    pub fn wind_enabled(&self) -> bool {
        self.wind != Vec3::ZERO
    }

    /// Whether hair can come to rest, so strands that stop may sleep: not in the wind,
    /// which never stops (its strength never falls below half).
    pub fn hair_can_rest(&self) -> bool {
        !self.wind_enabled()
    }
}

/// Everything one substep needs, derived in f64 and rounded once to f32.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepConstants {
    /// Model-to-world head transform H at the end of the substep.
    pub head: glam::Mat4,
    /// Its inverse (world to model), where the body's distance field is sampled.
    pub head_inverse: glam::Mat4,
    /// Velocity kept by the Verlet step: (1 - damping)^(h·60).
    pub velocity_retention: f32,
    /// Gravity times h².
    pub gravity_h2: Vec3,
    /// The four wind vectors W1..W4, each scaled by the magnitude sin²(3t) + 0.5 and h².
    pub wind_h2: [Vec3; 4],
}

impl StepConstants {
    /// Constants for the substep that ends at `time` seconds.
    pub fn new(params: &SimParams, time: f64, head: DMat4) -> Self {
        let h = params.substep_dt();
        let h2 = h * h;
        let retention = (1.0 - f64::from(params.damping)).powf(h * 60.0);
        // Seed eq. 7: magnitude sin²(frame · 0.05) + 0.5 at 60 frames per second.
        let magnitude = (time * 3.0).sin().powi(2) + 0.5;
        let wind = params.wind.as_dvec3();
        let strength = wind.length();
        let wind_h2 = if strength > 0.0 {
            let d = wind / strength;
            let (u, v) = d.any_orthonormal_pair();
            let a = f64::from(params.wind_cone_deg).to_radians();
            let tilt = |axis: DVec3, angle: f64| d * angle.cos() + axis * angle.sin();
            [tilt(u, a), tilt(u, -a), tilt(v, a), tilt(v, -a)]
                .map(|w| (w * (0.5 * strength * magnitude * h2)).as_vec3())
        } else {
            [Vec3::ZERO; 4]
        };
        Self {
            head: head.as_mat4(),
            head_inverse: head.inverse().as_mat4(),
            velocity_retention: retention as f32,
            gravity_h2: (params.gravity.as_dvec3() * h2).as_vec3(),
            wind_h2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The skin's blend is on unless turned off: by default (where it fits) and when
    /// asked for.
    #[test]
    fn the_skins_blend_is_on_unless_turned_off() {
        let with = |skin_blend| SimParams {
            skin_blend,
            ..SimParams::default()
        };
        assert!(with(None).blends());
        assert!(with(Some(true)).blends());
        assert!(!with(Some(false)).blends());
    }
}
