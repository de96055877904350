//! Triangle meshes: their data, bounds and normals, and the per-triangle ownership masks
//! that let every interpolated hair be drawn exactly once (OBJ files: `obj.rs`;
//! generated models: `shapes.rs`).

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::TextureSpec;
use crate::error::Result;
use crate::geometry::{Sdf, Triangles, V3};

/// An indexed triangle mesh with one smooth normal per vertex. One master hair grows
/// from every vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Three indices per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
    /// Texture coordinates, one per triangle corner (`uvs[k]` belongs to `indices[k]`,
    /// so seams are exact), or empty when the model has none. Image convention: (0, 0)
    /// is the top-left corner of the image's first row, v grows downwards (as Vulkan
    /// samples); OBJ's `vt` (v up) is flipped on reading and writing. Values outside
    /// [0, 1] repeat.
    pub uvs: Vec<Vec2>,
    /// The model's colour texture: for an OBJ file, the diffuse texture (`map_Kd`) of
    /// the first material its faces use, as a [`TextureSpec::File`] resolved against
    /// the OBJ file's folder; `None` when it names none. Not checked to exist:
    /// [`TextureSpec::load`] reports that.
    pub texture: Option<TextureSpec>,
}

impl Mesh {
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Per vertex, the model's half-thickness there: the deepest point inside the body
    /// along the inward normal before the ray leaves the body (from a distance field of
    /// the mesh), so a thin ear or leg reads small and a round body large. A vertex
    /// whose inward ray finds no inside within two cells of the field gets half a cell
    /// on a closed model (a part thinner than the field can see) and the bounding
    /// radius on an open one (a patch with no inside).
    pub fn half_thickness(&self) -> Result<Vec<f32>> {
        Ok(self.half_thicknesses(&[false])?.remove(0))
    }

    /// [`Mesh::half_thickness`] as earlier versions measured it: the deepest point along
    /// the whole inward ray (through the body and into any part behind it), and a
    /// vertex whose ray finds no inside gets the bounding radius. Skinned bodies keep
    /// it: the walking critter's collision is tuned on the hair it grows (its ears'
    /// full-length hair; measured by `tests/skinning/depth.rs`).
    pub fn half_thickness_through(&self) -> Result<Vec<f32>> {
        Ok(self.half_thicknesses(&[true])?.remove(0))
    }

    /// Both measures, [`Mesh::half_thickness`] and [`Mesh::half_thickness_through`],
    /// from one distance field.
    pub fn half_thickness_both(&self) -> Result<(Vec<f32>, Vec<f32>)> {
        let mut both = self.half_thicknesses(&[false, true])?;
        let through = both.pop().unwrap_or_default();
        Ok((both.pop().unwrap_or_default(), through))
    }

    /// The half-thicknesses for each of `throughs` (whether the ray goes through the
    /// body), from one distance field.
    fn half_thicknesses(&self, throughs: &[bool]) -> Result<Vec<Vec<f32>>> {
        const RESOLUTION: u32 = 40;
        const STEPS: usize = 24;
        let (_, radius) = self.bounds();
        let padding = 0.05 * radius;
        let (sdf, report) = Sdf::build(self, RESOLUTION, padding)?;
        let (lo, hi) = self.aabb();
        let cell = ((hi - lo).max_element() + 2.0 * padding) / RESOLUTION as f32;
        Ok(throughs
            .iter()
            .map(|&through| {
                let unseen = if report.closed() && !through {
                    0.5 * cell
                } else {
                    radius
                };
                // Every 1/24 of the radius (and, but through, eight times finer over
                // the first of those).
                let fine = (1..8)
                    .filter(|_| !through)
                    .map(|k| radius * k as f32 / (8 * STEPS) as f32);
                let depths: Vec<f32> = fine
                    .chain((1..=STEPS).map(|k| radius * k as f32 / STEPS as f32))
                    .collect();
                self.positions
                    .iter()
                    .zip(&self.normals)
                    .map(|(p, n)| {
                        let mut deepest = 0.0f32;
                        for &depth in &depths {
                            let inside = sdf
                                .sample(V3::<f32>::from_vec3(*p - *n * depth))
                                .map_or(0.0, |(d, _)| -d);
                            if inside > 0.0 {
                                deepest = deepest.max(inside);
                            } else if !through && (deepest > 0.0 || depth > 2.0 * cell) {
                                break;
                            }
                        }
                        if deepest > 0.0 {
                            deepest
                        } else {
                            unseen
                        }
                    })
                    .collect()
            })
            .collect())
    }

    /// Bounding radii a model is drawn at as it is; outside, [`Mesh::normalize_scale`]
    /// rescales it.
    pub const SCALE_RANGE: (f32, f32) = (1e-3, 1e4);

