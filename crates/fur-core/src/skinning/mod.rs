//! Skinned bodies in motion: which clip plays and when, the per-vertex tangent frames
//! that give each master hair its own root transform, the CPU reference skinning
//! (`cpu.rs`); the compute pass that skins the body on the device is the GPU layer's.
//!
//! A strand's root transform takes its rest pose to the posed body rigidly:
//! `S_s(x) = R_s (x − r_s) + q_s`, with `r_s` the rest root, `q_s` the skinned root and
//! `R_s = F_s · F_rest,sᵀ`, where a frame `F = [t, n × t, n]` is built from the skinned
//! normal `n` and the skinned tangent made orthogonal to it (Gram–Schmidt). Shear and
//! scale of the blended skinning matrix never reach the strand's shape. A rigid body's
//! head transform `H` is the case where every `S_s` is the identity.

pub mod blend;
pub mod capsules;
pub mod cpu;
pub mod dual_quaternion;

use glam::Vec3;

use crate::scene::{BoneFlow, Mesh, Rig};

pub use cpu::RootPose;

/// Which clip plays, how fast and from when.
#[derive(Clone, Debug, PartialEq)]
pub struct Playback {
    /// Index into the rig's clips; `None` holds the rest pose.
    pub clip: Option<usize>,
    /// Clip seconds per simulated second.
    pub speed: f32,
    /// Clip time at simulated time 0, seconds.
    pub start: f32,
    /// Wrap around at the clip's end (else hold its last pose).
    pub looping: bool,
    /// Remove the root's horizontal motion so the body moves on the spot.
    pub in_place: bool,
}

impl Default for Playback {
    fn default() -> Self {
        Self {
            clip: None,
            speed: 1.0,
            start: 0.0,
            looping: true,
            in_place: true,
        }
    }
}

impl Playback {
    /// The clip time at simulated time `t` (seconds).
    pub fn clip_time(&self, rig: &Rig, t: f64) -> f32 {
        let Some(clip) = self.clip.and_then(|c| rig.clips.get(c)) else {
            return 0.0;
        };
        let duration = f64::from(clip.duration());
        let t = f64::from(self.start) + f64::from(self.speed) * t;
        if duration <= 0.0 {
            0.0
        } else if self.looping {
            t.rem_euclid(duration) as f32
        } else {
            t.clamp(0.0, duration) as f32
        }
    }

    /// The skinning matrices of every joint at simulated time `t`.
    pub fn joint_matrices(&self, rig: &Rig, t: f64) -> Vec<glam::Mat4> {
        let clip = self.clip.and_then(|c| rig.clips.get(c));
        let locals = rig.pose(clip, self.clip_time(rig, t), self.in_place);
        rig.joint_matrices(&locals)
    }
}

/// A mesh with its rig, and what the skinning of its strands' roots needs: one bind-space
/// tangent per vertex and the rest frame `F_rest` it skins to.
#[derive(Clone, Debug)]
pub struct SkinnedBody {
    pub rig: Rig,
    /// Per vertex, a unit tangent orthogonal to the bind normal.
    pub bind_tangents: Vec<Vec3>,
    /// Per vertex, the rest frame's tangent and normal (`F_rest = [t, n × t, n]`).
    pub rest_frames: Vec<(Vec3, Vec3)>,
    /// The bones' capsules, for collision.
    pub capsules: Vec<capsules::Capsule>,
    /// Per vertex, its position at the rest pose (where the rest field is built).
    pub rest_positions: Vec<Vec3>,
    /// Per joint, the inverse of its skinning matrix at the rest pose.
    pub rest_inverse: Vec<glam::Mat4>,
}

impl SkinnedBody {
    /// Prepares `rig` (vertex-aligned with `mesh`): tangents from the bones' directions,
    /// and rest frames skinned from them with the CPU reference.
    pub fn new(mesh: &Mesh, rig: Rig) -> Self {
        let bones = rig.bone_directions();
        let bind_tangents: Vec<Vec3> = rig
            .bind_normals
            .iter()
            .zip(&bones)
            .map(|(&n, &b)| tangent_across(n, b))
            .collect();
        debug_assert_eq!(bind_tangents.len(), mesh.vertex_count());
        let rest = rig.rest_matrices();
        let (rest_positions, normals, tangents) = rig.skin(&rest, &bind_tangents);
        let rest_frames = normals
            .iter()
            .zip(&tangents)
            .map(|(&n, &t)| {
                let f = cpu::frame(n, t);
                (f.x_axis, f.z_axis)
            })
            .collect();
        let capsules = capsules::fit(&rig);
        let rest_inverse = rest.iter().map(|m| m.inverse()).collect();
        Self {
            rig,
            bind_tangents,
            rest_frames,
            capsules,
            rest_positions,
            rest_inverse,
        }
    }

