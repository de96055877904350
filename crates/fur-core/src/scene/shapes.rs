//! Generated models: the default blob, icospheres, UV spheres and flat grids, each with
//! texture coordinates per triangle corner.

use std::collections::HashMap;
use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use super::Mesh;

impl Mesh {
    /// The default model: a lumpy blob with two ears, a dented face and ridged flanks,
    /// so the fur shows over convex and concave regions alike. Its texture coordinates
    /// are [`Mesh::spherical_uvs`] (ears towards v = 0, belly towards v = 1, the seam
    /// behind).
    pub fn blob() -> Self {
        let mut mesh = Self::icosphere(4);
        let ears = [
            Vec3::new(0.55, 0.8, 0.1).normalize(),
            Vec3::new(-0.55, 0.8, 0.1).normalize(),
        ];
        let face = Vec3::new(0.0, 0.1, 1.0).normalize();
        for p in &mut mesh.positions {
            let d = p.normalize();
            let ear: f32 = ears
                .iter()
                .map(|e| 0.55 * d.dot(*e).max(0.0).powi(12))
                .sum();
            let dent = -0.22 * d.dot(face).max(0.0).powi(6);
            let ridges = 0.07 * (5.0 * d.z.atan2(d.x)).sin() * (1.0 - d.y * d.y);
            let belly = 0.12 * (-d.y).max(0.0).powi(2);
            *p = d * (1.0 + ear + dent + ridges + belly);
        }
        mesh.normals = mesh.face_weighted_normals();
        mesh.uvs = mesh.spherical_uvs();
        mesh
    }

