//! An imported groom on the body: every guide curve's root bound to the nearest point
//! of the surface, and one master hair per mesh vertex blended from its nearest guides
//! (their shapes carried into the vertex's own root frame), so interpolation, density,
//! simulation and collision work on it as on grown fur.

use std::path::PathBuf;

use glam::{Quat, Vec3};
use rayon::prelude::*;

use super::{GroomParams, Mesh, Strands};
use crate::error::{Error, Result};
use crate::geometry::grid::Grid;
use crate::groom_file::Guides;

/// A root farther than this from the surface (in bounding radii) is reported.
pub const BIND_TOLERANCE: f32 = 0.02;
/// A groom with a root farther than this from the surface (in bounding radii) is
/// refused: it was made for another body, or in another space.
pub const BIND_LIMIT: f32 = 0.25;
/// How many guides each master hair blends.
pub const BLEND_GUIDES: usize = 4;
/// A vertex is in the groomed region when its nearest guide root is within this many
/// times the guides' median spacing (root to nearest other root).
pub const REGION_SPACINGS: f32 = 2.0;
/// A bald vertex's master hair: this fraction of the guides' median length, along the
/// normal (a hair must have length for the simulation's constraints).
pub const BALD_FRACTION: f32 = 1e-3;
/// A vertex this close to a guide's root (in bounding radii) is that root: it takes
/// that guide alone, so a groom fur wrote comes back as the same hairs.
pub const EXACT_ROOT: f32 = 1e-6;

/// What vertices outside the groomed region get.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Outside {
    /// A stub a thousandth of the guides' length; the tessellation draws nothing on a
    /// triangle whose three masters are stubs ([`crate::render::STUB_LIMIT`]).
    #[default]
    Bald,
    /// The hair fur grows there from the groom settings.
    Grow,
}

impl Outside {
    pub const ALL: [Self; 2] = [Self::Bald, Self::Grow];

    pub fn name(self) -> &'static str {
        match self {
            Self::Bald => "bald",
            Self::Grow => "grow",
        }
    }
}

impl std::str::FromStr for Outside {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|o| o.name() == s)
            .ok_or_else(|| format!("`{s}` is not bald or grow"))
    }
}

/// How a groom's guides become the hairs drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GroomMode {
    /// Each body vertex in the groom's region blends its nearest guides into a master
    /// hair, and the tessellation interpolates hairs between masters.
    #[default]
    Blend,
    /// Each guide is a master hair of its own, rooted where it binds to the surface,
    /// and drawn as it is: one hair per guide, no interpolation (for grooms that are
    /// already dense). See `groom_draw`.
    Draw,
}

impl GroomMode {
    pub const ALL: [Self; 2] = [Self::Blend, Self::Draw];

    pub fn name(self) -> &'static str {
        match self {
            Self::Blend => "blend",
            Self::Draw => "draw",
        }
    }
}

impl std::str::FromStr for GroomMode {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|o| o.name() == s)
            .ok_or_else(|| format!("`{s}` is not blend or draw"))
    }
}

/// Where a groom comes from, how its guides are drawn and what the rest of the body
/// gets.
#[derive(Clone, Debug, PartialEq)]
pub struct GroomSource {
    pub path: PathBuf,
    pub outside: Outside,
    pub mode: GroomMode,
}

/// The nearest point of the surface to a guide's root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    pub triangle: u32,
    pub barycentric: Vec3,
    pub point: Vec3,
    /// The vertex normals interpolated there, normalised.
    pub normal: Vec3,
    /// From the root to `point`.
    pub distance: f32,
}

/// The closest point of triangle (a, b, c) to p, as barycentric weights (Ericson,
/// Real-Time Collision Detection, 5.1.5).
pub fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Vec3::X;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Vec3::Y;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return Vec3::new(1.0 - v, v, 0.0);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Vec3::Z;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return Vec3::new(1.0 - w, 0.0, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Vec3::new(0.0, 1.0 - w, w);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    Vec3::new(1.0 - v - w, v, w)
}

/// The nearest point of `mesh`'s surface to `p` (every triangle tried).
pub fn nearest_surface_point(mesh: &Mesh, p: Vec3) -> SurfacePoint {
    let all: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
    surface_point(mesh, p, all.into_iter())
}

/// The point on `mesh`'s triangle `t` nearest to `p`.
fn on_triangle(mesh: &Mesh, t: u32, p: Vec3) -> SurfacePoint {
    let tri = &mesh.indices[3 * t as usize..3 * t as usize + 3];
    let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize]);
    let w = closest_on_triangle(p, a, b, c);
    let q = w.x * a + w.y * b + w.z * c;
    let n = w.x * mesh.normals[tri[0] as usize]
        + w.y * mesh.normals[tri[1] as usize]
        + w.z * mesh.normals[tri[2] as usize];
    SurfacePoint {
        triangle: t,
        barycentric: w,
        point: q,
        normal: n.try_normalize().unwrap_or(Vec3::Y),
        distance: q.distance(p),
    }
}

