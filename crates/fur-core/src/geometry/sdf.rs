//! Signed distance fields of triangle meshes on a regular grid of cubic cells: the
//! body's field that hair collides with (built for the simulation by
//! `crate::sim::sdf`, in model space: the body moves rigidly, so strands sample it at
//! H⁻¹·x) and the one the scene measures a model's thickness with. Distances are
//! positive outside, negative inside.
//!
//! Every grid point stores its distance and the field's gradient there (central
//! differences, at build). A point is sampled from its nearest grid point to first
//! order, `d(p) ≈ d(c) + ∇d(c)·(p − c)`: one 16-byte load per strand vertex on the GPU,
//! where trilinear interpolation needs eight, with errors of the same second order in
//! the cell size. CPU (here) and GPU (`shaders/simulate.comp`) use the same arithmetic
//! on the same values, read from a storage buffer with plain loads (a filtered 3D
//! texture would round its weights to a few bits on common GPUs and break parity with
//! the CPU reference). On the default scene trilinear sampling made collision a large
//! share of the simulation step (its eight reads per sample).
//!
//! The nearest-point expansion jumps where the nearest grid point changes, by up to a
//! cell's worth of distance in a crease (two surfaces' gradients meet there), and hair
//! resting in one can be thrown across that jump and back every frame. Skinned bodies,
//! whose creases open and close, sample trilinearly ([`Sdf::sample_trilinear`]):
//! continuous, at eight loads.

use std::collections::HashMap;

use glam::Vec3;
use mesh_to_sdf::{generate_grid_sdf, Grid, SignMethod, Topology};

use super::math::{Real, V3};
use super::Triangles;
use crate::error::{Error, Result};

/// Cells along the longest axis a distance field may have, at least and at most.
pub const RESOLUTION_RANGE: (u32, u32) = (8, 128);

/// A signed distance field on a regular grid of cubic cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Sdf {
    /// Grid points along x, y, z.
    pub dims: [u32; 3],
    /// Model-space position of grid point (0, 0, 0).
    pub origin: Vec3,
    /// Distance between neighbouring grid points.
    pub cell: f32,
    /// One value per grid point, x fastest, then y, then z.
    pub values: Vec<f32>,
    /// The field's gradient at each grid point (central differences).
    pub gradients: Vec<Vec3>,
}

/// What building the field found out about the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SdfReport {
    /// Edges used by one triangle only (holes), after welding coincident vertices.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles, or twice in the same direction.
    pub inconsistent_edges: usize,
    /// Milliseconds the field took to build.
    pub build_ms: f64,
}

impl SdfReport {
    pub fn closed(&self) -> bool {
        self.boundary_edges == 0 && self.inconsistent_edges == 0
    }

    /// What the user must know about model `name`'s field, if anything.
    pub fn warning(&self, name: &str) -> Option<String> {
        (!self.closed()).then(|| {
            format!(
                "model {name} is not a closed, consistently oriented surface ({} open edges, {} \
                 inconsistent ones): inside and outside of its distance field are estimated from \
                 the nearest triangles' normals and may be wrong near the holes, so collisions \
                 there are approximate",
                self.boundary_edges, self.inconsistent_edges
            )
        })
    }
}

/// Counts boundary and inconsistently oriented edges of `mesh` with coincident
/// vertices (within a millionth of its size) welded: a UV sphere's seam is closed.
fn topology(mesh: Triangles) -> (usize, usize) {
    let (_, radius) = mesh.bounds();
    let (weld, _) = super::topology::weld(mesh.positions, radius * 1e-6);
    // Per undirected edge: (uses a→b with a < b, uses b→a).
    let mut edges: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    for t in mesh.indices.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (weld[t[k] as usize], weld[t[(k + 1) % 3] as usize]);
            if a == b {
                continue;
            }
            let entry = edges.entry((a.min(b), a.max(b))).or_default();
            if a < b {
                entry.0 += 1;
            } else {
                entry.1 += 1;
            }
        }
    }
    let boundary = edges.values().filter(|(f, b)| f + b == 1).count();
    let inconsistent = edges
        .values()
        .filter(|&&(f, b)| f + b > 2 || (f + b == 2 && f != 1))
        .count();
    (boundary, inconsistent)
}