    /// A unit icosphere with `subdivisions` levels of 4-to-1 splitting, with
    /// [`Mesh::spherical_uvs`].
    pub fn icosphere(subdivisions: u32) -> Self {
        let t = (1.0 + 5f32.sqrt()) / 2.0;
        let mut positions: Vec<Vec3> = [
            (-1.0, t, 0.0),
            (1.0, t, 0.0),
            (-1.0, -t, 0.0),
            (1.0, -t, 0.0),
            (0.0, -1.0, t),
            (0.0, 1.0, t),
            (0.0, -1.0, -t),
            (0.0, 1.0, -t),
            (t, 0.0, -1.0),
            (t, 0.0, 1.0),
            (-t, 0.0, -1.0),
            (-t, 0.0, 1.0),
        ]
        .iter()
        .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
        .collect();
        let mut indices: Vec<u32> = vec![
            0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7,
            6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10,
            8, 6, 7, 9, 8, 1,
        ];
        for _ in 0..subdivisions {
            let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
            let mut next = Vec::with_capacity(indices.len() * 4);
            for tri in indices.chunks_exact(3) {
                let mut mid = |a: u32, b: u32| {
                    *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                        positions.push(
                            ((positions[a as usize] + positions[b as usize]) * 0.5).normalize(),
                        );
                        positions.len() as u32 - 1
                    })
                };
                let (a, b, c) = (tri[0], tri[1], tri[2]);
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                next.extend_from_slice(&[a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca]);
            }
            indices = next;
        }
        let normals = positions.clone();
        let mut mesh = Self {
            positions,
            normals,
            indices,
            uvs: Vec::new(),
            texture: None,
        };
        mesh.uvs = mesh.spherical_uvs();
        mesh
    }

    /// Latitude-longitude texture coordinates per triangle corner about the centre of
    /// the bounding box, poles on ±y: v = colatitude / π (0 at +y, 1 at −y) and
    /// u = longitude / 2π, growing counter-clockwise seen from +y (so the image is not
    /// mirrored seen from outside), 0.5 towards +z and the seam towards −z. A triangle
    /// across the seam gets 1 added to its small u's (u up to 1.5; textures repeat). A
    /// corner on the pole axis, or the corner nearest it in a triangle around the axis
    /// (whose u's span more than half a turn even after that), takes the mean u of the
    /// triangle's other corners.
    pub fn spherical_uvs(&self) -> Vec<Vec2> {
        let (centre, radius) = self.bounds();
        let on_axis = 1e-6 * radius;
        let mut uvs = Vec::with_capacity(self.indices.len());
        for t in self.indices.chunks_exact(3) {
            // Per corner: u (None on the pole axis), v and the distance from the axis.
            let mut corners = [t[0], t[1], t[2]].map(|i| {
                let d = self.positions[i as usize] - centre;
                let length = d.length();
                let v = if length > 0.0 {
                    (d.y / length).clamp(-1.0, 1.0).acos() / PI
                } else {
                    0.5
                };
                let across = Vec2::new(d.x, d.z).length();
                let u = (across > on_axis).then(|| (d.x.atan2(d.z) / TAU + 0.5).clamp(0.0, 1.0));
                (u, v, across)
            });
            if corners.iter().all(|c| c.0.is_some()) && seam_fixed(corners.map(|c| c.0)).1 > 0.5 {
                if let Some(nearest) = corners.iter_mut().min_by(|a, b| a.2.total_cmp(&b.2)) {
                    nearest.0 = None;
                }
            }
            let (fixed, _) = seam_fixed(corners.map(|c| c.0));
            let known: Vec<f32> = fixed.iter().flatten().copied().collect();
            let mean = if known.is_empty() {
                0.5
            } else {
                known.iter().sum::<f32>() / known.len() as f32
            };
            for (u, (_, v, _)) in fixed.iter().zip(corners) {
                uvs.push(Vec2::new(u.unwrap_or(mean), v));
            }
        }
        uvs
    }

    /// A UV sphere of `radius` around the origin with its poles on ±z: `rings` latitude
    /// bands and `segments` longitude bands. Each pole is one vertex; every inner ring
    /// has `segments + 1` vertices, the first and last coinciding on the seam (as in
    /// most exporters, and in the original fur demo's scene: `uv_sphere(2.0, 40, 80)`
    /// has 3,161 vertices and 6,240 triangles). Texture coordinates per corner:
    /// u = longitude / 2π (1 on the seam's second column), v = colatitude / π (0 at +z);
    /// a pole corner takes the u half-way between its triangle's other two.
    pub fn uv_sphere(radius: f32, rings: u32, segments: u32) -> Self {
        let rings = rings.max(2);
        let segments = segments.max(3);
        let mut positions = vec![Vec3::new(0.0, 0.0, radius)];
        for k in 1..rings {
            let theta = PI * k as f32 / rings as f32;
            for j in 0..=segments {
                // The seam's two columns are the same points, exactly.
                let phi = TAU * (j % segments) as f32 / segments as f32;
                let d = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                positions.push(d * radius);
            }
        }
        positions.push(Vec3::new(0.0, 0.0, -radius));
        let south = positions.len() as u32 - 1;
        let ring = |k: u32, j: u32| 1 + (k - 1) * (segments + 1) + j;
        let uv = |k: u32, j: u32| Vec2::new(j as f32 / segments as f32, k as f32 / rings as f32);
        let mut indices = Vec::new();
        let mut uvs = Vec::new();
        for j in 0..segments {
            let pole_u = (j as f32 + 0.5) / segments as f32;
            indices.extend_from_slice(&[0, ring(1, j), ring(1, j + 1)]);
            uvs.extend_from_slice(&[Vec2::new(pole_u, 0.0), uv(1, j), uv(1, j + 1)]);
            for k in 1..rings - 1 {
                let (a, b) = (ring(k, j), ring(k, j + 1));
                let (c, d) = (ring(k + 1, j), ring(k + 1, j + 1));
                indices.extend_from_slice(&[a, c, d, a, d, b]);
                let (a, b) = (uv(k, j), uv(k, j + 1));
                let (c, d) = (uv(k + 1, j), uv(k + 1, j + 1));
                uvs.extend_from_slice(&[a, c, d, a, d, b]);
            }
            indices.extend_from_slice(&[ring(rings - 1, j), south, ring(rings - 1, j + 1)]);
            uvs.extend_from_slice(&[
                uv(rings - 1, j),
                Vec2::new(pole_u, 1.0),
                uv(rings - 1, j + 1),
            ]);
        }
        let normals = positions.iter().map(|p| p.normalize()).collect();
        Self {
            positions,
            normals,
            indices,
            uvs,
            texture: None,
        }
    }

    /// A flat `nx` × `nz` grid of quads (two triangles each) in the XZ plane, centred on
    /// the origin, `size` wide, facing +Y. Texture coordinates: u along x, v along z,
    /// each 0 to 1 across the grid.
    pub fn grid(nx: u32, nz: u32, size: f32) -> Self {
        let mut positions = Vec::new();
        for j in 0..=nz {
            for i in 0..=nx {
                positions.push(Vec3::new(
                    size * (i as f32 / nx as f32 - 0.5),
                    0.0,
                    size * (j as f32 / nz as f32 - 0.5),
                ));
            }
        }
        let mut indices = Vec::new();
        let row = nx + 1;
        for j in 0..nz {
            for i in 0..nx {
                let a = j * row + i;
                let (b, c, d) = (a + 1, a + row, a + row + 1);
                indices.extend_from_slice(&[a, c, b, b, c, d]);
            }
        }
        let uvs = indices
            .iter()
            .map(|&k| Vec2::new((k % row) as f32 / nx as f32, (k / row) as f32 / nz as f32))
            .collect();
        let normals = vec![Vec3::Y; positions.len()];
        Self {
            positions,
            normals,
            indices,
            uvs,
            texture: None,
        }
    }
}