fn surface_point(mesh: &Mesh, p: Vec3, triangles: impl Iterator<Item = u32>) -> SurfacePoint {
    triangles
        .map(|t| on_triangle(mesh, t, p))
        .min_by(|a, b| a.distance.total_cmp(&b.distance))
        .unwrap_or(SurfacePoint {
            triangle: 0,
            barycentric: Vec3::X,
            point: p,
            normal: Vec3::Y,
            distance: f32::MAX,
        })
}

/// The body's triangles in a grid, for nearest-point queries.
fn triangle_grid(mesh: &Mesh) -> Grid {
    let boxes: Vec<(Vec3, Vec3)> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
            (a.min(b).min(c), a.max(b).max(c))
        })
        .collect();
    Grid::new(&boxes)
}

/// What binding a groom found, for the user.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GroomReport {
    pub guides: usize,
    /// Vertices in the groomed region.
    pub groomed_vertices: usize,
    /// Roots farther than [`BIND_TOLERANCE`] from the surface, and the farthest.
    pub far_roots: usize,
    pub farthest: f32,
    /// What reading the file changed (from [`Guides::notes`]).
    pub notes: Vec<String>,
}

impl GroomReport {
    /// What binding `guides` at `roots` found, `groomed` vertices in their region, on a
    /// body of bounding radius `radius`.
    pub(super) fn of(guides: &Guides, roots: &[SurfacePoint], groomed: usize, radius: f32) -> Self {
        Self {
            guides: guides.count(),
            groomed_vertices: groomed,
            far_roots: roots
                .iter()
                .filter(|r| r.distance > BIND_TOLERANCE * radius)
                .count(),
            farthest: roots.iter().map(|r| r.distance).fold(0.0, f32::max),
            notes: guides.notes.clone(),
        }
    }

    /// The lines to show the user: the notes and the far roots.
    pub fn warnings(&self, radius: f32) -> Vec<String> {
        let mut out = self.notes.clone();
        if self.far_roots > 0 {
            out.push(format!(
                "{} of {} guide roots lie farther than {} bounding radii from the body's \
                 surface (the farthest {:.3}); they are bound to the nearest surface point",
                self.far_roots,
                self.guides,
                BIND_TOLERANCE,
                self.farthest / radius
            ));
        }
        out
    }
}