    /// Scales a model whose bounding radius is outside [`Mesh::SCALE_RANGE`] (about the
    /// origin) to a radius of 1 (fur, camera and collision follow the model's size, but
    /// the depth range and the simulation's forces need a sane one). Returns the factor
    /// applied, if any.
    pub fn normalize_scale(&mut self) -> Option<f32> {
        let (_, radius) = self.bounds();
        let (lo, hi) = Self::SCALE_RANGE;
        if (lo..=hi).contains(&radius) {
            return None;
        }
        let factor = 1.0 / radius;
        for p in &mut self.positions {
            *p *= factor;
        }
        Some(factor)
    }

    /// Flips the normals when most of them point into the model (an inside-out mesh:
    /// fur would grow inwards). Returns whether it did.
    pub fn orient_outwards(&mut self) -> bool {
        let (centre, _) = self.bounds();
        let outward: f32 = self
            .positions
            .iter()
            .zip(&self.normals)
            .map(|(p, n)| n.dot(*p - centre).signum())
            .sum();
        if outward >= 0.0 {
            return false;
        }
        self.normals.iter_mut().for_each(|n| *n = -*n);
        true
    }

    /// Area-weighted vertex normals from the triangles.
    pub fn face_weighted_normals(&self) -> Vec<Vec3> {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for t in self.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| self.positions[i as usize]);
            let n = (b - a).cross(c - a); // length = twice the area
            for &i in t {
                normals[i as usize] += n;
            }
        }
        normals
            .into_iter()
            .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
            .collect()
    }

    /// The axis-aligned bounding box: (min corner, max corner).
    pub fn aabb(&self) -> (Vec3, Vec3) {
        self.triangles().aabb()
    }

    /// Bounding-sphere centre and radius (of the box around the vertices).
    pub fn bounds(&self) -> (Vec3, f32) {
        self.triangles().bounds()
    }

    /// The positions and indices, as the geometry below the scene takes them.
    pub fn triangles(&self) -> Triangles<'_> {
        Triangles {
            positions: &self.positions,
            indices: &self.indices,
        }
    }

    /// The number of distinct undirected edges.
    pub fn edge_count(&self) -> usize {
        let mut edges = std::collections::HashSet::new();
        for t in self.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        edges.len()
    }

    /// Per triangle, which of its corners and edges it owns (the first triangle that
    /// uses a vertex or edge owns it). Bit `k` (0..3): corner `k`; bit `3 + k`: the edge
    /// opposite corner `k`. Tessellation generates shared corner and edge points once
    /// per adjacent patch; only the owner draws them.
    pub fn ownership_masks(&self) -> Vec<u32> {
        let mut vertex_owned = vec![false; self.positions.len()];
        let mut edge_owned: HashMap<(u32, u32), ()> = HashMap::new();
        self.indices
            .chunks_exact(3)
            .map(|t| {
                let mut mask = 0;
                for k in 0..3 {
                    if !vertex_owned[t[k] as usize] {
                        vertex_owned[t[k] as usize] = true;
                        mask |= 1 << k;
                    }
                    let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                    if edge_owned.insert((a.min(b), a.max(b)), ()).is_none() {
                        mask |= 1 << (3 + k);
                    }
                }
                mask
            })
            .collect()
    }
}

impl<'a> From<&'a Mesh> for Triangles<'a> {
    fn from(mesh: &'a Mesh) -> Self {
        mesh.triangles()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_counts_follow_euler() {
        let m = Mesh::icosphere(3);
        assert_eq!(m.triangle_count(), 20 * 4usize.pow(3));
        // V - E + F = 2 for a closed genus-0 surface.
        assert_eq!(m.vertex_count() + m.triangle_count(), m.edge_count() + 2);
    }

    #[test]
    fn the_original_uv_sphere_has_its_counts_and_faces_outwards() {
        let m = Mesh::uv_sphere(2.0, 40, 80);
        assert_eq!(m.vertex_count(), 3161);
        assert_eq!(m.triangle_count(), 6240);
        for t in m.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 0.0, "degenerate triangle {t:?}");
            assert!(n.dot(a + b + c) > 0.0, "triangle {t:?} faces inwards");
        }
        assert!(m.positions.iter().all(|p| (p.length() - 2.0).abs() < 1e-5));
        assert_eq!(m.positions[0], Vec3::new(0.0, 0.0, 2.0));
    }

    #[test]
    fn ownership_assigns_every_corner_and_edge_once() {
        let m = Mesh::blob();
        let masks = m.ownership_masks();
        let corners: u32 = masks.iter().map(|m| (m & 7).count_ones()).sum();
        let edges: u32 = masks.iter().map(|m| (m >> 3).count_ones()).sum();
        assert_eq!(corners as usize, m.vertex_count());
        assert_eq!(edges as usize, m.edge_count());
    }

    #[test]
    fn blob_normals_point_outwards() {
        let m = Mesh::blob();
        let (c, _) = m.bounds();
        let outward = m
            .positions
            .iter()
            .zip(&m.normals)
            .filter(|(p, n)| (**p - c).dot(**n) > 0.0)
            .count();
        assert!(outward as f32 > 0.95 * m.vertex_count() as f32, "{outward}");
    }
}
