//! Which way grown fur lies: a flow field along the body, from a head end to every
//! other end. The field is the gradient of the geodesic distance from the head end
//! (the heat method, `flow/heat.rs`), so hair runs from the head end back and down
//! every limb, and the field's singular points (whorls, where hair parts from or meets
//! at a point; saddles, where a part joins the body) fall where the distance has its
//! critical points: at the head end, at the tips of the parts, and where they join.

use std::fmt;

use glam::{DVec3, Vec3};

use super::Mesh;
use crate::error::{Error, Result};

mod heat;
mod singular;
#[cfg(test)]
mod tests;

pub use singular::{critical_points, singular_points, Singularity};

/// How grown fur is combed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Flow {
    /// Along the body from its head end ([`FlowFrom`]); a skinned body's along its bones.
    #[default]
    Body,
    /// Towards one constant direction projected onto each tangent plane (the comb of
    /// earlier versions: whorls fall wherever the normal is parallel to it).
    Direction,
}

impl Flow {
    pub const ALL: [Flow; 2] = [Flow::Body, Flow::Direction];

    pub fn name(self) -> &'static str {
        match self {
            Flow::Body => "body",
            Flow::Direction => "direction",
        }
    }
}

impl std::str::FromStr for Flow {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Flow::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| format!("unknown flow `{s}` (expected body or direction)"))
    }
}

/// Where the body's head end is: the flow starts there.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum FlowFrom {
    /// The end of the body's longest axis (its principal axis, by area) that faces
    /// forward (+z, glTF's front); an axis across z takes its upper (+y) end, and
    /// one across both its +x end.
    #[default]
    Auto,
    /// The end of the body furthest along this unit direction (`+x`, `-z`…).
    Axis(Vec3),
    /// The surface nearest this point, in the model's space.
    Point(Vec3),
}

/// A vertex whose triangles' distance gradients, summed, keep less than this fraction
/// of their lengths' sum is a centre the flow turns about.
pub const CANCELLED: f64 = 0.3;

/// [`FlowFrom::Auto`] takes an axis's +z end if it leans at least this much towards z
/// (its z component), else its +y end by the same rule, else its +x end.
pub const AXIS_LEAN: f64 = 0.3;

/// How much of the body's extent along the axis the head end's cap takes.
pub const CAP: f64 = 0.03;

impl fmt::Display for FlowFrom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FlowFrom::Auto => write!(f, "auto"),
            FlowFrom::Axis(a) => {
                let (i, v) = (0..3)
                    .map(|i| (i, a[i]))
                    .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
                    .unwrap_or((0, 1.0));
                let sign = if v < 0.0 { '-' } else { '+' };
                write!(f, "{sign}{}", ['x', 'y', 'z'][i])
            }
            FlowFrom::Point(p) => write!(f, "{},{},{}", p.x, p.y, p.z),
        }
    }
}

impl std::str::FromStr for FlowFrom {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let s = s.trim();
        if s == "auto" {
            return Ok(FlowFrom::Auto);
        }
        let axis = |c: &str| match c {
            "x" => Some(Vec3::X),
            "y" => Some(Vec3::Y),
            "z" => Some(Vec3::Z),
            _ => None,
        };
        if let Some(rest) = s.strip_prefix('+') {
            if let Some(a) = axis(rest) {
                return Ok(FlowFrom::Axis(a));
            }
        }
        if let Some(rest) = s.strip_prefix('-') {
            if let Some(a) = axis(rest) {
                return Ok(FlowFrom::Axis(-a));
            }
        }
        let numbers: Vec<&str> = s.split(',').map(str::trim).collect();
        if let [x, y, z] = numbers[..] {
            let parsed: Option<Vec<f32>> = [x, y, z].iter().map(|n| n.parse().ok()).collect();
            if let Some(v) = parsed.map(|v| Vec3::new(v[0], v[1], v[2])) {
                if v.is_finite() {
                    return Ok(FlowFrom::Point(v));
                }
            }
        }
        Err(format!(
            "`{s}` is not a place to start the flow (expected auto, an axis end such as \
             +x or -z, or a point x,y,z)"
        ))
    }
}

/// A flow field: per mesh vertex, the unit tangent direction hair lies in (zero where
/// the field has no direction), and the geodesic distance from the head end.
#[derive(Clone, Debug)]
pub struct FlowField {
    pub directions: Vec<Vec3>,
    pub distance: Vec<f32>,
    /// The mesh vertices the flow starts from.
    pub sources: Vec<u32>,
}

/// The heat's diffusion time is this fraction of the body's size, squared (and at
/// least the squared mean edge length): long enough that the heat reaches the far
/// ends of a model of any resolution within the range of an f64, short enough that
/// the distance stays geodesic.
pub const HEAT_TIME: f64 = 0.05;

impl FlowField {
    /// The field along `mesh` from `from`.
    pub fn build(mesh: &Mesh, from: FlowFrom) -> Result<Self> {
        let surface = surface(mesh)?;
        let sources = head_end(&surface, from);
        Self::solve(mesh, &surface, &sources)
    }

    /// The field along `mesh` away from where the heat starts: `heat` per mesh
    /// vertex (0 where none starts; vertices at one position take the most of theirs).
    pub fn from_heat(mesh: &Mesh, heat: &[f32]) -> Result<Self> {
        if heat.len() != mesh.vertex_count() {
            return Err(Error::Parameter(format!(
                "{} heat values for {} vertices",
                heat.len(),
                mesh.vertex_count()
            )));
        }
        let surface = surface(mesh)?;
        let mut sources = vec![0.0f64; surface.len()];
        for (h, &j) in heat.iter().zip(&surface.joined) {
            let s = &mut sources[j as usize];
            *s = s.max(f64::from(h.max(0.0)));
        }
        Self::solve(mesh, &surface, &sources)
    }

