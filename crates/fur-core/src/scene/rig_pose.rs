//! Playing a rig: sampling its clips (glTF 2.0's STEP, LINEAR and CUBICSPLINE), the
//! node hierarchy's world transforms, the joints' skinning matrices, and linear blend
//! skinning on the CPU (the reference a GPU skinning pass is checked against).

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use super::{Channel, Clip, Interpolation, Property, Rig, Transform};

impl Clip {
    /// The last key time over all channels, 0 when there is none.
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .filter_map(|c| c.times.last().copied())
            .fold(0.0, f32::max)
    }
}

impl Channel {
    /// The channel's value at time `t` (seconds): the first key's before the first key,
    /// the last key's after the last. Rotations come back as unit quaternions (x, y, z, w),
    /// translations and scales in xyz (w = 0). A channel with no keys (or missing values)
    /// gives the property's neutral value.
    pub fn sample(&self, t: f32) -> Vec4 {
        let rotation = self.property == Property::Rotation;
        let neutral = match self.property {
            Property::Translation => Vec4::ZERO,
            Property::Rotation => Vec4::W,
            Property::Scale => Vec4::new(1.0, 1.0, 1.0, 0.0),
        };
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let stride = if cubic { 3 } else { 1 };
        // Key k's value, in-tangent (a) and out-tangent (b).
        let at = |i: usize| self.values.get(i).copied().unwrap_or(neutral);
        let value = |k: usize| at(stride * k + usize::from(cubic));
        let finish = |v: Vec4| {
            if rotation {
                v.try_normalize().unwrap_or(Vec4::W)
            } else {
                v
            }
        };
        let n = self.times.len();
        if n == 0 {
            return neutral;
        }
        if n == 1 || t.is_nan() || t <= self.times[0] {
            return finish(value(0));
        }
        if t >= self.times[n - 1] {
            return finish(value(n - 1));
        }
        // times[k] <= t < times[k + 1]
        let k = self.times.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let td = t1 - t0;
        let s = if td > 0.0 {
            ((t - t0) / td).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (v0, v1) = (value(k), value(k + 1));
        // Between equal keys (and, for a spline, flat tangents) the value is the key,
        // exactly: the blends below round, and a held pose must not flicker by an ulp.
        let flat = !cubic || (at(3 * k + 2) == Vec4::ZERO && at(3 * (k + 1)) == Vec4::ZERO);
        if v0 == v1 && flat {
            return finish(v0);
        }
        finish(match self.interpolation {
            Interpolation::Step => v0,
            Interpolation::Linear if rotation => slerp(v0, v1, s),
            Interpolation::Linear => v0.lerp(v1, s),
            Interpolation::CubicSpline => {
                let (b0, a1) = (at(3 * k + 2), at(3 * (k + 1)));
                let (s2, s3) = (s * s, s * s * s);
                v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
                    + b0 * (td * (s3 - 2.0 * s2 + s))
                    + v1 * (-2.0 * s3 + 3.0 * s2)
                    + a1 * (td * (s3 - s2))
            }
        })
    }
}

/// Spherical interpolation of two unit quaternions (x, y, z, w) on the shorter arc
/// (glam's), normalised.
fn slerp(a: Vec4, b: Vec4, s: f32) -> Vec4 {
    let q = glam::Quat::from_vec4(a).slerp(glam::Quat::from_vec4(b), s);
    Vec4::from(q).try_normalize().unwrap_or(Vec4::W)
}

impl Rig {
    /// Local transforms of every node at clip time `t` (`None`: the rest pose). Looping
    /// is the caller's job (`t` in [0, duration]). `in_place`: the horizontal (x, z; glTF
    /// is +Y up) translation of each root node (no parent) is held at the clip's value
    /// at time 0, so a walk stays on the spot; its vertical bob is kept.
    pub fn pose(&self, clip: Option<&Clip>, t: f32, in_place: bool) -> Vec<Transform> {
        let mut locals: Vec<Transform> = self.nodes.iter().map(|n| n.rest).collect();
        let Some(clip) = clip else {
            return locals;
        };
        for c in &clip.channels {
            let Some(local) = locals.get_mut(c.node) else {
                continue;
            };
            let v = c.sample(t);
            match c.property {
                Property::Translation => {
                    let mut p = v.truncate();
                    if in_place && self.nodes[c.node].parent.is_none() {
                        let start = c.sample(0.0);
                        (p.x, p.z) = (start.x, start.z);
                    }
                    local.translation = p;
                }
                Property::Rotation => local.rotation = Quat::from_vec4(v),
                Property::Scale => local.scale = v.truncate(),
            }
        }
        locals
    }

    /// Each node's global transform (parents first; a node whose parent does not come
    /// before it is treated as a root). Missing locals are the rest transforms.
    pub fn world(&self, locals: &[Transform]) -> Vec<Mat4> {
        let mut world: Vec<Mat4> = Vec::with_capacity(self.nodes.len());
        for (i, node) in self.nodes.iter().enumerate() {
            let local = locals.get(i).unwrap_or(&node.rest).matrix();
            world.push(match node.parent {
                Some(p) if p < i => world[p] * local,
                _ => local,
            });
        }
        world
    }

