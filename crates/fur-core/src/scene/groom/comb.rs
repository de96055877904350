//! Which way each master hair leans as it grows, how far, and how long it may be: the
//! comb's tangent direction per vertex (the body's flow, a skinned body's bones, or one
//! constant direction), and on thin parts (limbs, ears, tails) a lean that lays the
//! hair flat along the part.

use glam::Vec3;

use super::GroomParams;
use crate::error::{Error, Result};
use crate::geometry::topology::{pieces, weld};
use crate::scene::{Flow, FlowField, Mesh};

/// A part whose half-thickness is at most this fraction of the body's (its
/// [`BODY_PERCENTILE`]th percentile over the vertices) is thin: its hair lies flat
/// along it.
pub const THIN: f32 = 0.3;
/// From this fraction of the body's half-thickness up, hair leans as combed; between
/// [`THIN`] and here the two blend smoothly.
pub const THICK: f32 = 0.6;
/// The percentile of the vertices' half-thicknesses that stands for the body's.
pub const BODY_PERCENTILE: usize = 90;
/// On a skinned body, hair lies flat only as far as the skin under it follows one bone:
/// fully where its heaviest bone's weight is 1, not at all at or below this weight,
/// smoothly between. Where the skin blends bones it bends as they turn (a hip, the
/// root of an ear), and hair laid flat there sinks into it.
pub const ONE_BONE: f32 = 0.7;
/// The lean of a hair lying flat: 1 / tan 10°, so each segment rises about 10° (with
/// the default comb's length, 9.6°) from the tangent plane.
pub const FLAT_LEAN: f32 = 5.671_282;

/// The comb of one groom on one mesh.
pub struct Comb {
    /// Per vertex, the tangent the hair leans towards, scaled by the comb's length
    /// (zero at a whorl's centre, where the hair stands along the normal).
    pub direction: Vec<Vec3>,
    /// Per vertex, how flat the hair lies: 0 as combed, 1 flat along the part.
    pub flat: Vec<f32>,
    /// Per vertex, the hair's length.
    lengths: Vec<f32>,
    strength: f32,
}

impl Comb {
    pub fn new(mesh: &Mesh, groom: &GroomParams) -> Result<Self> {
        let full = groom.segment_length * groom.segments as f32;
        if let Some(bones) = &groom.comb_field {
            let n = mesh.vertex_count();
            if bones.directions.len() != n || bones.one_bone.len() != n {
                return Err(Error::Parameter(format!(
                    "the bones' fur flow has {} directions and {} weights for {n} vertices",
                    bones.directions.len(),
                    bones.one_bone.len()
                )));
            }
        }
        // A comb of strength 0 leans nothing: no field, no thin parts to find. Thin parts
        // lie flat only under the thickness limit: hair as long as asked on a thin part
        // would, laid flat, reach past its end and into the parts beside it.
        let combed = groom.comb_strength > 0.0;
        let limited = groom.thickness_limit > 0.0;
        let body = groom.flow == Flow::Body && combed && limited;
        // The half-thickness that finds thin parts, and the one that bounds the hair's
        // length: the same on a rigid body; a skinned body keeps its lengths measured
        // through the body, on which its collision is tuned (docs/design.md, "How grown
        // fur lies"). Both come from one distance field.
        let (thin, through) = match (body, limited, groom.comb_field.is_none()) {
            (true, _, false) => {
                let (thin, through) = mesh.half_thickness_both()?;
                (Some(thin), Some(through))
            }
            (false, true, false) => (None, Some(mesh.half_thickness_through()?)),
            (true, _, true) | (_, true, true) => (Some(mesh.half_thickness()?), None),
            (false, false, _) => (None, None),
        };
        let lengths = match through.as_ref().or(thin.as_ref()) {
            Some(h) if limited => bounded(h, groom, full),
            _ => vec![full; mesh.vertex_count()],
        };
        let mut flat = match (&thin, body) {
            (Some(h), true) => flatness(h),
            _ => vec![0.0; mesh.vertex_count()],
        };
        if let Some(bones) = &groom.comb_field {
            for (f, &w) in flat.iter_mut().zip(&bones.one_bone) {
                *f *= smoothstep((w - ONE_BONE) / (1.0 - ONE_BONE));
            }
        }
        Ok(Self {
            direction: if combed {
                directions(mesh, groom, &flat)?
            } else {
                vec![Vec3::ZERO; mesh.vertex_count()]
            },
            flat,
            lengths,
            strength: groom.comb_strength,
        })
    }

    /// The length of vertex `i`'s hair.
    pub fn length(&self, i: usize) -> f32 {
        self.lengths[i]
    }

    /// How far vertex `i`'s hair leans towards its comb direction at `along` (0 at
    /// the root, 1 at the tip) for each unit it rises along the normal: the comb
    /// strength growing along the hair, or on a thin part [`FLAT_LEAN`] from the root
    /// (a comb of strength 0 lays nothing flat).
    pub fn lean(&self, i: usize, along: f32) -> f32 {
        let combed = self.strength * along;
        let flat = self.flat[i] * self.strength.min(1.0);
        combed + flat * (FLAT_LEAN.max(combed) - combed)
    }
}

/// Per vertex, the hair's length under the thickness limit from the half-thicknesses `h`.
fn bounded(h: &[f32], groom: &GroomParams, full: f32) -> Vec<f32> {
    h.iter()
        .map(|h| (groom.thickness_limit * h).min(full))
        .collect()
}