impl Sdf {
    /// The field of `mesh` (a scene's `&Mesh` will do) over its bounding box padded by
    /// `padding`, with `resolution` grid cells along the longest axis.
    pub fn build<'a>(
        mesh: impl Into<Triangles<'a>>,
        resolution: u32,
        padding: f32,
    ) -> Result<(Self, SdfReport)> {
        let mesh = mesh.into();
        let start = std::time::Instant::now();
        let (lo, hi) = RESOLUTION_RANGE;
        if !(lo..=hi).contains(&resolution) {
            return Err(Error::Parameter(format!(
                "the distance field's resolution must be {lo}..={hi} cells along the longest axis, got {resolution}"
            )));
        }
        if !(padding.is_finite() && padding >= 0.0) {
            return Err(Error::Parameter(format!(
                "the distance field's padding must be finite and ≥ 0, got {padding}"
            )));
        }
        let (min, max) = mesh.aabb();
        let (min, max) = (min - Vec3::splat(padding), max + Vec3::splat(padding));
        let cell = (max - min).max_element() / resolution as f32;
        if !(cell.is_finite() && cell > 0.0) {
            return Err(Error::Parameter(
                "the model has no extent to build a distance field over".into(),
            ));
        }
        // Grid points at cell centres of the padded box, one more cell each way so the
        // box's edges are inside the grid.
        let dims = ((max - min) / cell)
            .ceil()
            .as_uvec3()
            .to_array()
            .map(|n| n.max(1) + 2);
        // The sign comes from rays cast from the grid points along the axes. Offsetting
        // the grid by unrelated fractions of a cell keeps those rays off the edges of
        // axis-aligned faces (a box's face diagonals), where a crossing would be
        // counted twice or not at all and flip whole columns of the field.
        let origin =
            min - Vec3::new(0.5 + 0.123_456_7, 0.5 + 0.314_159_3, 0.5 + 0.271_828_2) * cell;
        let (boundary_edges, inconsistent_edges) = topology(mesh);
        let mut report = SdfReport {
            boundary_edges,
            inconsistent_edges,
            build_ms: 0.0,
        };
        // Ray casting gives the right sign for any closed mesh whatever its winding; for
        // an open or inconsistent one it can flip whole regions, so the sign then comes
        // from the nearest triangles' normals, which errs only near the holes.
        let sign = if report.closed() {
            SignMethod::Raycast
        } else {
            SignMethod::Normal
        };
        let vertices: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
        // The crate's grid holds cell centres from `first_cell`, index z fastest.
        let grid = Grid::new(origin.to_array(), [cell; 3], dims.map(|n| n as usize));
        // The crate spreads its propagation over rayon's threads, and which thread
        // reaches a cell first decides the distance stored there: on one thread the
        // same mesh gives the same field on every run (and so the same hair lengths
        // under the thickness limit, the same collisions, the same images).
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| Error::Parameter(format!("starting the distance field's thread: {e}")))?;
        let values = pool.install(|| {
            generate_grid_sdf(
                &vertices,
                Topology::TriangleList(Some(mesh.indices)),
                &grid,
                sign,
            )
        });
        let [nx, ny, nz] = dims.map(|n| n as usize);
        let mut ordered = vec![0.0f32; nx * ny * nz];
        for x in 0..nx {
            for y in 0..ny {
                for z in 0..nz {
                    ordered[x + nx * (y + ny * z)] = values[grid.get_cell_idx(&[x, y, z])];
                }
            }
        }
        if let Some(bad) = ordered.iter().find(|v| !v.is_finite()) {
            return Err(Error::Parameter(format!(
                "the model's distance field has a non-finite value ({bad})"
            )));
        }
        report.build_ms = start.elapsed().as_secs_f64() * 1e3;
        let mut sdf = Self {
            dims,
            origin,
            cell,
            values: ordered,
            gradients: Vec::new(),
        };
        sdf.gradients = sdf.central_differences();
        Ok((sdf, report))
    }

    /// Bytes the field takes on the device.
    pub fn bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<[f32; 4]>()
    }

    fn index(&self, x: u32, y: u32, z: u32) -> usize {
        let [nx, ny, _] = self.dims;
        (x + nx * (y + ny * z)) as usize
    }

    /// The gradient at every grid point: central differences inside, one-sided at the
    /// grid's faces.
    fn central_differences(&self) -> Vec<Vec3> {
        let [nx, ny, nz] = self.dims;
        let mut out = Vec::with_capacity(self.values.len());
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let c = [x, y, z];
                    let mut g = [0.0f32; 3];
                    for (k, gk) in g.iter_mut().enumerate() {
                        let (mut lo, mut hi) = (c, c);
                        lo[k] = c[k].saturating_sub(1);
                        hi[k] = (c[k] + 1).min(self.dims[k] - 1);
                        let span = (hi[k] - lo[k]) as f32 * self.cell;
                        let (a, b) = (
                            self.values[self.index(lo[0], lo[1], lo[2])],
                            self.values[self.index(hi[0], hi[1], hi[2])],
                        );
                        *gk = if span > 0.0 { (b - a) / span } else { 0.0 };
                    }
                    out.push(Vec3::from_array(g));
                }
            }
        }
        out
    }

    /// What the GPU reads: per grid point the value and the gradient.
    pub fn texels(&self) -> Vec<[f32; 4]> {
        self.values
            .iter()
            .zip(&self.gradients)
            .map(|(v, g)| [*v, g.x, g.y, g.z])
            .collect()
    }

    /// `p`'s coordinates in grid cells from grid point (0, 0, 0), or None outside the
    /// grid.
    fn grid_coordinates<T: Real>(&self, p: V3<T>) -> Option<[T; 3]> {
        let inv = T::from_f32(1.0 / self.cell);
        let o = V3::<T>::from_vec3(self.origin);
        let g = [(p.0 - o.0) * inv, (p.1 - o.1) * inv, (p.2 - o.2) * inv];
        let inside = g
            .iter()
            .zip(self.dims)
            .all(|(&x, n)| x >= T::ZERO && x <= T::from_f32((n - 1) as f32));
        inside.then_some(g)
    }

    /// Grid point `at`'s first-order expansion `offset` away from it, and its gradient.
    fn expansion<T: Real>(&self, at: usize, offset: [T; 3]) -> (T, V3<T>) {
        let grad = V3::<T>::from_vec3(self.gradients[at]);
        let value = T::from_f32(self.values[at])
            + (grad.0 * offset[0] + grad.1 * offset[1] + grad.2 * offset[2]);
        (value, grad)
    }

    /// The distance at model-space point `p` to first order from its nearest grid
    /// point, and the gradient there (not normalised); None outside the grid. The
    /// arithmetic, step by step, is the shader's `sdf_sample`.
    pub fn sample<T: Real>(&self, p: V3<T>) -> Option<(T, V3<T>)> {
        let g = self.grid_coordinates(p)?;
        let cell = T::from_f32(self.cell);
        let nearest = g.map(|x| (x + T::HALF).to_f64().floor() as u32);
        let offset = [0, 1, 2].map(|k| (g[k] - T::from_f32(nearest[k] as f32)) * cell);
        Some(self.expansion(self.index(nearest[0], nearest[1], nearest[2]), offset))
    }

    /// The distance and gradient at model-space point `p`: the trilinear blend of the
    /// eight grid points around it, each point's first-order expansion at `p` (as
    /// [`Sdf::sample`] takes from the nearest), and of their gradients. Continuous across
    /// cells, unlike [`Sdf::sample`]; and like it, never above the distance where the
    /// field is convex (outside a convex part of the body: each expansion is a tangent
    /// plane), where blending the values alone would overestimate it and let hair in.
    /// None outside the grid. The arithmetic, step by step, is the shader's
    /// `sdf_sample_trilinear`.
    pub fn sample_trilinear<T: Real>(&self, p: V3<T>) -> Option<(T, V3<T>)> {
        let g = self.grid_coordinates(p)?;
        // The cell's lower corner; the far face of the grid belongs to the last cell.
        let base = [0, 1, 2].map(|k| (g[k].to_f64().floor() as u32).min(self.dims[k] - 2));
        let f = [0, 1, 2].map(|k| g[k] - T::from_f32(base[k] as f32));
        let cell = T::from_f32(self.cell);
        let mut value = T::ZERO;
        let mut gradient = V3::<T>(T::ZERO, T::ZERO, T::ZERO);
        for corner in 0..8u32 {
            let step = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
            let weight = |k: usize| if step[k] == 1 { f[k] } else { T::ONE - f[k] };
            let w = weight(0) * weight(1) * weight(2);
            let at = self.index(base[0] + step[0], base[1] + step[1], base[2] + step[2]);
            // This grid point's first-order expansion at p.
            let offset = [0, 1, 2].map(|k| (f[k] - T::from_f32(step[k] as f32)) * cell);
            let (expansion, grad) = self.expansion(at, offset);
            value = value + w * expansion;
            gradient = gradient + grad.scale(w);
        }
        Some((value, gradient))
    }
}