/// `polyline` resampled to `segments` equal steps of its arc length.
pub fn resample(polyline: &[Vec3], segments: usize) -> Vec<Vec3> {
    let lengths: Vec<f32> = polyline.windows(2).map(|w| w[0].distance(w[1])).collect();
    let total: f32 = lengths.iter().sum();
    let mut out = Vec::with_capacity(segments + 1);
    let (mut k, mut before) = (0, 0.0f32);
    for s in 0..=segments {
        let at = total * s as f32 / segments as f32;
        while k + 1 < lengths.len() && before + lengths[k] < at {
            before += lengths[k];
            k += 1;
        }
        let t = if lengths[k] > 0.0 {
            ((at - before) / lengths[k]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(polyline[k].lerp(polyline[k + 1], t));
    }
    out
}

impl Strands {
    /// One master hair per vertex of `mesh` from the guide curves `guides` (in the
    /// model's rest space): see the module documentation. `groom` gives the segment
    /// count and, for [`Outside::Grow`], the grown hair.
    pub fn from_guides(
        mesh: &Mesh,
        guides: &Guides,
        groom: &GroomParams,
        outside: Outside,
    ) -> std::result::Result<(Self, GroomReport), String> {
        let (_, radius) = mesh.bounds();
        let segments = groom.segments as usize;
        let roots = bind_roots(mesh, guides)?;
        let root_grid = Grid::new(&roots.iter().map(|r| (r.point, r.point)).collect::<Vec<_>>());
        let shapes: Vec<Vec<Vec3>> = guides
            .curves()
            .map(|c| {
                let r = resample(c, segments);
                r.iter().map(|&p| p - r[0]).collect()
            })
            .collect();
        let spacing = median(
            roots
                .par_iter()
                .enumerate()
                .map(|(i, a)| {
                    root_grid
                        .nearest(a.point, 2, |j| a.point.distance(roots[j as usize].point))
                        .iter()
                        .find(|&&(_, j)| j as usize != i)
                        .map_or(f32::MAX, |n| n.0)
                })
                .collect(),
        );
        let region = if roots.len() > 1 {
            REGION_SPACINGS * spacing
        } else {
            f32::MAX
        };
        let lengths = guides
            .curves()
            .map(|c| c.windows(2).map(|w| w[0].distance(w[1])).sum())
            .collect();
        let stub = stub_step(lengths, segments);
        let grown = match outside {
            Outside::Grow => Some(Strands::grow_from_mesh(mesh, groom).map_err(|e| e.to_string())?),
            Outside::Bald => None,
        };
        let exact = EXACT_ROOT * radius;
        let per_vertex: Vec<Option<Vec<Vec3>>> = mesh
            .positions
            .par_iter()
            .zip(&mesh.normals)
            .map(|(&v, &n)| {
                let n = n.try_normalize().unwrap_or(Vec3::Y);
                let near: Vec<(f32, usize)> = root_grid
                    .nearest(v, BLEND_GUIDES, |g| roots[g as usize].point.distance(v))
                    .into_iter()
                    .map(|(d, g)| (d, g as usize))
                    .collect();
                if near[0].0 > region {
                    return None;
                }
                let mut shape = vec![Vec3::ZERO; segments + 1];
                let mut total = 0.0;
                for &(d, g) in near
                    .iter()
                    .take(if near[0].0 <= exact { 1 } else { BLEND_GUIDES })
                {
                    if d > region {
                        break;
                    }
                    let w = 1.0 / (d * d + exact * exact);
                    let turn = Quat::from_rotation_arc(roots[g].normal, n);
                    for (s, o) in shape.iter_mut().zip(&shapes[g]) {
                        *s += w * (turn * *o);
                    }
                    total += w;
                }
                Some(shape.iter().map(|s| v + *s / total).collect())
            })
            .collect();
        let mut positions = Vec::with_capacity(mesh.vertex_count() * (segments + 1));
        let mut groomed = 0;
        for (i, hair) in per_vertex.into_iter().enumerate() {
            match (hair, &grown) {
                (Some(h), _) => {
                    groomed += 1;
                    positions.extend(h);
                }
                (None, Some(g)) => positions.extend_from_slice(g.strand(i)),
                (None, None) => positions.extend(bald_hair(mesh, i, stub, segments)),
            }
        }
        if groomed == 0 {
            return Err("no vertex of the body lies near a guide root".into());
        }
        let report = GroomReport::of(guides, &roots, groomed, radius);
        Ok((
            Strands {
                vertices_per_strand: groom.vertices_per_strand(),
                positions,
            },
            report,
        ))
    }

    /// The master hairs as guide curves (for writing a groom).
    pub fn to_guides(&self, width: Option<f32>) -> Guides {
        Guides {
            counts: vec![self.vertices_per_strand; self.count()],
            points: self.positions.clone(),
            widths: width.map(|w| vec![w; self.positions.len()]),
            colors: None,
            notes: Vec::new(),
        }
    }
}

/// Every guide's root bound to the nearest point of `mesh`'s surface; refused when a
/// root lies farther than [`BIND_LIMIT`] from it.
pub(super) fn bind_roots(
    mesh: &Mesh,
    guides: &Guides,
) -> std::result::Result<Vec<SurfacePoint>, String> {
    guides.validate()?;
    let (_, radius) = mesh.bounds();
    let triangles = triangle_grid(mesh);
    let roots: Vec<SurfacePoint> = guides
        .curves()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|c| {
            let near = triangles.nearest(c[0], 1, |t| on_triangle(mesh, t, c[0]).distance);
            on_triangle(mesh, near.first().map_or(0, |n| n.1), c[0])
        })
        .collect();
    let farthest = roots.iter().map(|r| r.distance).fold(0.0, f32::max);
    let beyond = roots
        .iter()
        .filter(|r| r.distance > BIND_LIMIT * radius)
        .count();
    if beyond > 0 {
        return Err(format!(
            "{beyond} of {} guide roots lie farther than {BIND_LIMIT} bounding radii from \
             the body's surface (the farthest {:.3}): the groom does not fit this body \
             (another model, or another unit or placement)",
            roots.len(),
            farthest / radius
        ));
    }
    Ok(roots)
}

/// The step of a bald vertex's stub for guides of these `lengths`: a
/// [`BALD_FRACTION`] of their median length, over `segments` steps.
pub(super) fn stub_step(lengths: Vec<f32>, segments: usize) -> f32 {
    BALD_FRACTION * median(lengths).max(f32::MIN_POSITIVE) / segments as f32
}

/// Vertex `i`'s bald master hair: a stub of `segments` steps of `step` along its normal.
pub(super) fn bald_hair(mesh: &Mesh, i: usize, step: f32, segments: usize) -> Vec<Vec3> {
    let n = mesh.normals[i].try_normalize().unwrap_or(Vec3::Y);
    (0..=segments)
        .map(|k| mesh.positions[i] + n * step * k as f32)
        .collect()
}

fn median(mut v: Vec<f32>) -> f32 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

/// Reads the groom `source` names and makes the master hairs from it, with what to
/// tell the user.
pub fn strands_from_file(
    mesh: &Mesh,
    groom: &GroomParams,
    source: &GroomSource,
) -> Result<(Strands, Vec<String>)> {
    let guides = crate::groom_file::read_groom(&source.path)?;
    let (strands, report) =
        Strands::from_guides(mesh, &guides, groom, source.outside).map_err(|m| Error::Groom {
            path: source.path.clone(),
            message: m,
        })?;
    let (_, radius) = mesh.bounds();
    Ok((strands, report.warnings(radius)))
}
