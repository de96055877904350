//! Master hairs: one strand grown from every mesh vertex along its normal, bent by a
//! comb and a curl so the simulation has a style to preserve.

use glam::Vec3;

use super::Mesh;
use crate::error::{Error, Result};

/// Groom controls. Lengths are in scene units (metres for the default model).
#[derive(Clone, Debug, PartialEq)]
pub struct GroomParams {
    /// Segments per master hair (vertices = segments + 1); 1..=63.
    pub segments: u32,
    /// Length of every segment; > 0.
    pub segment_length: f32,
    /// Direction the fur is combed towards (projected onto each vertex's tangent plane).
    pub comb_direction: Vec3,
    /// How the fur is combed: along the body (every scene's default,
    /// [`crate::scene_file::SceneOptions`]) or towards `comb_direction` (this struct's
    /// default: the low-level comb the unit tests' scenarios are built on).
    pub flow: super::Flow,
    /// Where a body's flow starts (its head end).
    pub flow_from: super::FlowFrom,
    /// A skinned body's fur flow along its bones, which replaces the body's flow.
    /// Unused by [`Flow::Direction`].
    ///
    /// [`Flow::Direction`]: super::Flow::Direction
    pub comb_field: Option<BoneFlow>,
    /// How far the tip leans towards the comb direction; 0 = straight along the normal.
    pub comb_strength: f32,
    /// Curl radius as a fraction of the segment length; 0 = no curl.
    pub curl: f32,
    /// Curl turns per strand.
    pub curl_turns: f32,
    /// Each master hair is at most this many times the model's local half-thickness
    /// long (measured inwards from its root), so thin parts (ears, legs, tails) are not
    /// buried; 0 = every hair `segments × segment_length`.
    pub thickness_limit: f32,
    /// A groom file whose guide curves make the master hairs instead (the comb, curl
    /// and length settings then do not apply; the segment count does).
    pub source: Option<super::GroomSource>,
}

/// A skinned body's fur flow (`skinning::fur_flow`): per vertex, the direction fur
/// runs along its bones (its length ignored) and how closely the skin there follows
/// one bone (its heaviest bone's weight, 1 where it follows that bone alone: hair lies
/// flat only as far as the skin under it moves as one, [`comb::ONE_BONE`]).
#[derive(Clone, Debug, PartialEq)]
pub struct BoneFlow {
    pub directions: Vec<Vec3>,
    pub one_bone: Vec<f32>,
}

impl Default for GroomParams {
    fn default() -> Self {
        Self {
            segments: 16,
            segment_length: 0.016,
            comb_direction: Vec3::new(0.0, -1.0, -0.3),
            flow: super::Flow::Direction,
            flow_from: super::FlowFrom::Auto,
            comb_field: None,
            comb_strength: 0.9,
            curl: 0.0,
            curl_turns: 1.5,
            thickness_limit: 0.0,
            source: None,
        }
    }
}

/// The most segments a master hair has (strands of at most 64 vertices).
pub const MAX_SEGMENTS: u32 = 63;

/// How strongly the fur is combed and curled, and how long it may be against the
/// body's thickness (the scene's settings take their range from it,
/// `scene_file/keys/view.rs`).
pub const SHAPE: crate::span::Span = crate::span::Span::within(0.0, 1e3);

impl GroomParams {
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_SEGMENTS).contains(&self.segments) {
            return Err(Error::Parameter(format!(
                "segments must be in 1..={MAX_SEGMENTS} (strands of at most 64 vertices), got {}",
                self.segments
            )));
        }
        if !(self.segment_length.is_finite() && self.segment_length > 0.0) {
            return Err(Error::Parameter(format!(
                "segment length must be positive and finite, got {}",
                self.segment_length
            )));
        }
        for (name, v, span) in [
            ("comb strength", self.comb_strength, SHAPE),
            ("curl", self.curl, SHAPE),
            (
                "curl turns",
                self.curl_turns,
                crate::span::Span::non_negative(),
            ),
            ("thickness limit", self.thickness_limit, SHAPE),
        ] {
            span.require(name, v)?;
        }
        if !self.comb_direction.is_finite() {
            return Err(Error::Parameter("comb direction must be finite".into()));
        }
        if let super::FlowFrom::Point(p) | super::FlowFrom::Axis(p) = self.flow_from {
            if !p.is_finite()
                || (matches!(self.flow_from, super::FlowFrom::Axis(_)) && p.length() < 1e-6)
            {
                return Err(Error::Parameter(format!(
                    "the flow's head end must be a finite point or a non-zero axis, got {}",
                    self.flow_from
                )));
            }
        }
        Ok(())
    }

    /// The groom file to draw guide by guide (`--groom-mode draw`), if this groom is
    /// one; `None` for grown fur and for a blended groom.
    pub fn drawn_source(&self) -> Option<&super::GroomSource> {
        self.source
            .as_ref()
            .filter(|s| s.mode == super::GroomMode::Draw)
    }

    pub fn vertices_per_strand(&self) -> u32 {
        self.segments + 1
    }
}

