//! Generated models: the default blob, icospheres, UV spheres and flat grids.

use std::collections::HashMap;

use glam::Vec3;

use super::Mesh;

impl Mesh {
    /// The default model: a lumpy blob with two ears, a dented face and ridged flanks,
    /// so the fur shows over convex and concave regions alike.
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
        mesh
    }

    /// A unit icosphere with `subdivisions` levels of 4-to-1 splitting.
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
        Self {
            positions,
            normals,
            indices,
        }
    }

    /// A UV sphere of `radius` around the origin with its poles on ±z: `rings` latitude
    /// bands and `segments` longitude bands. Each pole is one vertex; every inner ring
    /// has `segments + 1` vertices, the first and last coinciding on the seam (as in
    /// most exporters, and in the original fur demo's scene: `uv_sphere(2.0, 40, 80)`
    /// has 3,161 vertices and 6,240 triangles).
    pub fn uv_sphere(radius: f32, rings: u32, segments: u32) -> Self {
        let rings = rings.max(2);
        let segments = segments.max(3);
        let mut positions = vec![Vec3::new(0.0, 0.0, radius)];
        for k in 1..rings {
            let theta = std::f32::consts::PI * k as f32 / rings as f32;
            for j in 0..=segments {
                // The seam's two columns are the same points, exactly.
                let phi = std::f32::consts::TAU * (j % segments) as f32 / segments as f32;
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
        let mut indices = Vec::new();
        for j in 0..segments {
            indices.extend_from_slice(&[0, ring(1, j), ring(1, j + 1)]);
            for k in 1..rings - 1 {
                let (a, b) = (ring(k, j), ring(k, j + 1));
                let (c, d) = (ring(k + 1, j), ring(k + 1, j + 1));
                indices.extend_from_slice(&[a, c, d, a, d, b]);
            }
            indices.extend_from_slice(&[ring(rings - 1, j), south, ring(rings - 1, j + 1)]);
        }
        let normals = positions.iter().map(|p| p.normalize()).collect();
        Self {
            positions,
            normals,
            indices,
        }
    }

    /// A flat `nx` × `nz` grid of quads (two triangles each) in the XZ plane, centred on
    /// the origin, `size` wide, facing +Y.
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
        let normals = vec![Vec3::Y; positions.len()];
        Self {
            positions,
            normals,
            indices,
        }
    }
}
