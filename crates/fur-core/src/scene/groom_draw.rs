//! `--groom-mode draw`: every guide of a groom is a master hair of its own, drawn as it
//! is, for grooms that are already dense.
//!
//! The fur pipeline roots master hairs at mesh vertices and draws hairs through
//! patches. Here each guide's root, bound to the nearest point of the surface, becomes
//! one more vertex of the body (its position, normal, texture coordinates and, on a
//! skinned body, skin weights blended from its triangle's corners by the barycentric
//! weights), a vertex no triangle of the body uses, so the body's surface, its field
//! and its mesh pass are the same. The guide is drawn through a degenerate patch
//! (g, g, g) that owns only its first corner: the tessellation gives it one point, at
//! that corner, so its one hair is the master hair itself ([`HairPatches`]). The body's
//! own vertices get the bald stub (or the grown hair, by `--groom-outside`), as in
//! blend mode.

use glam::{Vec2, Vec3};

use super::groom_bind::{bald_hair, bind_roots, resample, stub_step};
use super::{GroomParams, GroomReport, GroomSource, Mesh, Outside, Rig, Strands};
use crate::error::{Error, Result};
use crate::groom_file::Guides;

/// Patches the fur pass draws beyond the body's own triangles: three vertex indices
/// each, with their ownership masks and (for a textured body) their corner UVs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HairPatches {
    pub indices: Vec<u32>,
    /// Per patch, the corners and edges it owns ([`Mesh::ownership_masks`]' bits).
    pub masks: Vec<u32>,
    /// Per corner, its texture coordinates; empty when the body has none.
    pub uvs: Vec<Vec2>,
}

impl HairPatches {
    pub fn count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// A body with a drawn groom: the body grown by one vertex per guide, its rig likewise,
/// the master hairs (the body's vertices first, then one per guide) and the guides'
/// patches.
pub struct DrawnGroom {
    pub mesh: Mesh,
    pub rig: Option<Rig>,
    pub strands: Strands,
    pub patches: HairPatches,
    /// The body's own vertex count: the guides' master hairs are those from here on.
    pub body_vertices: usize,
    pub report: GroomReport,
}

impl DrawnGroom {
    /// Reads the groom `source` names and draws its guides on `mesh` (and `rig`).
    pub fn from_file(
        mesh: Mesh,
        rig: Option<Rig>,
        groom: &GroomParams,
        source: &GroomSource,
    ) -> Result<Self> {
        groom.validate()?;
        let guides = crate::groom_file::read_groom(&source.path)?;
        Self::new(mesh, rig, &guides, groom, source.outside).map_err(|m| Error::Groom {
            path: source.path.clone(),
            message: m,
        })
    }

    /// Draws `guides` (in the model's rest space) on `mesh`: see the module
    /// documentation. `groom` gives the segment count and, for [`Outside::Grow`], the
    /// hair grown on the body's vertices.
    pub fn new(
        mut mesh: Mesh,
        mut rig: Option<Rig>,
        guides: &Guides,
        groom: &GroomParams,
        outside: Outside,
    ) -> std::result::Result<Self, String> {
        let roots = bind_roots(&mesh, guides)?;
        let (_, radius) = mesh.bounds();
        let segments = groom.segments as usize;
        let body_vertices = mesh.vertex_count();
        let mut positions = match outside {
            Outside::Grow => {
                Strands::grow_from_mesh(&mesh, groom)
                    .map_err(|e| e.to_string())?
                    .positions
            }
            Outside::Bald => {
                let lengths = guides
                    .curves()
                    .map(|c| c.windows(2).map(|w| w[0].distance(w[1])).sum())
                    .collect();
                let step = stub_step(lengths, segments);
                (0..body_vertices)
                    .flat_map(|i| bald_hair(&mesh, i, step, segments))
                    .collect()
            }
        };
        let textured = mesh.uvs.len() == mesh.indices.len() && !mesh.uvs.is_empty();
        let mut patches = HairPatches::default();
        for (g, (curve, root)) in guides.curves().zip(&roots).enumerate() {
            // The guide as it is, resampled, its root moved onto the surface.
            let hair = resample(curve, segments);
            positions.extend(hair.iter().map(|&p| p - hair[0] + root.point));
            let v = (body_vertices + g) as u32;
            mesh.positions.push(root.point);
            mesh.normals.push(root.normal);
            patches.indices.extend([v, v, v]);
            patches.masks.push(1);
            let corners = 3 * root.triangle as usize..3 * root.triangle as usize + 3;
            let corner = |k: usize| mesh.indices[corners.start + k] as usize;
            if textured {
                let uv = (0..3)
                    .map(|k| root.barycentric[k] * mesh.uvs[corners.start + k])
                    .sum::<Vec2>();
                patches.uvs.extend([uv; 3]);
            }
            if let Some(rig) = rig.as_mut() {
                let triangle = [corner(0), corner(1), corner(2)];
                blend_skin(rig, triangle, root.barycentric);
            }
        }
        let strands = Strands {
            vertices_per_strand: groom.vertices_per_strand(),
            positions,
        };
        let report = GroomReport::of(guides, &roots, 0, radius);
        Ok(Self {
            mesh,
            rig,
            strands,
            patches,
            body_vertices,
            report,
        })
    }

