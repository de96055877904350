//! The CPU reference simulation: the same algorithm, in the same order, as the compute
//! shaders, generic over `f32` (the GPU's precision) and `f64` (the converged oracle).

use std::sync::Arc;

use glam::DMat4;

use super::collide::{self, Carry};
use super::math::{max, min, min_length, Head, Real, M3, V3};
use super::params::{SimParams, StepConstants};
use super::rest::RestPose;
use super::sdf::Sdf;
use crate::scene::Strands;
use crate::skinning::cpu::Posed;
use crate::skinning::RootPose;

/// A strand whose root did not move in a frame (to this many ulps of its largest
/// coordinate) and whose other vertices moved by no more than that, or than slow motion
/// ([`REST_MOTION`], [`REST_GRAVITY`]), is at rest: it is put back where the frame
/// started, with no velocity. Constant targets leave f32 hair dithering by an ulp or two
/// a frame forever (the constraints' rounding never reaches a fixed point), and hair
/// that gravity presses into a crease of the body creeps there, contact switching on
/// and off; sleeping stops both, like static friction. Any real motion wakes the
/// strand: its root moving, or a frame from rest with an unbalanced force. With wind,
/// which never stops, nothing sleeps (and the kernel compiles the test out).
///
/// Tuned, as are the two below (docs/testing.md, "Tuned constants").
pub const SLEEP_ULPS: f32 = 16.0;
/// Slow motion at rest, per frame, at most this fraction of the strand's own length…
/// (tuned: small enough that hair swinging visibly never sleeps, large enough that hair
/// pressed into a crease of the walking critter's held pose stops creeping; bound by
/// `slow_motion_sleeps_and_faster_motion_does_not` and
/// `a_still_pose_under_gravity_with_collision_comes_to_rest`)
pub const REST_MOTION: f32 = 1e-3;
/// …and at most this fraction of `|g| Δt²`, about what gravity moves a free vertex in a
/// frame from rest, so a hair whose weight is not balanced always wakes.
pub const REST_GRAVITY: f32 = 0.1;

/// The CPU reference simulator for one set of master hairs.
#[derive(Clone, Debug)]
pub struct CpuSim<T: Real> {
    pub rest: RestPose<T>,
    pub params: SimParams,
    /// Positions one substep ago (world space).
    pub previous: Vec<V3<T>>,
    /// Current positions (world space).
    pub current: Vec<V3<T>>,
    /// Simulated time in seconds.
    pub time: f64,
    /// The body's distance field, for collision.
    pub sdf: Option<Arc<Sdf>>,
    /// The longest master hair.
    pub hair_length: f32,
    /// On a skinned body, every strand's root pose after the last substep (empty until
    /// the first posed substep or placement).
    pub last_poses: Vec<RootPose>,
    /// On a skinned body, the skin's blend of bones at each of the field's grid points
    /// (see [`crate::skinning::blend`]); empty: the root pose carries every vertex back.
    pub blend: Vec<crate::skinning::blend::Packed>,
}

impl<T: Real> CpuSim<T> {
    /// Starts at rest, posed by `head`.
    pub fn new(strands: &Strands, params: SimParams, head: DMat4) -> Self {
        let rest = RestPose::new(strands);
        let head = head.as_mat4();
        let current: Vec<V3<T>> = strands
            .positions
            .iter()
            .map(|p| V3::from_vec3(head.transform_point3(*p)))
            .collect();
        Self {
            rest,
            params,
            previous: current.clone(),
            current,
            time: 0.0,
            sdf: None,
            hair_length: strands.hair_length(),
            last_poses: Vec::new(),
            blend: Vec::new(),
        }
    }

    /// Collides the strands with the body whose distance field is `sdf` (when
    /// `params.collision` is on).
    pub fn with_sdf(mut self, sdf: Arc<Sdf>) -> Self {
        self.sdf = Some(sdf);
        self
    }

    /// Carries a skinned body's strand vertices back to the rest field through the
    /// skin's blend of bones (`blend`: per grid point of the field, see
    /// [`crate::skinning::blend::grid`]).
    pub fn with_blend(mut self, blend: Vec<crate::skinning::blend::Packed>) -> Self {
        self.blend = blend;
        self
    }

    pub fn vertices_per_strand(&self) -> usize {
        self.rest.vertices_per_strand
    }

    /// Advances one frame (`params.substeps` substeps), with the head transform given as
    /// a function of time.
    pub fn step_frame(&mut self, head_at: impl Fn(f64) -> DMat4) {
        self.advance(&head_at, None);
    }

