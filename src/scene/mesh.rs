//! Triangle meshes: OBJ loading, generated models and the per-triangle ownership masks
//! that let every interpolated hair be drawn exactly once.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;

use crate::error::{Error, Result};

/// An indexed triangle mesh with one smooth normal per vertex. One master hair grows
/// from every vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Three indices per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Loads an OBJ file (all its objects, triangulated). Normals come from the file
    /// when every face has them, otherwise from area-weighted face normals. A UTF-8
    /// byte-order mark and bytes that are not UTF-8 (in comments and names, as some
    /// exporters write them) are accepted.
    pub fn load_obj(path: &Path) -> Result<Self> {
        let error = |message: String| Error::Model {
            path: path.to_path_buf(),
            message,
        };
        if path.is_dir() {
            return Err(error("it is a folder, not an OBJ file".into()));
        }
        if !path.exists() {
            return Err(error("no such file".into()));
        }
        let bytes = std::fs::read(path).map_err(|e| error(e.to_string()))?;
        Self::parse_obj(&bytes).map_err(error)
    }

    /// Parses OBJ text (see [`Mesh::load_obj`]); the error says what is wrong.
    pub fn parse_obj(bytes: &[u8]) -> std::result::Result<Self, String> {
        let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        let text = String::from_utf8_lossy(bytes);
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ignore_points: true,
            ignore_lines: true,
        };
        let (models, _materials) =
            tobj::load_obj_buf(&mut std::io::Cursor::new(text.as_bytes()), &options, |_| {
                Ok(Default::default())
            })
            .map_err(|e| format!("not a valid OBJ file ({e})"))?;
        let mut positions = Vec::new();
        let mut file_normals: Vec<Vec3> = Vec::new();
        let mut normal_indices: Vec<u32> = Vec::new();
        let mut indices = Vec::new();
        let mut all_faces_have_normals = true;
        for model in &models {
            let m = &model.mesh;
            if m.positions.len() % 3 != 0 {
                return Err(format!(
                    "object `{}` has a truncated position list",
                    model.name
                ));
            }
            let base = positions.len() as u32;
            let normal_base = file_normals.len() as u32;
            positions.extend(
                m.positions
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
            file_normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
            for &i in &m.indices {
                if (base + i) as usize >= positions.len() {
                    return Err(format!(
                        "object `{}` references vertex {} of {}",
                        model.name,
                        i + 1,
                        m.positions.len() / 3
                    ));
                }
                indices.push(base + i);
            }
            if m.normal_indices.len() == m.indices.len() && !m.normals.is_empty() {
                for &i in &m.normal_indices {
                    if i as usize >= m.normals.len() / 3 {
                        return Err(format!(
                            "object `{}` references normal {} of {}",
                            model.name,
                            i + 1,
                            m.normals.len() / 3
                        ));
                    }
                    normal_indices.push(normal_base + i);
                }
            } else if !m.indices.is_empty() {
                all_faces_have_normals = false;
            }
        }
        if indices.is_empty() {
            return Err("the file has no faces: fur grows from triangles".into());
        }
        if let Some(p) = positions.iter().find(|p| !p.is_finite()) {
            return Err(format!("a vertex position is not finite: {p}"));
        }
        let normals = if all_faces_have_normals {
            let mut normals = vec![Vec3::ZERO; positions.len()];
            for (&vi, &ni) in indices.iter().zip(&normal_indices) {
                normals[vi as usize] += file_normals[ni as usize];
            }
            normals
        } else {
            Vec::new()
        };
        let mut mesh = Self {
            positions,
            normals,
            indices,
        };
        mesh.drop_degenerate_triangles();
        if mesh.indices.is_empty() {
            return Err("every face is degenerate (zero area)".into());
        }
        mesh.compact();
        // A normal that cannot be normalised (zero, infinite or NaN: from broken `vn`
        // lines or ones that cancel out) discards the file's normals.
        if mesh.normals.is_empty() || mesh.normals.iter().any(|n| n.try_normalize().is_none()) {
            mesh.normals = mesh.face_weighted_normals();
        } else {
            mesh.normals.iter_mut().for_each(|n| *n = n.normalize());
        }
        Ok(mesh)
    }

    /// Writes the mesh as OBJ with positions, normals and faces.
    pub fn write_obj(&self, path: &Path) -> Result<()> {
        use std::fmt::Write as _;
        let mut text = String::from("# fur: generated model\n");
        for p in &self.positions {
            let _ = writeln!(text, "v {:.6} {:.6} {:.6}", p.x, p.y, p.z);
        }
        for n in &self.normals {
            let _ = writeln!(text, "vn {:.6} {:.6} {:.6}", n.x, n.y, n.z);
        }
        for t in self.indices.chunks_exact(3) {
            let (a, b, c) = (t[0] + 1, t[1] + 1, t[2] + 1);
            let _ = writeln!(text, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        std::fs::write(path, text).map_err(|e| Error::io("write the model to", path, e))
    }

    /// Per vertex, the model's half-thickness there: the deepest point inside the body
    /// along the inward normal (from a distance field of the mesh), so a thin ear or leg
    /// reads small and a round body large. A vertex whose inward ray finds no inside (an
    /// open or inside-out patch) gets the bounding radius.
    pub fn half_thickness(&self) -> Result<Vec<f32>> {
        let (_, radius) = self.bounds();
        let (sdf, _) = crate::sim::Sdf::build(self, 40, 0.05 * radius)?;
        const STEPS: usize = 24;
        Ok(self
            .positions
            .iter()
            .zip(&self.normals)
            .map(|(p, n)| {
                let deepest = (1..=STEPS)
                    .filter_map(|k| {
                        let q = *p - *n * (radius * k as f32 / STEPS as f32);
                        sdf.sample(crate::sim::V3::<f32>::from_vec3(q))
                            .map(|(d, _)| -d)
                    })
                    .fold(0.0f32, f32::max);
                if deepest > 0.0 {
                    deepest
                } else {
                    radius
                }
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

    /// Removes triangles with repeated indices or zero area.
    fn drop_degenerate_triangles(&mut self) {
        let positions = &self.positions;
        let kept: Vec<u32> = self
            .indices
            .chunks_exact(3)
            .filter(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
                t[0] != t[1]
                    && t[1] != t[2]
                    && t[0] != t[2]
                    && (b - a).cross(c - a).length_squared() > 0.0
            })
            .flatten()
            .copied()
            .collect();
        self.indices = kept;
    }

    /// Drops vertices no triangle uses: they would grow hairs nobody draws.
    fn compact(&mut self) {
        let mut remap = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        for i in self.indices.iter_mut() {
            let old = *i as usize;
            if remap[old] == u32::MAX {
                remap[old] = positions.len() as u32;
                positions.push(self.positions[old]);
                if let Some(n) = self.normals.get(old) {
                    normals.push(*n);
                }
            }
            *i = remap[old];
        }
        self.positions = positions;
        self.normals = normals;
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
        self.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// Bounding-sphere centre and radius (of the box around the vertices).
    pub fn bounds(&self) -> (Vec3, f32) {
        let (min, max) = self.aabb();
        // In f64: the squared diagonal of a model 1e20 units across overflows f32.
        let diagonal = (max.as_dvec3() - min.as_dvec3()).length();
        ((min * 0.5 + max * 0.5), (diagonal * 0.5) as f32)
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
