//! The collision step of the CPU reference (`collide` in `shaders/simulate.comp`, the
//! same arithmetic): a rigid body's signed distance field, or on a skinned body the rest
//! pose's field carried by each strand's root pose together with the bones' capsules.

use super::math::{max, min, min_length, Head, Real, M3, V3};
use super::sdf::Sdf;

/// Projections onto the margin per vertex and substep, at most, on a rigid body.
const PROJECTIONS: usize = 3;
/// The same on a skinned body, onto each of its constraints in turn. A second and third
/// round moved the walk's deepest vertex by 3e-4 hair lengths and took a tenth of the
/// simulation step (docs/benchmark.md); what one leaves, the next substep takes up.
const PROJECTIONS_SKINNED: usize = 1;

/// A strand's root pose: rotation, rest root, skinned root (model space).
pub(super) type Pose<T> = (M3<T>, V3<T>, V3<T>);

/// The body as the collision step sees it.
pub(super) struct Collider<'a, T> {
    pub sdf: &'a Sdf,
    /// World to model space (H⁻¹).
    pub to_model: Head<T>,
    /// The margin as a fraction of a strand's rest length.
    pub fraction: T,
    pub friction: T,
}

fn greater<T: Real>(a: T, b: T) -> bool {
    a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater)
}

fn less<T: Real>(a: T, b: T) -> bool {
    a.partial_cmp(&b) == Some(std::cmp::Ordering::Less)
}

/// clamp((m − a)·ab / |ab|², 0, 1) for `len2` = |ab|², as GLSL's clamp.
fn segment_parameter<T: Real>(m: V3<T>, a: V3<T>, ab: V3<T>, len2: T) -> T {
    if greater(len2, T::ZERO) {
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
    }
}

/// Capsules a strand collides with in a substep, at most.
const NEAR_CAPSULES: usize = 4;

/// How far, in strand lengths, a capsule's bone must move relative to a strand's root
/// for the capsule to reach its full radius ([`near_capsules`]). Measured on the walking
/// critter (deepest vertex, in hair lengths): 1 let hair 12.5 % into the skin near
/// joints; 0.25 and 0.1 both 8.1 %, as every capsule at its full radius does.
const CAPSULE_RAMP: f32 = 0.25;

/// A capsule as the collision loop reads it: `a`, radius, `b − a`, `|b − a|²`, and the
/// strand's root's distance from its axis.
#[derive(Clone, Copy, Debug)]
pub(super) struct NearCapsule<T> {
    a: V3<T>,
    radius: T,
    ab: V3<T>,
    len2: T,
    root: T,
}

/// The capsules a strand with root `pose` and rest `length` collides with: the
/// [`NEAR_CAPSULES`] nearest within `length + margin` of their surface; nearest first,
/// ties by index (`select_capsules` in `simulate.comp`).
///
/// The rest field carried by the root pose already holds every part of the body that
/// moved with the root; a capsule stands only for how far its bone moved *relative* to
/// it. Its radius is scaled by how far its posed ends lie from where the root pose
/// carries its `rest` ends, over [`CAPSULE_RAMP`] strand lengths, up to 1: a leg
/// swinging through the belly's fur has its whole radius, the thigh under the belly's
/// hair at the pose the field was built in has none (two shapes of one thigh would push
/// hair back and forth between them, and hair could never rest there), and the bone a
/// strand is bound to counts as far as the root's blend of bones moved away from it.
pub(super) fn near_capsules<T: Real>(
    pose: &Pose<T>,
    (capsules, rest): (&[[glam::Vec4; 2]], &[[glam::Vec4; 2]]),
    (length, margin): (T, T),
) -> Vec<NearCapsule<T>> {
    let (rotation, rest_root, root) = *pose;
    let reach = length + margin;
    let mut near: Vec<(T, NearCapsule<T>)> = Vec::with_capacity(NEAR_CAPSULES);
    for (c, cap) in capsules.iter().enumerate() {
        let a = V3::from_vec3(cap[0].truncate());
        let b = V3::from_vec3(cap[1].truncate());
        let ab = b - a;
        let len2 = ab.dot(ab);
        let t = segment_parameter(root, a, ab, len2);
        let dist = (root - (a + ab.scale(t))).length();
        // Out of reach at its full radius, out of reach at any (the scaling only shrinks
        // it).
        if !less(dist - T::from_f32(cap[0].w), reach) {
            continue;
        }
        let carried =
            |p: glam::Vec4| rotation.mul_vec(V3::from_vec3(p.truncate()) - rest_root) + root;
        let (ra, rb) = rest
            .get(c)
            .map_or((a, b), |r| (carried(r[0]), carried(r[1])));
        let mut moved = max((a - ra).length(), (b - rb).length());
        // The skin at the capsule's far end bends with its child bone: the child's far
        // end counts too.
        let child = rest.get(c).map_or(-1.0, |r| r[1].w);
        if child >= 0.0 {
            let j = child as usize;
            if let (Some(posed), Some(r)) = (capsules.get(j), rest.get(j)) {
                let kb = V3::from_vec3(posed[1].truncate());
                moved = max(moved, (kb - carried(r[1])).length());
            }
        }
        let ramp = T::from_f32(CAPSULE_RAMP) * length;
        let scale = if less(moved, ramp) {
            moved / ramp
        } else {
            T::ONE
        };
        let radius = T::from_f32(cap[0].w) * scale;
        let d = dist - radius;
        if !less(d, reach) {
            continue;
        }
        let mut j = if near.len() < NEAR_CAPSULES {
            near.push((
                d,
                NearCapsule {
                    a,
                    radius,
                    ab,
                    len2,
                    root: dist,
                },
            ));
            near.len() - 1
        } else if less(d, near[NEAR_CAPSULES - 1].0) {
            NEAR_CAPSULES - 1
        } else {
            continue;
        };
        while j > 0 && less(d, near[j - 1].0) {
            near[j] = near[j - 1];
            j -= 1;
        }
        near[j] = (
            d,
            NearCapsule {
                a,
                radius,
                ab,
                len2,
                root: dist,
            },
        );
    }
    near.into_iter().map(|(_, c)| c).collect()
}