/// 0 at and below 0, 1 at and above 1, smooth between.
fn smoothstep(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Per vertex, 0 (thick) to 1 (thin) from the half-thicknesses `h`.
fn flatness(h: &[f32]) -> Vec<f32> {
    let mut sorted: Vec<f32> = h.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(f32::total_cmp);
    let body = sorted
        .get(sorted.len() * BODY_PERCENTILE / 100)
        .copied()
        .unwrap_or(0.0)
        .max(f32::MIN_POSITIVE);
    h.iter()
        .map(|&v| 1.0 - smoothstep((v / body - THIN) / (THICK - THIN)))
        .collect()
}

/// Per vertex, the comb's tangent direction times the comb's length; where the body is
/// thin (`flat` above 0), blended towards the direction along the part, away from
/// where it joins the body.
fn directions(mesh: &Mesh, groom: &GroomParams, flat: &[f32]) -> Result<Vec<Vec3>> {
    let length = groom.comb_direction.length();
    let tangent = |n: Vec3, d: Vec3| (d - d.dot(n) * n).normalize_or_zero() * length;
    let normals = || {
        mesh.normals
            .iter()
            .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
    };
    match (groom.flow, &groom.comb_field) {
        (Flow::Body, Some(bones)) => {
            let fallback = groom.comb_direction.try_normalize().unwrap_or(Vec3::NEG_Y);
            let along = along_parts(mesh, flat)?;
            // As the constant comb, each vertex's own direction with a second across
            // it where the surface faces along it.
            Ok(normals()
                .zip(&bones.directions)
                .enumerate()
                .map(|(i, (n, d))| {
                    let d = match &along {
                        Some(a) if a[i] != Vec3::ZERO => d.normalize_or_zero().lerp(a[i], flat[i]),
                        _ => *d,
                    };
                    let primary = d.try_normalize().unwrap_or(fallback);
                    let secondary = primary.any_orthonormal_vector();
                    let along_first = primary - primary.dot(n) * n;
                    let blend = 1.0 - along_first.length();
                    (along_first + blend * (secondary - secondary.dot(n) * n)) * length
                })
                .collect())
        }
        (Flow::Body, None) => {
            let field = FlowField::build(mesh, groom.flow_from)?;
            let along = along_parts(mesh, flat)?;
            Ok(normals()
                .zip(&field.directions)
                .enumerate()
                .map(|(i, (n, d))| match &along {
                    Some(a) if a[i] != Vec3::ZERO => {
                        tangent(n, d.lerp(a[i], flat[i]).normalize_or(*d))
                    }
                    _ => tangent(n, *d),
                })
                .collect())
        }
        (Flow::Direction, _) => Ok(constant(mesh, groom)),
    }
}

/// Per vertex, the direction along a thin part: the flow of the heat method's distance
/// from the thick body (`flat` 0), which on a part runs from where it joins the body to
/// its tip whichever way the body's flow crosses it (the flow from a head end reaches
/// an ear's back over its rim, and there runs across the ear). Only a part thin
/// throughout beyond its join has one: somewhere on it the hair lies wholly flat (a
/// part thin only at its rim, as the blob's ears are, would get a field across it, from
/// the thick middle to the rim, and keeps the body's flow). `None` where no part is
/// thin.
fn along_parts(mesh: &Mesh, flat: &[f32]) -> Result<Option<Vec<Vec3>>> {
    // The thin parts: vertices with some flatness, joined by the mesh's edges and at
    // its seams; each a part of its own when somewhere on it the hair lies wholly flat.
    let (_, radius) = mesh.bounds();
    let (joined, count) = weld(&mesh.positions, radius * 1e-6);
    let thin = |v: u32| flat[v as usize] > 0.0;
    let edges = mesh.indices.chunks_exact(3).flat_map(|t| {
        [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
            .into_iter()
            .filter(|&(a, b)| thin(a) && thin(b))
            .map(|(a, b)| (joined[a as usize], joined[b as usize]))
    });
    let (part, parts) = pieces(count, edges);
    let mut thinnest = vec![0.0f32; parts];
    for (v, &f) in flat.iter().enumerate() {
        let p = part[joined[v] as usize] as usize;
        thinnest[p] = thinnest[p].max(f);
    }
    let on_part = |v: usize| thinnest[part[joined[v] as usize] as usize] >= 1.0;
    if !(0..flat.len()).any(on_part) {
        return Ok(None);
    }
    let thick: Vec<f32> = flat.iter().map(|&f| f32::from(f <= 0.0)).collect();
    let mut along = FlowField::from_heat(mesh, &thick)?.directions;
    for (v, a) in along.iter_mut().enumerate() {
        if !on_part(v) {
            *a = Vec3::ZERO;
        }
    }
    Ok(Some(along))
}

/// The constant comb: its direction projected onto each tangent plane. A second
/// direction across the first takes over where the surface faces along the first
/// (whose projection vanishes there and would swirl into a whorl): the direction
/// across the first closest to the model's back (−z).
fn constant(mesh: &Mesh, groom: &GroomParams) -> Vec<Vec3> {
    let primary = groom.comb_direction.try_normalize().unwrap_or(Vec3::NEG_Y);
    let secondary = (Vec3::NEG_Z - Vec3::NEG_Z.dot(primary) * primary)
        .try_normalize()
        .unwrap_or_else(|| primary.any_orthonormal_vector());
    let length = groom.comb_direction.length();
    mesh.normals
        .iter()
        .map(|normal| {
            let n = normal.try_normalize().unwrap_or(Vec3::Y);
            let along_first = primary - primary.dot(n) * n;
            let blend = 1.0 - along_first.length();
            (along_first + blend * (secondary - secondary.dot(n) * n)) * length
        })
        .collect()
}
