//! Geodesic distance on a triangle mesh by the heat method (Crane, Weischedel and
//! Wardetzky 2013): heat let flow from the sources for a short time, its gradient
//! normalised, and the distance whose gradient is closest to that field (a Poisson
//! problem). Both solves use the mesh's cotangent Laplacian and lumped mass matrix,
//! factored once by `faer`'s sparse Cholesky (with its fill-reducing ordering).

use std::collections::HashMap;

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use glam::DVec3;

use crate::error::{Error, Result};
use crate::geometry::topology::{pieces, weld};

/// A closed or open triangle mesh as the operators see it: vertices at one position
/// (within a millionth of its size, as the distance field joins them) are one, so a
/// model split at its texture seams is still one surface; triangles that collapse once
/// they are joined are dropped.
pub(super) struct Surface {
    /// Per vertex of the mesh, its joined vertex.
    pub joined: Vec<u32>,
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Per joined vertex, a third of its triangles' area.
    pub mass: Vec<f64>,
    /// Per edge (i < j), in order, the cotangent weight ½ (cot α + cot β), never
    /// below zero.
    weights: Vec<(u32, u32, f64)>,
    /// Per joined vertex, its connected piece.
    pub piece: Vec<u32>,
    pub pieces: usize,
    /// The mean edge length.
    pub spacing: f64,
}