impl<T: Real> Collider<'_, T> {
    /// Moves a vertex closer than the margin to a rigid body's surface out along the
    /// field's gradient to the margin. The move is not velocity (the previous position
    /// moves with it, so nothing pops out); of the vertex's velocity the part into the
    /// body is removed (an inelastic contact) and friction removes part of the sliding
    /// part.
    pub fn push_out(&self, head: &Head<T>, margin: T, x: &mut V3<T>, previous: &mut V3<T>) {
        let velocity = *x - *previous;
        // The first contact's normal splits the velocity; a few more projections settle
        // a vertex that one step along a curved field leaves short of the margin.
        let mut contact = None;
        for _ in 0..PROJECTIONS {
            let Some((d, g)) = self.sdf.sample(self.to_model.point(*x)) else {
                break;
            };
            if !less(d, margin) {
                break;
            }
            let len = g.length();
            if !greater(len, min_length::<T>()) {
                break;
            }
            let n = head.rotation.mul_vec(g.scale(T::ONE / len));
            *x = *x + n.scale(margin - d);
            contact.get_or_insert(n);
        }
        self.respond(contact, velocity, *x, previous);
    }

    /// [`Collider::push_out`] on a skinned body: the rest pose's field carried by the
    /// strand's root `pose` (sampled trilinearly: creases open and close as the body
    /// moves, and the nearest-point sample jumps in them), and the bone capsules near it
    /// ([`near_capsules`]), each a constraint projected in turn, in model space; the
    /// contact's normal is the direction of the whole push. For a vertex `arc` along
    /// the hair from its root, a capsule reaches no farther from its axis than the root's
    /// distance plus `arc`: as far as the vertex can get while attached. A root inside
    /// a capsule's radius, in a crease the capsule overfills (the armpit), would
    /// otherwise have its first vertices pushed into the skin beside it.
    pub fn push_out_skinned(
        &self,
        head: &Head<T>,
        (pose, capsules, arc, margin): (&Pose<T>, &[NearCapsule<T>], T, T),
        x: &mut V3<T>,
        previous: &mut V3<T>,
    ) {
        let velocity = *x - *previous;
        let (rotation, rest_root, root) = pose;
        let m0 = self.to_model.point(*x);
        let mut m = m0;
        let mut contact = None;
        for _ in 0..PROJECTIONS_SKINNED {
            let mut moved = false;
            let rest = rotation.transpose_mul_vec(m - *root) + *rest_root;
            if let Some((d, g)) = self.sdf.sample_trilinear(rest) {
                let len = g.length();
                if less(d, margin) && greater(len, min_length::<T>()) {
                    let n = rotation.mul_vec(g.scale(T::ONE / len));
                    m = m + n.scale(margin - d);
                    contact.get_or_insert(n);
                    moved = true;
                }
            }
            for c in capsules {
                let (a, ab) = (c.a, c.ab);
                let t = segment_parameter(m, a, ab, c.len2);
                let off = m - (a + ab.scale(t));
                let dist = off.length();
                let d = dist - min(c.radius, c.root + arc);
                if less(d, margin) && greater(dist, min_length::<T>()) {
                    let n = off.scale(T::ONE / dist);
                    m = m + n.scale(margin - d);
                    contact.get_or_insert(n);
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        if let Some(first) = contact {
            // The contact's normal is the direction of the whole push: with the field
            // and a capsule both touching, the first one's normal would leave the
            // velocity into the other, and hair squeezed between them would creep.
            let push = m - m0;
            let len = push.length();
            let n = if greater(len, min_length::<T>()) {
                push.scale(T::ONE / len)
            } else {
                first
            };
            *x = *x + head.rotation.mul_vec(push);
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