    fn solve(mesh: &Mesh, surface: &heat::Surface, sources: &[f64]) -> Result<Self> {
        let (lo, hi) = mesh.aabb();
        let size = f64::from(hi.distance(lo));
        let time = (HEAT_TIME * size)
            .powi(2)
            .max(surface.spacing * surface.spacing);
        let distance = surface.distance(sources, time)?;
        // Per joined vertex, the area-weighted gradient of the distance; where the
        // gradients around a vertex cancel, the flow turns about it (it is a whorl's or
        // a saddle's centre) and has no direction there.
        let mut sum = vec![(DVec3::ZERO, 0.0); surface.len()];
        for t in &surface.triangles {
            let p = t.map(|i| surface.positions[i as usize]);
            let g = heat::gradient(p, t.map(|i| distance[i as usize]));
            let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            for &i in t {
                let s = &mut sum[i as usize];
                *s = (s.0 + area * g, s.1 + area * g.length());
            }
        }
        let directions = mesh
            .normals
            .iter()
            .zip(&surface.joined)
            .map(|(n, &j)| {
                let (g, magnitude) = sum[j as usize];
                if g.length() <= CANCELLED * magnitude {
                    return Vec3::ZERO;
                }
                let (g, n) = (g.as_vec3(), n.normalize_or_zero());
                (g - g.dot(n) * n).normalize_or_zero()
            })
            .collect();
        Ok(Self {
            directions,
            distance: surface
                .joined
                .iter()
                .map(|&j| distance[j as usize] as f32)
                .collect(),
            sources: (0..mesh.vertex_count() as u32)
                .filter(|&v| sources[surface.joined[v as usize] as usize] > 0.0)
                .collect(),
        })
    }

    /// Where the flow turns: the critical points of its distance
    /// ([`critical_points`]), exact where [`singular_points`] of the directions can
    /// miss a point at which neighbouring directions differ by half a turn.
    pub fn singular_points(&self, mesh: &Mesh) -> Vec<Singularity> {
        critical_points(mesh, &self.distance)
    }
}

/// `mesh` as the heat method sees it, refusing a vertex that is not finite.
fn surface(mesh: &Mesh) -> Result<heat::Surface> {
    if mesh.positions.iter().any(|p| !p.is_finite()) {
        return Err(Error::Parameter(
            "the model has a vertex that is not finite; no flow can be laid on it".into(),
        ));
    }
    heat::Surface::new(&mesh.positions, &mesh.indices)
}

/// The body's longest axis (by area), pointing to its head end by [`FlowFrom::Auto`]'s
/// rule.
fn auto_axis(surface: &heat::Surface) -> DVec3 {
    let total: f64 = surface.mass.iter().sum();
    let centre = surface
        .positions
        .iter()
        .zip(&surface.mass)
        .map(|(p, m)| *p * *m)
        .sum::<DVec3>()
        / total.max(f64::MIN_POSITIVE);
    let mut covariance = faer::Mat::<f64>::zeros(3, 3);
    for (p, m) in surface.positions.iter().zip(&surface.mass) {
        let d = *p - centre;
        for r in 0..3 {
            for c in 0..3 {
                covariance[(r, c)] += m * d[r] * d[c];
            }
        }
    }
    let axis = covariance
        .self_adjoint_eigen(faer::Side::Lower)
        .ok()
        .and_then(|e| {
            let (s, u) = (e.S(), e.U());
            (0..3)
                .max_by(|&a, &b| s[a].total_cmp(&s[b]))
                .map(|k| DVec3::new(u[(0, k)], u[(1, k)], u[(2, k)]))
        })
        .filter(|a| a.is_finite() && a.length() > 0.5)
        .unwrap_or(DVec3::Z);
    // Forward, else up, else +x: the first of z, y, x the axis leans towards.
    let sign = [2, 1, 0]
        .into_iter()
        .find(|&c| axis[c].abs() >= AXIS_LEAN)
        .map_or(1.0, |c| axis[c].signum());
    axis * sign
}

/// The heat the flow starts from, per joined vertex: in each piece of the surface, a
/// peak at its head end (rising linearly over the last [`CAP`] of the piece's extent
/// along the axis to 1 at its far end), or at its vertex nearest the point.
fn head_end(surface: &heat::Surface, from: FlowFrom) -> Vec<f64> {
    let mut heat = vec![0.0; surface.len()];
    let axis = match from {
        FlowFrom::Auto => auto_axis(surface),
        FlowFrom::Axis(a) => a.as_dvec3().normalize_or(DVec3::Z),
        FlowFrom::Point(p) => {
            let p = p.as_dvec3();
            let mut nearest = vec![(f64::INFINITY, 0usize); surface.pieces];
            for (i, q) in surface.positions.iter().enumerate() {
                let best = &mut nearest[surface.piece[i] as usize];
                let d = q.distance_squared(p);
                if d < best.0 {
                    *best = (d, i);
                }
            }
            for (_, i) in nearest {
                heat[i] = 1.0;
            }
            return heat;
        }
    };
    let mut range = vec![(f64::INFINITY, f64::NEG_INFINITY); surface.pieces];
    for (i, q) in surface.positions.iter().enumerate() {
        let r = &mut range[surface.piece[i] as usize];
        let along = q.dot(axis);
        *r = (r.0.min(along), r.1.max(along));
    }
    for (i, q) in surface.positions.iter().enumerate() {
        let (lo, hi) = range[surface.piece[i] as usize];
        let cap = (CAP * (hi - lo)).max(f64::MIN_POSITIVE);
        heat[i] = ((q.dot(axis) - (hi - cap)) / cap).max(0.0);
    }
    heat
}
