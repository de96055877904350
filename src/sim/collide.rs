//! The collision step of the CPU reference (`collide` in `shaders/simulate.comp`, the
//! same arithmetic): a rigid body's signed distance field, or on a skinned body the rest
//! pose's field carried by each strand's root pose together with the bones' capsules.

use super::math::{min_length, Head, Real, M3, V3};
use super::sdf::Sdf;

/// Projections onto the margin per vertex and substep, at most.
const PROJECTIONS: usize = 3;

/// A strand's root pose: rotation, rest root, skinned root (model space).
pub(super) type Pose<T> = (M3<T>, V3<T>, V3<T>);

/// The body as the collision step sees it.
pub(super) struct Collider<'a, T> {
    pub sdf: &'a Sdf,
    /// World to model space (H⁻¹).
    pub to_model: Head<T>,
    pub margin: T,
    pub friction: T,
}

fn greater<T: Real>(a: T, b: T) -> bool {
    a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater)
}

fn less<T: Real>(a: T, b: T) -> bool {
    a.partial_cmp(&b) == Some(std::cmp::Ordering::Less)
}

impl<T: Real> Collider<'_, T> {
    /// Moves a vertex closer than the margin to a rigid body's surface out along the
    /// field's gradient to the margin. The move is not velocity (the previous position
    /// moves with it, so nothing pops out); of the vertex's velocity the part into the
    /// body is removed (an inelastic contact) and friction removes part of the sliding
    /// part.
    pub fn push_out(&self, head: &Head<T>, x: &mut V3<T>, previous: &mut V3<T>) {
        let velocity = *x - *previous;
        // The first contact's normal splits the velocity; a few more projections settle
        // a vertex that one step along a curved field leaves short of the margin.
        let mut contact = None;
        for _ in 0..PROJECTIONS {
            let Some((d, g)) = self.sdf.sample(self.to_model.point(*x)) else {
                break;
            };
            if !less(d, self.margin) {
                break;
            }
            let len = g.length();
            if !greater(len, min_length::<T>()) {
                break;
            }
            let n = head.rotation.mul_vec(g.scale(T::ONE / len));
            *x = *x + n.scale(self.margin - d);
            contact.get_or_insert(n);
        }
        self.respond(contact, velocity, *x, previous);
    }

    /// [`Collider::push_out`] on a skinned body: the rest pose's field carried by the
    /// strand's root `pose`, and every posed bone capsule (`(a, radius)`, `(b, 0)` in
    /// model space), each a constraint projected in turn, in model space.
    pub fn push_out_skinned(
        &self,
        head: &Head<T>,
        (pose, capsules): (&Pose<T>, &[[glam::Vec4; 2]]),
        x: &mut V3<T>,
        previous: &mut V3<T>,
    ) {
        let velocity = *x - *previous;
        let (rotation, rest_root, root) = pose;
        let m0 = self.to_model.point(*x);
        let mut m = m0;
        let mut contact = None;
        for _ in 0..PROJECTIONS {
            let mut moved = false;
            let rest = rotation.transpose_mul_vec(m - *root) + *rest_root;
            if let Some((d, g)) = self.sdf.sample(rest) {
                let len = g.length();
                if less(d, self.margin) && greater(len, min_length::<T>()) {
                    let n = rotation.mul_vec(g.scale(T::ONE / len));
                    m = m + n.scale(self.margin - d);
                    contact.get_or_insert(n);
                    moved = true;
                }
            }
            for c in capsules {
                let a = V3::from_vec3(c[0].truncate());
                let ab = V3::from_vec3(c[1].truncate()) - a;
                let len2 = ab.dot(ab);
                // clamp((m − a)·ab / |ab|², 0, 1), as GLSL's clamp.
                let t = if greater(len2, T::ZERO) {
                    let t = (m - a).dot(ab) / len2;
                    if less(t, T::ZERO) {
                        T::ZERO
                    } else if greater(t, T::ONE) {
                        T::ONE
                    } else {
                        t
                    }
                } else {
                    T::ZERO
                };
                let off = m - (a + ab.scale(t));
                let dist = off.length();
                let d = dist - T::from_f32(c[0].w);
                if less(d, self.margin) && greater(dist, min_length::<T>()) {
                    let n = off.scale(T::ONE / dist);
                    m = m + n.scale(self.margin - d);
                    contact.get_or_insert(n);
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        if let Some(n) = contact {
            *x = *x + head.rotation.mul_vec(m - m0);
            self.respond(Some(head.rotation.mul_vec(n)), velocity, *x, previous);
        }
    }

    /// After a contact with world normal `contact`: the previous position that keeps
    /// the vertex's sliding velocity (less friction) and its outward part.
    fn respond(&self, contact: Option<V3<T>>, velocity: V3<T>, x: V3<T>, previous: &mut V3<T>) {
        if let Some(n) = contact {
            let normal = velocity.dot(n);
            let tangential = velocity - n.scale(normal);
            let outward = if normal > T::ZERO { normal } else { T::ZERO };
            let kept = tangential.scale(T::ONE - self.friction) + n.scale(outward);
            *previous = x - kept;
        }
    }
}