/// Exact signed distances from `points` to a closed `mesh` (ray-cast sign), point by
/// point: the measure collision is judged by.
pub fn exact_distances<'a>(mesh: impl Into<Triangles<'a>>, points: &[Vec3]) -> Vec<f32> {
    let mesh = mesh.into();
    let vertices: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let queries: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    mesh_to_sdf::generate_sdf(
        &vertices,
        Topology::TriangleList(Some(mesh.indices)),
        &queries,
        mesh_to_sdf::AccelerationMethod::Bvh(SignMethod::Raycast),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_resolution_and_padding_are_errors() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let indices = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
        let mesh = Triangles {
            positions: &positions,
            indices: &indices,
        };
        assert!(Sdf::build(mesh, 16, 0.1).is_ok());
        assert!(Sdf::build(mesh, 4, 0.1).is_err());
        assert!(Sdf::build(mesh, 1000, 0.1).is_err());
        assert!(Sdf::build(mesh, 16, f32::NAN).is_err());
    }

    #[test]
    fn sampling_reproduces_a_linear_field_and_its_gradient() {
        // A plane's distance is linear: first-order sampling is exact.
        let mut sdf = Sdf {
            dims: [4, 5, 6],
            origin: Vec3::new(-1.0, 0.5, 2.0),
            cell: 0.25,
            values: Vec::new(),
            gradients: Vec::new(),
        };
        let normal = Vec3::new(1.0, 2.0, -2.0) / 3.0;
        for z in 0..6 {
            for y in 0..5 {
                for x in 0..4 {
                    let p = sdf.origin + Vec3::new(x as f32, y as f32, z as f32) * sdf.cell;
                    sdf.values.push(p.dot(normal) - 0.3);
                }
            }
        }
        sdf.gradients = sdf.central_differences();
        let p = V3::<f64>(-0.6, 1.1, 2.7);
        let (d, g) = sdf.sample(p).unwrap();
        let exact =
            p.0 * f64::from(normal.x) + p.1 * f64::from(normal.y) + p.2 * f64::from(normal.z) - 0.3;
        assert!((d - exact).abs() < 1e-6, "{d} vs {exact}");
        assert!((g.0 - f64::from(normal.x)).abs() < 1e-5);
        assert!((g.1 - f64::from(normal.y)).abs() < 1e-5);
        assert!((g.2 - f64::from(normal.z)).abs() < 1e-5);
        assert!(sdf.sample(V3::<f64>(-1.1, 1.0, 2.5)).is_none());
        let (d, g) = sdf.sample_trilinear(p).unwrap();
        assert!((d - exact).abs() < 1e-6, "{d} vs {exact}");
        assert!((g.0 - f64::from(normal.x)).abs() < 1e-5);
        assert!(sdf.sample_trilinear(V3::<f64>(-1.1, 1.0, 2.5)).is_none());
        // The grid's far corner is inside it.
        let far = sdf.origin + Vec3::new(3.0, 4.0, 5.0) * sdf.cell;
        assert!(sdf.sample_trilinear(V3::<f64>::from_vec3(far)).is_some());
    }

    /// Across the faces where the nearest grid point changes, the first-order sample
    /// jumps in a crease (two planes meeting at a ridge) and the trilinear one does not.
    #[test]
    fn trilinear_sampling_is_continuous_where_the_nearest_point_jumps() {
        let mut sdf = Sdf {
            dims: [8, 8, 3],
            origin: Vec3::ZERO,
            cell: 1.0,
            values: Vec::new(),
            gradients: Vec::new(),
        };
        // The distance to the union of two half-spaces meeting at the plane x = y: a
        // crease along z, its ridge on the grid's diagonal.
        for _z in 0..3 {
            for y in 0..8 {
                for x in 0..8 {
                    sdf.values.push((x as f32).min(y as f32) - 1.0);
                }
            }
        }
        sdf.gradients = sdf.central_differences();
        // Walk along x at y = 3.3 through the ridge in tiny steps: the largest change of
        // the value between neighbouring samples.
        let largest_step = |sample: &dyn Fn(V3<f64>) -> f64| {
            let mut worst = 0.0f64;
            let mut last = sample(V3(1.0, 3.3, 1.0));
            for k in 1..=5000 {
                let v = sample(V3(1.0 + 5.0 * f64::from(k) / 5000.0, 3.3, 1.0));
                worst = worst.max((v - last).abs());
                last = v;
            }
            worst
        };
        let nearest = largest_step(&|p| sdf.sample(p).unwrap().0);
        let trilinear = largest_step(&|p| sdf.sample_trilinear(p).unwrap().0);
        // A step of 1e-3 moves a continuous sample with slope ≤ 1 by ≤ 1e-3.
        assert!(nearest > 0.1, "nearest-point sampling jumps by {nearest}");
        assert!(trilinear < 2e-3, "trilinear sampling jumps by {trilinear}");
    }
}
