//! The rest pose in the form the local shape constraint needs: every segment expressed
//! in its parent's local frame, plus one root frame per strand (Han & Harada §4.2).
//!
//! Frames are carried root to tip. Frame 0 is the root frame `F₀`, rigidly attached
//! to the mesh, with its x axis along the first rest segment. Walking segment `i`
//! (from vertex `i` to `i + 1`): its rest vector in frame `i` is `vᵢ = Fᵢᵀ (xᵢ₊₁ − xᵢ)`,
//! and the next frame turns the x axis onto that segment, `Fᵢ₊₁ = Fᵢ · R(x → v̂ᵢ)`.

use super::math::{min_length, Head, Real, M3, V3};
use crate::scene::Strands;

/// Rest data for all strands, in model space.
#[derive(Clone, Debug)]
pub struct RestPose<T: Real> {
    pub vertices_per_strand: usize,
    pub positions: Vec<V3<T>>,
    /// Per vertex `i`: the rest vector of segment `i` in frame `i` (zero at the tip).
    pub local: Vec<V3<T>>,
    /// Per vertex `i`: rest length of the segment from `i - 1` to `i` (zero at the root).
    pub lengths: Vec<T>,
    /// Per strand: the root frame `F₀` in model space.
    pub root_frames: Vec<M3<T>>,
}

impl<T: Real> RestPose<T> {
    pub fn new(strands: &Strands) -> Self {
        let v = strands.vertices_per_strand as usize;
        let positions: Vec<V3<T>> = strands
            .positions
            .iter()
            .map(|p| V3::from_vec3(*p))
            .collect();
        let mut local = vec![V3::ZERO; positions.len()];
        let mut lengths = vec![T::ZERO; positions.len()];
        let mut root_frames = Vec::with_capacity(strands.count());
        for s in 0..strands.count() {
            let x = &positions[s * v..(s + 1) * v];
            let first = x[1] - x[0];
            let len = first.length();
            let root = if len > min_length::<T>() {
                M3::rotation_from_x(first.scale(T::ONE / len))
            } else {
                M3::rotation_from_x(V3(T::ONE, T::ZERO, T::ZERO))
            };
            root_frames.push(root);
            let mut frame = root;
            for i in 0..v - 1 {
                let segment = x[i + 1] - x[i];
                let vi = frame.transpose_mul_vec(segment);
                local[s * v + i] = vi;
                lengths[s * v + i + 1] = segment.length();
                frame = advance_frame(&frame, vi);
            }
        }
        Self {
            vertices_per_strand: v,
            positions,
            local,
            lengths,
            root_frames,
        }
    }

    pub fn count(&self) -> usize {
        self.root_frames.len()
    }

    /// One root-to-tip pass of the local shape constraint over strand `s` (positions `x`
    /// in world space, `head` the current head transform).
    pub(crate) fn local_walk(&self, s: usize, head: &Head<T>, stiffness: T, x: &mut [V3<T>]) {
        let v = self.vertices_per_strand;
        let mut frame = head.rotation.mul_mat(&self.root_frames[s]);
        for i in 0..v - 1 {
            // F (vᵢ − Fᵀ(xᵢ₊₁ − xᵢ)) is `x_i + F vᵢ − xᵢ₊₁` for an orthonormal F, and is
            // exactly zero at rest: the rest pose is a fixed point, not a rounding drift.
            let current = frame.transpose_mul_vec(x[i + 1] - x[i]);
            let delta = frame
                .mul_vec(self.local[s * v + i] - current)
                .scale(stiffness);
            if i == 0 {
                x[i + 1] = x[i + 1] + delta;
            } else {
                x[i] = x[i] - delta.scale(T::HALF);
                x[i + 1] = x[i + 1] + delta.scale(T::HALF);
            }
            frame = advance_frame(&frame, frame.transpose_mul_vec(x[i + 1] - x[i]));
        }
    }
}

/// The frame of the next segment: `F · R(x → v̂)` for `v` in `F`'s coordinates.
/// A zero-length segment keeps the frame.
pub(crate) fn advance_frame<T: Real>(frame: &M3<T>, v: V3<T>) -> M3<T> {
    let len = v.length();
    if len > min_length::<T>() {
        frame.mul_mat(&M3::rotation_from_x(v.scale(T::ONE / len)))
    } else {
        *frame
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{GroomParams, Mesh};

    #[test]
    fn rest_walk_reproduces_the_rest_pose() {
        let mesh = Mesh::icosphere(1);
        let groom = GroomParams {
            curl: 0.8,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        let rest = RestPose::<f64>::new(&strands);
        let head = Head::new(glam::Mat4::IDENTITY);
        for s in 0..rest.count() {
            let v = rest.vertices_per_strand;
            let mut x = rest.positions[s * v..(s + 1) * v].to_vec();
            let before = x.clone();
            rest.local_walk(s, &head, 1.0, &mut x);
            for (a, b) in x.iter().zip(&before) {
                assert!((*a - *b).length() < 1e-12, "strand {s} moved at rest");
            }
        }
    }

    #[test]
    fn rotation_from_x_maps_x_onto_u_and_is_orthonormal() {
        for u in [
            V3(0.0, 1.0, 0.0),
            V3(0.6, 0.0, 0.8),
            V3(-0.9998, 0.02, 0.0),
            V3(-1.0, 0.0, 0.0),
            V3(1.0, 0.0, 0.0),
        ] {
            let u = u.scale(1.0 / u.length());
            let r = M3::<f64>::rotation_from_x(u);
            let x = r.mul_vec(V3(1.0, 0.0, 0.0));
            assert!((x - u).length() < 1e-3, "{u:?} -> {x:?}");
            for i in 0..3 {
                for j in 0..3 {
                    let d = r.0[i].dot(r.0[j]);
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((d - want).abs() < 1e-9, "not orthonormal for {u:?}");
                }
            }
        }
    }
}