    /// Advances one frame on a skinned body: `poses_at(t)` gives the body's pose at
    /// time `t`: every strand's root pose and the bones' capsules (see
    /// [`crate::skinning::cpu::pose`]).
    pub fn step_frame_posed(
        &mut self,
        head_at: impl Fn(f64) -> DMat4,
        poses_at: impl Fn(f64) -> Posed,
    ) {
        self.advance(&head_at, Some(&poses_at));
    }

    /// One frame: every substep, then sleep where hair can rest.
    fn advance(&mut self, head_at: &dyn Fn(f64) -> DMat4, poses_at: Option<&dyn Fn(f64) -> Posed>) {
        let start = self.params.hair_can_rest().then(|| self.current.clone());
        let h = self.params.substep_dt();
        let mut gravity_h2 = glam::Vec3::ZERO;
        for _ in 0..self.params.substeps {
            self.time += h;
            let constants = StepConstants::new(&self.params, self.time, head_at(self.time));
            gravity_h2 = constants.gravity_h2;
            let posed = poses_at.map(|poses_at| poses_at(self.time));
            self.substep_posed(&constants, posed.as_ref());
        }
        if let Some(start) = start {
            self.sleep(&start, gravity_h2);
        }
    }

    /// Puts every strand at rest this frame (see [`SLEEP_ULPS`]; from `start`) back
    /// where it started, not moving (`sleep` in `shaders/simulate.comp`); `gravity_h2`
    /// is the frame's substeps' g h².
    fn sleep(&mut self, start: &[V3<T>], gravity_h2: glam::Vec3) {
        let v = self.rest.vertices_per_strand;
        let ulps = T::from_f32(SLEEP_ULPS) * T::EPSILON;
        // |g h²| n², as the kernel computes it.
        let n = T::from_f32((self.params.substeps * self.params.substeps) as f32);
        let frame_gravity = V3::<T>::from_vec3(gravity_h2).length() * n;
        for (s, was) in start.chunks_exact(v).enumerate() {
            let range = s * v..(s + 1) * v;
            let root_moved = (self.current[s * v] - was[0]).max_abs();
            let mut moved = T::ZERO;
            let mut extent = T::ZERO;
            for (i, (x, w)) in self.current[range.clone()].iter().zip(was).enumerate() {
                if i > 0 {
                    moved = max(moved, (*x - *w).max_abs());
                }
                extent = max(extent, w.max_abs());
            }
            let length = self.rest.lengths[range.clone()]
                .iter()
                .skip(1)
                .fold(T::ZERO, |sum, &l| sum + l);
            let noise = ulps * extent;
            let slow = min(
                T::from_f32(REST_MOTION) * length,
                T::from_f32(REST_GRAVITY) * frame_gravity,
            );
            if root_moved <= noise && moved <= max(noise, slow) {
                self.current[range.clone()].copy_from_slice(was);
                self.previous[range].copy_from_slice(was);
            }
        }
    }

    /// Puts every strand at its rest shape carried by `head` and `poses` (one per
    /// strand; `None` for a rigid body), not moving.
    pub fn place(&mut self, head: DMat4, poses: Option<&[RootPose]>) {
        let v = self.rest.vertices_per_strand;
        if let Some(poses) = poses {
            self.last_poses = poses.to_vec();
        }
        let head = Head::<T>::new(head.as_mat4());
        for s in 0..self.rest.count() {
            let carrier = Carrier::new(&head, poses.map(|p| &p[s]), self.rest.positions[s * v]);
            for i in s * v..(s + 1) * v {
                let x = carrier.point(self.rest.positions[i]);
                self.current[i] = x;
                self.previous[i] = x;
            }
        }
    }