/// Master-hair vertices in model space, strand after strand.
#[derive(Clone, Debug)]
pub struct Strands {
    pub vertices_per_strand: u32,
    pub positions: Vec<Vec3>,
}

impl Strands {
    pub fn count(&self) -> usize {
        self.positions.len() / self.vertices_per_strand as usize
    }

    /// Length of the longest master hair (its polyline), scene units.
    pub fn hair_length(&self) -> f32 {
        (0..self.count())
            .map(|s| {
                let x = self.strand(s);
                x.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>()
            })
            .fold(0.0, f32::max)
    }

    /// The coat's mean height above the skin, scene units: each master's tip measured
    /// along the way its first segment leaves the skin (its normal, as grown), never
    /// below zero, averaged over the masters (a bald stub counts as the little it
    /// stands). 0 for strands of a single vertex.
    pub fn coat_height(&self) -> f32 {
        let heights = (0..self.count()).map(|s| {
            let x = self.strand(s);
            match (x.first(), x.get(1), x.last()) {
                (Some(&root), Some(&next), Some(&tip)) => {
                    (tip - root).dot((next - root).normalize_or_zero()).max(0.0)
                }
                _ => 0.0,
            }
        });
        let sum: f32 = heights.sum();
        sum / self.count().max(1) as f32
    }

    pub fn strand(&self, s: usize) -> &[Vec3] {
        let v = self.vertices_per_strand as usize;
        &self.positions[s * v..(s + 1) * v]
    }

    /// One master hair per mesh vertex: grown, or from the groom file `groom` names.
    pub fn grow(mesh: &Mesh, groom: &GroomParams) -> Result<Self> {
        Self::grow_reported(mesh, groom).map(|(s, _)| s)
    }

    /// [`Strands::grow`], with what to tell the user about a groom file (its notes,
    /// roots far from the surface).
    pub fn grow_reported(mesh: &Mesh, groom: &GroomParams) -> Result<(Self, Vec<String>)> {
        groom.validate()?;
        match &groom.source {
            Some(source) => super::groom_bind::strands_from_file(mesh, groom, source),
            None => Ok((Self::grow_from_mesh(mesh, groom)?, Vec::new())),
        }
    }

    /// Grows one master hair per mesh vertex along its normal, leaning along the comb
    /// ([`comb::Comb`]).
    pub(super) fn grow_from_mesh(mesh: &Mesh, groom: &GroomParams) -> Result<Self> {
        let segments = groom.segments as usize;
        let mut positions = Vec::with_capacity(mesh.vertex_count() * (segments + 1));
        let comb = comb::Comb::new(mesh, groom)?;
        for (i, (&root, &normal)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
            let n = normal.try_normalize().unwrap_or(Vec3::Y);
            let (b1, b2) = n.any_orthonormal_pair();
            let phase = hash_unit(i as u32) * std::f32::consts::TAU;
            let segment_length = comb.length(i) / segments as f32;
            let mut p = root;
            positions.push(p);
            for k in 0..segments {
                let along = (k as f32 + 0.5) / segments as f32;
                let angle = phase + along * groom.curl_turns * std::f32::consts::TAU;
                let curl = groom.curl * (angle.cos() * b1 + angle.sin() * b2);
                let dir = (n + comb.lean(i, along) * comb.direction[i] + curl)
                    .try_normalize()
                    .unwrap_or(n);
                p += dir * segment_length;
                positions.push(p);
            }
        }
        Ok(Self {
            vertices_per_strand: groom.vertices_per_strand(),
            positions,
        })
    }
}

/// A deterministic hash of an integer to [0, 1).
pub fn hash_unit(x: u32) -> f32 {
    let mut h = x.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    h ^= h >> 16;
    h = h.wrapping_mul(0x7FEB_352D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846C_A68B);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

pub(crate) mod comb;
#[cfg(test)]
mod tests;

pub use comb::{Comb, BODY_PERCENTILE, FLAT_LEAN, ONE_BONE, THICK, THIN};