    /// What to tell the user: the file's notes and the roots bound far from the body.
    pub fn warnings(&self) -> Vec<String> {
        self.report.warnings(self.mesh.bounds().1)
    }

    /// The guides' master hairs alone (what `fur export-groom` writes in draw mode).
    pub fn guide_strands(&self) -> Strands {
        let v = self.strands.vertices_per_strand as usize;
        Strands {
            vertices_per_strand: self.strands.vertices_per_strand,
            positions: self.strands.positions[self.body_vertices * v..].to_vec(),
        }
    }
}

impl Rig {
    /// The rig of the body's own `vertices` first vertices: a drawn groom's rig less
    /// its guides' roots (what a new session of the same body starts from).
    pub fn body_only(&self, vertices: usize) -> Rig {
        let mut rig = self.clone();
        rig.influences.truncate(vertices);
        rig.weights.truncate(vertices);
        rig.bind_positions.truncate(vertices);
        rig.bind_normals.truncate(vertices);
        rig
    }
}

/// Appends to `rig` a vertex at barycentric weights `b` of the body's `triangle`: its
/// bind position and normal the same blend of the corners', its skin the corners'
/// weights blended by `b`, the four heaviest joints kept and their weights summing to 1.
fn blend_skin(rig: &mut Rig, triangle: [usize; 3], b: Vec3) {
    let mut joints: Vec<(u16, f32)> = Vec::with_capacity(12);
    for (k, &c) in triangle.iter().enumerate() {
        for (&j, &w) in rig.influences[c].iter().zip(&rig.weights[c]) {
            let w = w * b[k];
            if w <= 0.0 {
                continue;
            }
            match joints.iter_mut().find(|(i, _)| *i == j) {
                Some(entry) => entry.1 += w,
                None => joints.push((j, w)),
            }
        }
    }
    joints.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    joints.truncate(4);
    let total: f32 = joints.iter().map(|j| j.1).sum();
    let mut influences = [0u16; 4];
    let mut weights = [0.0f32; 4];
    for (slot, &(j, w)) in joints.iter().enumerate() {
        influences[slot] = j;
        weights[slot] = if total > 0.0 { w / total } else { 0.0 };
    }
    if total <= 0.0 {
        // Corners with no weight on this side (b on an edge of unweighted corners):
        // the first corner's skin.
        influences = rig.influences[triangle[0]];
        weights = rig.weights[triangle[0]];
    }
    rig.influences.push(influences);
    rig.weights.push(weights);
    let blend = |v: &[Vec3]| (0..3).map(|k| b[k] * v[triangle[k]]).sum::<Vec3>();
    let position = blend(&rig.bind_positions);
    let normal = blend(&rig.bind_normals).try_normalize().unwrap_or(Vec3::Y);
    rig.bind_positions.push(position);
    rig.bind_normals.push(normal);
}

#[cfg(test)]
mod tests;