impl Surface {
    pub fn new(positions: &[glam::Vec3], indices: &[u32]) -> Result<Self> {
        let (_, radius) = crate::geometry::Triangles { positions, indices }.bounds();
        let (joined, count) = weld(positions, radius * 1e-6);
        let mut unique = vec![DVec3::ZERO; count];
        for (p, &j) in positions.iter().zip(&joined).rev() {
            unique[j as usize] = p.as_dvec3();
        }
        let mut triangles = Vec::with_capacity(indices.len() / 3);
        for t in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| joined[t[k] as usize]);
            if a != b && b != c && c != a {
                triangles.push([a, b, c]);
            }
        }
        if triangles.is_empty() {
            return Err(Error::Parameter(
                "the model has no triangle of three distinct corners to lay a flow on".into(),
            ));
        }
        let n = unique.len();
        let mut mass = vec![0.0; n];
        let mut weights: HashMap<(u32, u32), f64> = HashMap::new();
        let mut edge_sum = 0.0;
        for t in &triangles {
            let p = t.map(|i| unique[i as usize]);
            let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            for k in 0..3 {
                mass[t[k] as usize] += area / 3.0;
                // The corner k faces the edge (k+1, k+2).
                let (i, j) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                let weight = 0.5 * cotangent(p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                *weights.entry((i.min(j), i.max(j))).or_insert(0.0) += weight;
                edge_sum += p[(k + 1) % 3].distance(p[(k + 2) % 3]);
            }
        }
        // An obtuse pair of angles gives a negative weight; counted as zero, the heat
        // stays positive everywhere (the matrix is an M-matrix), so even its smallest
        // values far from the sources are exact to their last digits.
        let mut weights: Vec<(u32, u32, f64)> = weights
            .into_iter()
            .map(|((i, j), w)| (i, j, w.max(0.0)))
            .collect();
        weights.sort_unstable_by_key(|&(i, j, _)| (i, j));
        // A vertex of no triangle still needs a (tiny) mass for the matrices to be
        // definite; it is a piece of its own, which the heat reaches only if it starts
        // there.
        let spacing = edge_sum / (3 * triangles.len()) as f64;
        for m in &mut mass {
            *m = m.max(1e-9 * spacing * spacing);
        }
        let (piece, pieces) = pieces(n, weights.iter().map(|&(i, j, _)| (i, j)));
        Ok(Self {
            joined,
            positions: unique,
            spacing,
            triangles,
            mass,
            weights,
            piece,
            pieces,
        })
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// The factored matrix `diagonal · M + scale · L` (L the positive semi-definite
    /// cotangent Laplacian), sharing `symbolic`'s ordering.
    fn factor(
        &self,
        symbolic: &SymbolicLlt<usize>,
        diagonal: f64,
        scale: f64,
    ) -> Result<Llt<usize, f64>> {
        let matrix = self.matrix(diagonal, scale)?;
        Llt::try_new_with_symbolic(symbolic.clone(), matrix.as_ref(), Side::Lower)
            .map_err(|e| Error::Parameter(format!("the flow's solve failed: {e:?}")))
    }

    fn matrix(&self, diagonal: f64, scale: f64) -> Result<SparseColMat<usize, f64>> {
        let mut entries: Vec<Triplet<usize, usize, f64>> = self
            .mass
            .iter()
            .enumerate()
            .map(|(i, m)| Triplet::new(i, i, diagonal * m))
            .collect();
        let mut row_sums = vec![0.0; self.len()];
        for &(i, j, w) in &self.weights {
            entries.push(Triplet::new(j as usize, i as usize, -scale * w));
            row_sums[i as usize] += scale * w;
            row_sums[j as usize] += scale * w;
        }
        for (i, s) in row_sums.into_iter().enumerate() {
            entries.push(Triplet::new(i, i, s));
        }
        let n = self.len();
        SparseColMat::try_new_from_triplets(n, n, &entries)
            .map_err(|e| Error::Parameter(format!("the flow's matrix: {e:?}")))
    }

    /// Geodesic distance from the heat `sources` (per joined vertex, how much heat it
    /// starts with: a peak makes a whorl the flow parts from), each piece of the
    /// surface measured from its own sources and zero at its nearest point (a piece
    /// without any gets 0 everywhere). `time` is the heat's diffusion time, in squared
    /// scene units.
    pub fn distance(&self, sources: &[f64], time: f64) -> Result<Vec<f64>> {
        let pattern = self.matrix(1.0, 1.0)?;
        let symbolic = SymbolicLlt::try_new(pattern.symbolic(), Side::Lower)
            .map_err(|e| Error::Parameter(format!("the flow's ordering failed: {e:?}")))?;
        // 1. Heat from the sources: (M + t L) u = M u₀.
        let mut heat = Mat::<f64>::zeros(self.len(), 1);
        for (i, s) in sources.iter().enumerate() {
            heat[(i, 0)] = s * self.mass[i];
        }
        self.factor(&symbolic, 1.0, time)?
            .solve_in_place(heat.as_mut());
        // 2. The unit field pointing away from the sources, per triangle, and its
        // integrated divergence per vertex.
        let mut divergence = vec![0.0; self.len()];
        for t in &self.triangles {
            let p = t.map(|i| self.positions[i as usize]);
            let u = t.map(|i| heat[(i as usize, 0)]);
            let field = -gradient(p, u).normalize_or_zero();
            for k in 0..3 {
                let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                let (e1, e2) = (p[a] - p[k], p[b] - p[k]);
                // ½ Σ cot θ₁ (e₁ · X) + cot θ₂ (e₂ · X), θ the angles facing e₁ and e₂.
                let cot_b = cotangent(p[k] - p[b], p[a] - p[b]);
                let cot_a = cotangent(p[k] - p[a], p[b] - p[a]);
                divergence[t[k] as usize] += 0.5 * (cot_b * e1.dot(field) + cot_a * e2.dot(field));
            }
        }
        // 3. The distance whose gradient is nearest the field: L φ = −div X. L's
        // constants are its kernel; a small multiple of M makes it definite, and the
        // right-hand side, made orthogonal to the constants piece by piece, keeps the
        // solution from drifting.
        let mut sums = vec![(0.0, 0.0); self.pieces];
        for (i, d) in divergence.iter().enumerate() {
            let s = &mut sums[self.piece[i] as usize];
            s.0 += d;
            s.1 += self.mass[i];
        }
        let mut phi = Mat::<f64>::zeros(self.len(), 1);
        for (i, d) in divergence.iter().enumerate() {
            let (sum, mass) = sums[self.piece[i] as usize];
            phi[(i, 0)] = -(d - self.mass[i] * sum / mass);
        }
        let tiny = 1e-9 / (self.spacing * self.spacing);
        self.factor(&symbolic, tiny, 1.0)?
            .solve_in_place(phi.as_mut());
        // 4. Each piece's distance is zero at its nearest point to the sources; a piece
        // the heat never reached has none.
        let mut origin = vec![f64::INFINITY; self.pieces];
        let mut heated = vec![false; self.pieces];
        for i in 0..self.len() {
            let p = self.piece[i] as usize;
            origin[p] = origin[p].min(phi[(i, 0)]);
            heated[p] |= sources[i] > 0.0;
        }
        Ok((0..self.len())
            .map(|i| {
                let p = self.piece[i] as usize;
                if heated[p] && origin[p].is_finite() {
                    phi[(i, 0)] - origin[p]
                } else {
                    0.0
                }
            })
            .collect())
    }
}

/// The gradient of the linear function taking values `u` at the triangle's corners `p`.
pub(super) fn gradient(p: [DVec3; 3], u: [f64; 3]) -> DVec3 {
    let normal = (p[1] - p[0]).cross(p[2] - p[0]);
    let double_area = normal.length();
    if double_area <= 0.0 {
        return DVec3::ZERO;
    }
    let n = normal / double_area;
    (0..3)
        .map(|k| u[k] * n.cross(p[(k + 2) % 3] - p[(k + 1) % 3]))
        .sum::<DVec3>()
        / double_area
}

/// cot of the angle between `a` and `b`; 0 for a degenerate corner.
fn cotangent(a: DVec3, b: DVec3) -> f64 {
    let sine = a.cross(b).length();
    if sine > 0.0 {
        a.dot(b) / sine
    } else {
        0.0
    }
}