    /// One substep on a skinned body whose strands each follow their own root pose,
    /// colliding with the rest field carried by that pose and with the bones' capsules
    /// (`None`: the head transform alone, a rigid body).
    pub fn substep_posed(&mut self, c: &StepConstants, posed: Option<&Posed>) {
        let poses = posed.map(|p| p.roots.as_slice());
        if let Some(poses) = poses {
            if self.last_poses.len() != poses.len() {
                self.last_poses = poses.to_vec();
            }
        }
        let to_model = Head::<T>::new(c.head_inverse);
        let v = self.rest.vertices_per_strand;
        let head = Head::<T>::new(c.head);
        let retention = T::from_f32(c.velocity_retention);
        let gravity = V3::from_vec3(c.gravity_h2);
        let wind = c.wind_h2.map(V3::from_vec3);
        let cutoff = self.params.global_cutoff(v as u32) as usize;
        let s_g = T::from_f32(self.params.global_stiffness);
        let s_l = T::from_f32(self.params.local_stiffness);
        let collider = self
            .sdf
            .as_deref()
            .filter(|_| self.params.collision)
            .map(|sdf| collide::Collider {
                sdf,
                blend: if self.params.blends() {
                    &self.blend
                } else {
                    &[]
                },
                to_model: Head::new(c.head_inverse),
                fraction: T::from_f32(self.params.collision_margin),
                friction: T::from_f32(self.params.friction),
            });
        for s in 0..self.rest.count() {
            let range = s * v..(s + 1) * v;
            let rest = &self.rest.positions[range.clone()];
            let prev = &mut self.previous[range.clone()];
            let curr = &mut self.current[range];
            let carrier = Carrier::new(&head, poses.map(|p| &p[s]), rest[0]);
            // An unchanged pose carries nothing: skipping the ride keeps a held pose
            // exactly at rest (the carried map is the identity only up to rounding).
            if let Some(pose) = poses.map(|p| &p[s]).filter(|&p| *p != self.last_poses[s]) {
                let (last, x, p) = (&self.last_poses[s], &mut curr[1..], &mut prev[1..]);
                ride(&head, &to_model, last, pose, x, p);
                self.last_poses[s] = *pose;
            }
            // Integrate (Verlet); the new positions go into `prev`, then the two swap.
            prev[0] = carrier.point(rest[0]);
            for i in 1..v {
                prev[i] = curr[i] + (curr[i] - prev[i]).scale(retention) + gravity;
            }
            prev.swap_with_slice(curr);
            let x = curr;
            // Global shape constraint.
            for i in 1..=cutoff.min(v - 1) {
                x[i] = x[i] + (carrier.point(rest[i]) - x[i]).scale(s_g);
            }
            // Local shape constraint.
            for _ in 0..self.params.local_iterations {
                self.rest.local_walk(s, &carrier.frame, s_l, x);
            }
            // Edge-length constraint.
            let lengths = &self.rest.lengths[s * v..(s + 1) * v];
            for _ in 0..self.params.length_iterations {
                for parity in 0..2 {
                    for i in (parity..v - 1).step_by(2) {
                        let (a, b) = solve_length(x[i], x[i + 1], lengths[i + 1], i == 0);
                        x[i] = a;
                        x[i + 1] = b;
                    }
                }
            }
            // Wind.
            if self.params.wind_enabled() {
                let w = strand_wind(s, &wind);
                let old: Vec<V3<T>> = x.to_vec();
                for (i, xi) in x.iter_mut().enumerate().skip(1) {
                    *xi = *xi + wind_push(&old, i, w);
                }
            }
            // Collision with the body.
            if let Some(collider) = &collider {
                let capsules = posed.map_or(
                    collide::Capsules {
                        posed: &[],
                        rest: &[],
                    },
                    |p| collide::Capsules {
                        posed: p.capsules.as_slice(),
                        rest: p.rest_capsules.as_slice(),
                    },
                );
                // The margin is a fraction of this strand's own rest length.
                let length = lengths[1..].iter().fold(T::ZERO, |sum, &l| sum + l);
                let margin = collider.fraction * length;
                let near = carrier.pose.as_ref().map_or(Vec::new(), |pose| {
                    collide::near_capsules(pose, capsules, collide::Reach { length, margin })
                });
                let segments = T::from_f32((v - 1) as f32);
                let bones = posed.map_or(&[][..], |p| p.bones.as_slice());
                // As the kernel's loops: without the skin's blend the root pose carries
                // every vertex; with it, the first eighth goes by the root's bone and
                // the outer eighth through the blend.
                let blends = !collider.blend.is_empty();
                let (bone_to, outer) = (collide::bone_to(v), collide::blend_from(v));
                let bone = match &carrier.pose {
                    Some(pose) if blends && bone_to > 0 => collider.root_bone(pose, bones),
                    _ => Carry::Root,
                };
                let skinned = carrier.pose.as_ref().map(|pose| collide::SkinnedStrand {
                    pose,
                    bones,
                    capsules: &near,
                    margin,
                });
                for i in 1..v {
                    let carry = if !blends {
                        Carry::Root
                    } else if i <= bone_to {
                        bone
                    } else if i >= outer {
                        Carry::Blend
                    } else {
                        Carry::Root
                    };
                    match &skinned {
                        Some(strand) => collider.push_out_skinned(
                            &head,
                            strand,
                            T::from_f32(i as f32) * length / segments,
                            carry,
                            &mut x[i],
                            &mut prev[i],
                        ),
                        None => collider.push_out(&head, margin, &mut x[i], &mut prev[i]),
                    }
                }
            }
        }
    }
}