    /// Per joint, its skinning matrix: `scale · global(node) · inverse_bind`.
    pub fn joint_matrices(&self, locals: &[Transform]) -> Vec<Mat4> {
        let world = self.world(locals);
        let scale = Mat4::from_scale(Vec3::splat(self.scale));
        self.joints
            .iter()
            .map(|j| scale * world.get(j.node).copied().unwrap_or(Mat4::IDENTITY) * j.inverse_bind)
            .collect()
    }

    /// The skinning matrices of the rest pose.
    pub fn rest_matrices(&self) -> Vec<Mat4> {
        self.joint_matrices(&self.pose(None, 0.0, false))
    }

    /// CPU linear blend skinning, the oracle for a GPU pass: per vertex the blended
    /// matrix `M = w0·M[j0] + w1·M[j1] + w2·M[j2] + w3·M[j3]` (in that order, f32), the
    /// position `(M · (p, 1)).xyz`, the normal `normalize(mat3(M) · n)`. `tangents`:
    /// extra per-vertex vectors (the first `tangents.len()` vertices') carried like the
    /// normals. Returns (positions, normals, tangents). A joint index past `matrices`
    /// counts as a zero matrix.
    pub fn skin(&self, matrices: &[Mat4], tangents: &[Vec3]) -> (Vec<Vec3>, Vec<Vec3>, Vec<Vec3>) {
        let count = self.bind_positions.len();
        let mut positions = Vec::with_capacity(count);
        let mut normals = Vec::with_capacity(count);
        let mut carried = Vec::with_capacity(tangents.len().min(count));
        for v in 0..count {
            let (j, w) = (self.influences[v], self.weights[v]);
            let joint = |k: usize| matrices.get(j[k] as usize).copied().unwrap_or(Mat4::ZERO);
            let m = joint(0) * w[0] + joint(1) * w[1] + joint(2) * w[2] + joint(3) * w[3];
            let linear = Mat3::from_mat4(m);
            positions.push((m * self.bind_positions[v].extend(1.0)).truncate());
            normals.push((linear * self.bind_normals[v]).normalize_or_zero());
            if let Some(t) = tangents.get(v) {
                carried.push((linear * *t).normalize_or_zero());
            }
        }
        (positions, normals, carried)
    }

    /// The index of the clip named `name` (case-insensitively); the error lists the
    /// clips there are.
    pub fn clip_index(&self, name: &str) -> std::result::Result<usize, String> {
        let wanted = name.to_lowercase();
        self.clips
            .iter()
            .position(|c| c.name.to_lowercase() == wanted)
            .ok_or_else(|| {
                let names: Vec<String> =
                    self.clips.iter().map(|c| format!("`{}`", c.name)).collect();
                if names.is_empty() {
                    format!("no clip named `{name}`: the model has no clips")
                } else {
                    format!(
                        "no clip named `{name}`; the model's clips: {}",
                        names.join(", ")
                    )
                }
            })
    }

    /// Per vertex, the unit direction of the bone its heaviest joint belongs to, in rest
    /// pose world space: from the joint's node to its first child that is also a joint
    /// (else its first child), else from its parent to it; +Y when none of these has a
    /// length. Directions point away from the hierarchy's root (down the legs, out along
    /// the tail, and up the spine towards the head).
    pub fn bone_directions(&self) -> Vec<Vec3> {
        let world = self.world(&self.pose(None, 0.0, false));
        let at = |n: usize| world[n].w_axis.truncate();
        let mut is_joint = vec![false; self.nodes.len()];
        for j in &self.joints {
            if let Some(flag) = is_joint.get_mut(j.node) {
                *flag = true;
            }
        }
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(p) = node.parent.filter(|&p| p < i) {
                children[p].push(i);
            }
        }
        let per_joint: Vec<Vec3> = self
            .joints
            .iter()
            .map(|j| {
                let n = j.node;
                if n >= self.nodes.len() {
                    return Vec3::Y;
                }
                let child = children[n]
                    .iter()
                    .find(|&&c| is_joint[c])
                    .or(children[n].first());
                child
                    .and_then(|&c| (at(c) - at(n)).try_normalize())
                    .or_else(|| {
                        let p = self.nodes[n].parent.filter(|&p| p < n)?;
                        (at(n) - at(p)).try_normalize()
                    })
                    .unwrap_or(Vec3::Y)
            })
            .collect();
        self.influences
            .iter()
            .zip(&self.weights)
            .map(|(j, w)| {
                let heaviest = (1..4).fold(0, |best, k| if w[k] > w[best] { k } else { best });
                per_joint
                    .get(j[heaviest] as usize)
                    .copied()
                    .unwrap_or(Vec3::Y)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests;