    pub fn vertex_count(&self) -> usize {
        self.bind_tangents.len()
    }
}

/// A unit vector orthogonal to unit `n`, as close to `hint` as possible (any orthogonal
/// one when `hint` is parallel to `n` or zero).
pub fn tangent_across(n: Vec3, hint: Vec3) -> Vec3 {
    (hint - n * n.dot(hint))
        .try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector())
}

/// Per vertex, the direction fur flows on an animal: along the bone its heaviest joint
/// belongs to, away from the hierarchy's root (down the legs, out along the tail and
/// the ears), except along the chain from the root to the front-most joint (spine,
/// neck, head), where it runs back from the nose towards the tail. Whorls fall where
/// bones end: nose, paws, tail tip. With it, per vertex, its heaviest joint's weight.
pub fn fur_flow(rig: &Rig) -> BoneFlow {
    let world = rig.world(&rig.pose(None, 0.0, false));
    let front = rig
        .joints
        .iter()
        .map(|j| j.node)
        .filter(|&n| n < world.len())
        .max_by(|&a, &b| world[a].w_axis.z.total_cmp(&world[b].w_axis.z));
    let mut forward_chain = vec![false; rig.nodes.len()];
    let mut node = front;
    while let Some(n) = node.filter(|&n| n < rig.nodes.len() && !forward_chain[n]) {
        forward_chain[n] = true;
        node = rig.nodes[n].parent;
    }
    let (directions, one_bone) = rig
        .bone_directions()
        .into_iter()
        .zip(rig.influences.iter().zip(&rig.weights))
        .map(|(d, (joints, weights))| {
            let heaviest = (0..4)
                .max_by(|&a, &b| weights[a].total_cmp(&weights[b]))
                .unwrap_or(0);
            let joint = usize::from(joints[heaviest]);
            let on_chain = rig
                .joints
                .get(joint)
                .is_some_and(|j| forward_chain.get(j.node).copied().unwrap_or(false));
            let way = if on_chain { -d } else { d };
            (way, weights[heaviest])
        })
        .unzip();
    BoneFlow {
        directions,
        one_bone,
    }
}

/// Which clip a scene plays, by name (scene files' `[animation]`, `--animation`).
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationSpec {
    /// A clip name, matched in any case (`walk` finds `Walk`); `None` plays the
    /// model's first clip, `"none"` holds the rest pose.
    pub clip: Option<String>,
    /// Clip seconds per simulated second, [0, 100].
    pub speed: f32,
    /// Clip time at the first frame, seconds ≥ 0.
    pub start: f32,
    pub looping: bool,
    /// Walk on the spot: the root's horizontal motion is removed.
    pub in_place: bool,
}

impl Default for AnimationSpec {
    fn default() -> Self {
        Self {
            clip: None,
            speed: 1.0,
            start: 0.0,
            looping: true,
            in_place: true,
        }
    }
}

impl AnimationSpec {
    /// The playback of `rig`'s clip (an unknown name is an error listing the clips).
    /// A model without a rig plays nothing; naming a clip for it is an error.
    pub fn resolve(&self, rig: Option<Rig>, model: &str) -> crate::Result<Option<(Rig, Playback)>> {
        let error = |m: String| crate::Error::Parameter(format!("animation: {m}"));
        let Some(rig) = rig else {
            return match self.clip.as_deref() {
                Some(name) if name != "none" => Err(error(format!(
                    "model {model} has no skin or animation to play `{name}` on"
                ))),
                _ => Ok(None),
            };
        };
        let clip = match self.clip.as_deref() {
            Some("none") => None,
            Some(name) => Some(rig.clip_index(name).map_err(error)?),
            None => (!rig.clips.is_empty()).then_some(0),
        };
        if !(self.speed.is_finite() && (0.0..=100.0).contains(&self.speed)) {
            return Err(error(format!(
                "speed must be in [0, 100], got {}",
                self.speed
            )));
        }
        if !(self.start.is_finite() && self.start >= 0.0) {
            return Err(error(format!(
                "start must be a time ≥ 0 seconds, got {}",
                self.start
            )));
        }
        let playback = Playback {
            clip,
            speed: self.speed,
            start: self.start,
            looping: self.looping,
            in_place: self.in_place,
        };
        Ok(Some((rig, playback)))
    }
}

#[cfg(test)]
pub(crate) mod tests;