/// Carries a strand's vertices (`x`) and their previous positions (`p`) by the change of
/// its root pose from `last` to `now`, in model space under this substep's head
/// transform: the strand rides along with the body (`ride` in `simulate.comp`).
/// `to_model` is the inverse of `head`.
fn ride<T: Real>(
    head: &Head<T>,
    to_model: &Head<T>,
    last: &RootPose,
    now: &RootPose,
    x: &mut [V3<T>],
    p: &mut [V3<T>],
) {
    let m3 = |m: glam::Mat3| {
        M3([
            V3::from_vec3(m.x_axis),
            V3::from_vec3(m.y_axis),
            V3::from_vec3(m.z_axis),
        ])
    };
    let turn = m3(now.rotation).mul_mat(&m3(last.rotation).transpose());
    let (last_root, root) = (V3::from_vec3(last.root), V3::from_vec3(now.root));
    for v in x.iter_mut().chain(p.iter_mut()) {
        let m = to_model.point(*v);
        *v = head.point(turn.mul_vec(m - last_root) + root);
    }
}

/// What carries one strand's rest shape into world space: the head transform, after
/// the strand's root pose on a skinned body (`body_point` in `shaders/simulate.comp`).
struct Carrier<T> {
    head: Head<T>,
    /// Root pose rotation, rest root, skinned root.
    pose: Option<super::collide::Pose<T>>,
    /// The rotation the local-shape walk starts from (head, then pose); its translation
    /// is unused.
    frame: Head<T>,
}

impl<T: Real> Carrier<T> {
    fn new(head: &Head<T>, pose: Option<&RootPose>, rest_root: V3<T>) -> Self {
        let pose = pose.map(|p| {
            let col = |c: glam::Vec3| V3::from_vec3(c);
            (
                M3([
                    col(p.rotation.x_axis),
                    col(p.rotation.y_axis),
                    col(p.rotation.z_axis),
                ]),
                rest_root,
                col(p.root),
            )
        });
        let rotation = match &pose {
            Some((r, _, _)) => head.rotation.mul_mat(r),
            None => head.rotation,
        };
        Self {
            head: *head,
            pose,
            frame: Head {
                rotation,
                translation: head.translation,
            },
        }
    }

    fn point(&self, x: V3<T>) -> V3<T> {
        match &self.pose {
            Some((r, rest_root, root)) => self.head.point(r.mul_vec(x - *rest_root) + *root),
            None => self.head.point(x),
        }
    }
}

/// Moves the ends of one segment towards its rest length. The root (`pinned`) has
/// inverse mass 0 and stays put.
pub(crate) fn solve_length<T: Real>(p1: V3<T>, p2: V3<T>, rest: T, pinned: bool) -> (V3<T>, V3<T>) {
    let d = p1 - p2;
    let len = d.length();
    if len.partial_cmp(&min_length::<T>()) != Some(std::cmp::Ordering::Greater) {
        return (p1, p2);
    }
    let n = d.scale(T::ONE / len);
    let delta = n.scale(len - rest);
    if pinned {
        (p1, p2 + delta)
    } else {
        (p1 - delta.scale(T::HALF), p2 + delta.scale(T::HALF))
    }
}

/// The per-strand blend of the four wind vectors (seed eq. 8).
pub(crate) fn strand_wind<T: Real>(strand: usize, w: &[V3<T>; 4]) -> V3<T> {
    let a = T::from_f32((strand % 20) as f32 / 20.0);
    let b = T::ONE - a;
    w[0].scale(a) + w[1].scale(b) + w[2].scale(a) + w[3].scale(b)
}

/// The wind displacement of vertex `i`: the part of `w` perpendicular to the hair,
/// `(t × W) × t` for the unit tangent `t`.
pub(crate) fn wind_push<T: Real>(x: &[V3<T>], i: usize, w: V3<T>) -> V3<T> {
    let t = if i + 1 < x.len() {
        x[i] - x[i + 1]
    } else {
        x[i - 1] - x[i]
    };
    let len = t.length();
    if len.partial_cmp(&min_length::<T>()) != Some(std::cmp::Ordering::Greater) {
        return V3::ZERO;
    }
    let t = t.scale(T::ONE / len);
    w - t.scale(w.dot(t))
}

#[cfg(test)]
mod tests;