/// A triangle's corner u's (None: on the pole axis) with 1 added to the small ones
/// (below 0.5) when they span more than 0.5 (the triangle crosses the seam), and the
/// span of the result.
fn seam_fixed(us: [Option<f32>; 3]) -> ([Option<f32>; 3], f32) {
    let span = |us: &[Option<f32>; 3]| {
        let (lo, hi) = us
            .iter()
            .flatten()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &u| (lo.min(u), hi.max(u)));
        (hi - lo).max(0.0)
    };
    let fixed = if span(&us) > 0.5 {
        us.map(|u| u.map(|u| if u < 0.5 { u + 1.0 } else { u }))
    } else {
        us
    };
    let width = span(&fixed);
    (fixed, width)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest difference between the u's of one triangle's corners.
    fn widest_u_span(mesh: &Mesh) -> f32 {
        mesh.uvs
            .chunks_exact(3)
            .map(|t| {
                let u = t.iter().map(|uv| uv.x);
                u.clone().fold(f32::MIN, f32::max) - u.fold(f32::MAX, f32::min)
            })
            .fold(0.0, f32::max)
    }

    #[test]
    fn the_uv_sphere_has_seam_correct_lat_long_uvs() {
        let m = Mesh::uv_sphere(2.0, 40, 80);
        assert_eq!(m.uvs.len(), m.indices.len());
        assert!(widest_u_span(&m) <= 1.0 / 80.0 + 1e-6);
        for (&i, uv) in m.indices.iter().zip(&m.uvs) {
            let p = m.positions[i as usize] / 2.0;
            let colatitude = p.z.clamp(-1.0, 1.0).acos() / PI;
            assert!((uv.y - colatitude).abs() < 1e-4, "{p} {uv}");
            assert!((0.0..=1.0).contains(&uv.x));
            if p.z.abs() < 0.999 {
                let longitude = (p.y.atan2(p.x) / TAU).rem_euclid(1.0);
                let d = (uv.x - longitude).abs();
                assert!(d < 1e-4 || (d - 1.0).abs() < 1e-4, "{p} {uv}");
            }
        }
        // The seam's second column has u = 1.
        assert!(m.uvs.iter().any(|uv| uv.x == 1.0));
    }

    #[test]
    fn the_blob_and_icosphere_uvs_are_seam_fixed_per_triangle() {
        for m in [Mesh::blob(), Mesh::icosphere(3)] {
            assert_eq!(m.uvs.len(), m.indices.len());
            assert!(m.uvs.iter().all(|uv| uv.is_finite()));
            assert!(m.uvs.iter().all(|uv| (0.0..=1.5).contains(&uv.x)));
            assert!(m.uvs.iter().all(|uv| (0.0..=1.0).contains(&uv.y)));
            assert!(widest_u_span(&m) < 0.5, "{}", widest_u_span(&m));
        }
        // The icosphere has vertices on the poles; their u is the other corners' mean.
        let m = Mesh::icosphere(2);
        let mut poles = 0;
        for (t, uv) in m.indices.chunks_exact(3).zip(m.uvs.chunks_exact(3)) {
            for k in 0..3 {
                let p = m.positions[t[k] as usize];
                if p.x.abs() < 1e-6 && p.z.abs() < 1e-6 {
                    poles += 1;
                    let mean = 0.5 * (uv[(k + 1) % 3].x + uv[(k + 2) % 3].x);
                    assert!((uv[k].x - mean).abs() < 1e-6);
                    assert!(uv[k].y < 1e-6 || uv[k].y > 1.0 - 1e-6);
                }
            }
        }
        assert_eq!(poles, 12, "six triangles around each pole");
    }

    #[test]
    fn the_grid_maps_its_whole_area() {
        let m = Mesh::grid(4, 2, 2.0);
        assert_eq!(m.uvs.len(), m.indices.len());
        for (&i, uv) in m.indices.iter().zip(&m.uvs) {
            let p = m.positions[i as usize];
            assert!((uv.x - (p.x / 2.0 + 0.5)).abs() < 1e-6);
            assert!((uv.y - (p.z / 2.0 + 0.5)).abs() < 1e-6);
        }
    }
}
