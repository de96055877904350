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
    /// Per vertex, a direction that replaces `comb_direction` there (a skinned body's
    /// fur flow along its bones); its length is ignored.
    pub comb_field: Option<Vec<Vec3>>,
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
}

impl Default for GroomParams {
    fn default() -> Self {
        Self {
            segments: 16,
            segment_length: 0.016,
            comb_direction: Vec3::new(0.0, -1.0, -0.3),
            comb_field: None,
            comb_strength: 0.9,
            curl: 0.0,
            curl_turns: 1.5,
            thickness_limit: 0.0,
        }
    }
}

impl GroomParams {
    pub fn validate(&self) -> Result<()> {
        if !(1..=63).contains(&self.segments) {
            return Err(Error::Parameter(format!(
                "segments must be in 1..=63 (strands of at most 64 vertices), got {}",
                self.segments
            )));
        }
        if !(self.segment_length.is_finite() && self.segment_length > 0.0) {
            return Err(Error::Parameter(format!(
                "segment length must be positive and finite, got {}",
                self.segment_length
            )));
        }
        for (name, v) in [
            ("comb strength", self.comb_strength),
            ("curl", self.curl),
            ("curl turns", self.curl_turns),
            ("thickness limit", self.thickness_limit),
        ] {
            if !v.is_finite() || v < 0.0 {
                return Err(Error::Parameter(format!(
                    "{name} must be finite and ≥ 0, got {v}"
                )));
            }
        }
        if !self.comb_direction.is_finite() {
            return Err(Error::Parameter("comb direction must be finite".into()));
        }
        Ok(())
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

    pub fn strand(&self, s: usize) -> &[Vec3] {
        let v = self.vertices_per_strand as usize;
        &self.positions[s * v..(s + 1) * v]
    }

    /// Grows one master hair per mesh vertex.
    pub fn grow(mesh: &Mesh, groom: &GroomParams) -> Result<Self> {
        groom.validate()?;
        let segments = groom.segments as usize;
        let mut positions = Vec::with_capacity(mesh.vertex_count() * (segments + 1));
        let primary = groom.comb_direction.try_normalize().unwrap_or(Vec3::NEG_Y);
        // A second comb direction across the first takes over where the surface faces
        // along the first (whose projection vanishes there and would swirl into a whorl).
        // It is the direction across the first closest to the model's back (-z).
        let secondary = (Vec3::NEG_Z - Vec3::NEG_Z.dot(primary) * primary)
            .try_normalize()
            .unwrap_or_else(|| primary.any_orthonormal_vector());
        let comb_length = groom.comb_direction.length();
        let thickness = if groom.thickness_limit > 0.0 {
            Some(mesh.half_thickness()?)
        } else {
            None
        };
        if let Some(field) = &groom.comb_field {
            if field.len() != mesh.vertex_count() {
                return Err(Error::Parameter(format!(
                    "the comb field has {} directions for {} vertices",
                    field.len(),
                    mesh.vertex_count()
                )));
            }
        }
        for (i, (&root, &normal)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
            let n = normal.try_normalize().unwrap_or(Vec3::Y);
            let (primary, secondary) = match &groom.comb_field {
                Some(field) => {
                    let primary = field[i].try_normalize().unwrap_or(primary);
                    (primary, primary.any_orthonormal_vector())
                }
                None => (primary, secondary),
            };
            let along_first = primary - primary.dot(n) * n;
            let blend = 1.0 - along_first.length();
            let comb = (along_first + blend * (secondary - secondary.dot(n) * n)) * comb_length;
            let (b1, b2) = n.any_orthonormal_pair();
            let phase = hash_unit(i as u32) * std::f32::consts::TAU;
            let full = groom.segment_length * segments as f32;
            let segment_length = match &thickness {
                Some(h) => (groom.thickness_limit * h[i]).min(full) / segments as f32,
                None => groom.segment_length,
            };
            let mut p = root;
            positions.push(p);
            for k in 0..segments {
                let along = (k as f32 + 0.5) / segments as f32;
                let angle = phase + along * groom.curl_turns * std::f32::consts::TAU;
                let curl = groom.curl * (angle.cos() * b1 + angle.sin() * b2);
                let dir = (n + groom.comb_strength * along * comb + curl)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strands_have_the_requested_segment_length_and_start_at_the_root() {
        let mesh = Mesh::icosphere(1);
        let groom = GroomParams {
            curl: 0.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        assert_eq!(strands.count(), mesh.vertex_count());
        for s in 0..strands.count() {
            let strand = strands.strand(s);
            assert_eq!(strand[0], mesh.positions[s]);
            for w in strand.windows(2) {
                assert!(((w[1] - w[0]).length() - groom.segment_length).abs() < 1e-5);
            }
            // Hairs grow outwards.
            assert!((strand[1] - strand[0]).dot(mesh.normals[s]) > 0.0);
        }
    }

    #[test]
    fn bad_groom_is_rejected() {
        let mesh = Mesh::icosphere(0);
        for groom in [
            GroomParams {
                segments: 0,
                ..Default::default()
            },
            GroomParams {
                segments: 64,
                ..Default::default()
            },
            GroomParams {
                segment_length: -1.0,
                ..Default::default()
            },
            GroomParams {
                segment_length: f32::NAN,
                ..Default::default()
            },
        ] {
            assert!(matches!(
                Strands::grow(&mesh, &groom),
                Err(Error::Parameter(_))
            ));
        }
    }

    /// A mesh of lone vertices (no triangles): `(position, normal)` each.
    fn lone_vertices(vertices: &[(Vec3, Vec3)]) -> Mesh {
        Mesh {
            positions: vertices.iter().map(|v| v.0).collect(),
            normals: vertices.iter().map(|v| v.1).collect(),
            indices: Vec::new(),
            uvs: Vec::new(),
            texture: None,
        }
    }

    /// Checks strand `s` against the polyline from its root whose segment `k` has length
    /// `length` along `direction(k)` (normalised here).
    fn assert_strand(
        strands: &Strands,
        s: usize,
        length: f32,
        direction: impl Fn(usize) -> Vec3,
        what: &str,
    ) {
        let strand = strands.strand(s);
        for k in 0..strand.len() - 1 {
            let want = strand[k] + direction(k).normalize() * length;
            assert!(
                (strand[k + 1] - want).length() < 1e-6,
                "{what}: strand {s}, vertex {}: {}, not {want}",
                k + 1,
                strand[k + 1]
            );
        }
    }

    /// Where the surface is perpendicular to the comb, segment k of S leans towards the
    /// comb by tan⁻¹(strength × |comb| × (k + ½) / S): the tip leans most, and the comb
    /// direction's length scales the strength.
    #[test]
    fn hair_leans_towards_the_comb_more_towards_the_tip() {
        let mesh = lone_vertices(&[(Vec3::new(0.5, -0.25, 2.0), Vec3::Z)]);
        for (comb_direction, comb_strength) in [(Vec3::X, 0.8), (Vec3::X * 2.0, 0.4)] {
            let groom = GroomParams {
                segments: 4,
                segment_length: 0.1,
                comb_direction,
                comb_strength,
                ..Default::default()
            };
            let strands = Strands::grow(&mesh, &groom).unwrap();
            assert_eq!(strands.strand(0)[0], mesh.positions[0]);
            assert_strand(
                &strands,
                0,
                0.1,
                |k| Vec3::new(0.8 * (k as f32 + 0.5) / 4.0, 0.0, 1.0),
                "perpendicular comb",
            );
        }
    }

    /// Where the surface faces along the comb (its projection vanishes), the hair leans
    /// across it instead, towards the model's back: for the comb (0, −1, −1) that is
    /// (0, 1, −1)/√2, the direction perpendicular to the comb with the most −z, by the
    /// comb's full length (√2).
    #[test]
    fn hair_on_a_surface_facing_along_the_comb_leans_towards_the_back() {
        let comb = Vec3::new(0.0, -1.0, -1.0);
        let mesh = lone_vertices(&[(Vec3::ZERO, comb.normalize())]);
        let groom = GroomParams {
            segments: 3,
            segment_length: 0.2,
            comb_direction: comb,
            comb_strength: 0.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        assert_strand(
            &strands,
            0,
            0.2,
            |k| comb.normalize() + 0.5 * (k as f32 + 0.5) / 3.0 * Vec3::new(0.0, 1.0, -1.0),
            "facing along the comb",
        );
    }

    /// Between the two cases the comb blends: with the comb (3, 0, 4) over a surface
    /// facing +z, the comb's unit direction (0.6, 0, 0.8) has the tangential part
    /// (0.6, 0, 0), of length 0.6; the direction across it closest to −z is
    /// (0.8, 0, −0.6), tangential part (0.8, 0, 0), weighted by 1 − 0.6; both times the
    /// comb's length 5: (0.6 + 0.4 × 0.8) × 5 = 4.6 along x.
    #[test]
    fn a_comb_at_an_angle_to_the_surface_blends_in_the_across_direction() {
        let mesh = lone_vertices(&[(Vec3::ZERO, Vec3::Z)]);
        let groom = GroomParams {
            segments: 2,
            segment_length: 0.1,
            comb_direction: Vec3::new(3.0, 0.0, 4.0),
            comb_strength: 0.1,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        assert_strand(
            &strands,
            0,
            0.1,
            |k| Vec3::new(0.1 * (k as f32 + 0.5) / 2.0 * 4.6, 0.0, 1.0),
            "comb at an angle",
        );
    }

    /// A per-vertex comb field replaces the comb direction there (its length ignored,
    /// the comb direction's length kept); a zero entry falls back to the comb direction;
    /// a field of the wrong size is refused.
    #[test]
    fn a_comb_field_replaces_the_comb_direction_per_vertex() {
        let mesh = lone_vertices(&[(Vec3::ZERO, Vec3::Z), (Vec3::X, Vec3::Z)]);
        let groom = GroomParams {
            segments: 2,
            segment_length: 0.1,
            comb_direction: Vec3::Y * 2.0,
            comb_field: Some(vec![Vec3::X * 5.0, Vec3::ZERO]),
            comb_strength: 0.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        let lean = |k: usize| 0.5 * 2.0 * (k as f32 + 0.5) / 2.0;
        assert_strand(&strands, 0, 0.1, |k| Vec3::new(lean(k), 0.0, 1.0), "field");
        assert_strand(
            &strands,
            1,
            0.1,
            |k| Vec3::new(0.0, lean(k), 1.0),
            "fallback",
        );
        let short = GroomParams {
            comb_field: Some(vec![Vec3::X]),
            ..groom
        };
        assert!(matches!(
            Strands::grow(&mesh, &short),
            Err(Error::Parameter(_))
        ));
    }

    /// With a curl c and no comb, every segment leans by tan⁻¹(c) from the normal, and
    /// its lean turns about the normal (counter-clockwise seen from outside, for the
    /// normal +z from +x to +y) by `curl_turns` full turns over the strand, starting from
    /// the strand's own phase 2π × hash_unit(vertex): segment k of S at the angle
    /// 2π (hash + turns (k + ½) / S).
    #[test]
    fn curl_turns_each_segment_about_the_normal() {
        let mesh = lone_vertices(&[(Vec3::ZERO, Vec3::Z), (Vec3::ONE, Vec3::Z)]);
        let groom = GroomParams {
            segments: 6,
            segment_length: 0.1,
            comb_strength: 0.0,
            curl: 0.5,
            curl_turns: 1.5,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        for s in 0..2 {
            let angle = |k: usize| {
                std::f32::consts::TAU * (hash_unit(s as u32) + 1.5 * (k as f32 + 0.5) / 6.0)
            };
            assert_strand(
                &strands,
                s,
                0.1,
                |k| Vec3::new(0.5 * angle(k).cos(), 0.5 * angle(k).sin(), 1.0),
                "curl",
            );
        }
        // The two strands' phases differ.
        assert!((strands.strand(0)[1] - strands.strand(1)[1] + Vec3::ONE).length() > 1e-3);
    }

    /// With a thickness limit, each hair is at most the limit times the body's local
    /// half-thickness long (a unit sphere's is about 1), in equal segments; a limit
    /// above the full length leaves every hair `segments × segment_length` long.
    #[test]
    fn the_thickness_limit_shortens_hairs_on_thin_parts() {
        let mesh = Mesh::icosphere(2);
        let half = mesh.half_thickness().unwrap();
        assert!(half.iter().all(|h| (h - 1.0).abs() < 0.1), "{half:?}");
        for (limit, full) in [(0.05, false), (1.0, true)] {
            let groom = GroomParams {
                segments: 8,
                segment_length: 0.016,
                thickness_limit: limit,
                ..Default::default()
            };
            let strands = Strands::grow(&mesh, &groom).unwrap();
            for (s, h) in half.iter().enumerate() {
                let want = if full { 0.128 } else { limit * h };
                for w in strands.strand(s).windows(2) {
                    let segment = (w[1] - w[0]).length();
                    // Within 0.1 %: the grower measures the thickness from its own
                    // f32 sums (measured up to 3.3e-4 off); a wrong limit or unequal
                    // segments are off by far more.
                    assert!(
                        (segment / (want / 8.0) - 1.0).abs() < 1e-3,
                        "limit {limit}, strand {s}: segment {segment}, hair should be {want}"
                    );
                }
            }
        }
    }

    /// `segments + 1` vertices per strand; `count`, `strand` and `hair_length` (the
    /// longest polyline) of strands written by hand.
    #[test]
    fn strands_are_counted_sliced_and_measured() {
        assert_eq!(
            GroomParams {
                segments: 5,
                ..Default::default()
            }
            .vertices_per_strand(),
            6
        );
        let strands = Strands {
            vertices_per_strand: 3,
            positions: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::ONE,
                Vec3::new(1.0, 1.0, 4.0),
                Vec3::new(1.0, 1.0, 4.0),
            ],
        };
        assert_eq!(strands.count(), 2);
        assert_eq!(strands.strand(0), &strands.positions[..3]);
        assert_eq!(strands.strand(1), &strands.positions[3..]);
        assert_eq!(strands.hair_length(), 3.0);
        let grown = Strands::grow(
            &Mesh::icosphere(0),
            &GroomParams {
                segments: 5,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(grown.vertices_per_strand, 6);
        assert_eq!(grown.positions.len(), 6 * Mesh::icosphere(0).vertex_count());
    }

    /// Every groom number out of its range is refused (zero length, negative, NaN or
    /// infinite), the ends of the ranges are accepted.
    #[test]
    fn groom_numbers_are_checked_at_their_ends() {
        let ok = GroomParams::default();
        let zero = GroomParams {
            comb_strength: 0.0,
            curl: 0.0,
            curl_turns: 0.0,
            thickness_limit: 0.0,
            segments: 63,
            ..ok.clone()
        };
        zero.validate().unwrap();
        GroomParams {
            segments: 1,
            ..ok.clone()
        }
        .validate()
        .unwrap();
        let mut bad = vec![GroomParams {
            segment_length: 0.0,
            ..ok.clone()
        }];
        for v in [-1.0, f32::NAN, f32::INFINITY] {
            bad.push(GroomParams {
                comb_strength: v,
                ..ok.clone()
            });
            bad.push(GroomParams {
                curl: v,
                ..ok.clone()
            });
            bad.push(GroomParams {
                curl_turns: v,
                ..ok.clone()
            });
            bad.push(GroomParams {
                thickness_limit: v,
                ..ok.clone()
            });
        }
        for v in [f32::NAN, f32::INFINITY] {
            bad.push(GroomParams {
                comb_direction: Vec3::new(0.0, v, 0.0),
                ..ok.clone()
            });
            bad.push(GroomParams {
                segment_length: v,
                ..ok.clone()
            });
        }
        for groom in bad {
            assert!(
                matches!(groom.validate(), Err(Error::Parameter(_))),
                "{groom:?} accepted"
            );
        }
    }

    /// `hash_unit` spreads consecutive integers evenly over [0, 1): 16 buckets each get
    /// their share of 2¹⁴ values within 15 % (5 standard deviations), neighbours are
    /// uncorrelated (the mean product of consecutive values is ¼ within 0.01), and
    /// values repeat no more often than random ones would.
    #[test]
    fn hash_unit_spreads_evenly_over_the_unit_interval() {
        let n = 1u32 << 14;
        let values: Vec<f32> = (0..n).map(hash_unit).collect();
        assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
        let mut buckets = [0u32; 16];
        for v in &values {
            buckets[(v * 16.0) as usize] += 1;
        }
        let share = n as f32 / 16.0;
        for (b, count) in buckets.iter().enumerate() {
            assert!(
                (*count as f32 - share).abs() < 0.15 * share,
                "bucket {b}: {count} of {n}"
            );
        }
        let product = values.windows(2).map(|w| w[0] * w[1]).sum::<f32>() / (n - 1) as f32;
        assert!((product - 0.25).abs() < 0.01, "{product}");
        // Values are 24-bit fractions: 2¹⁴ random ones share one about 2²⁸ / 2²⁵ = 8
        // times; a hash that loses input bits shares thousands.
        let mut sorted = values.clone();
        sorted.sort_by(f32::total_cmp);
        let shared = sorted.windows(2).filter(|w| w[0] == w[1]).count();
        assert!(shared < 64, "{shared} values shared");
    }
}
