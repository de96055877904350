//! The collision step of the CPU reference (`collide` in `shaders/simulate.comp`, the
//! same arithmetic): a rigid body's signed distance field, or on a skinned body the rest
//! pose's field carried by each strand's root pose (with the skin's blend: the hair's
//! first eighth by its root's bone, its outer eighth by the blend) together with the
//! bones' capsules.

use super::math::{max, min, min_length, Head, Real, M3, V3};
use super::sdf::Sdf;

/// Projections onto the margin per vertex and substep, at most, on a rigid body.
/// Tuned (docs/testing.md, "Tuned constants").
pub const PROJECTIONS: u32 = 3;
/// The same on a skinned body, onto each of its constraints in turn. Further rounds
/// barely moved the walk's deepest vertex at a real share of the simulation step
/// (docs/benchmark.md); what one leaves, the next substep takes up.
/// Tuned (docs/testing.md, "Tuned constants").
pub const PROJECTIONS_SKINNED: u32 = 1;

/// The first vertex of a strand of `vertices` that the skin's blend carries back: from
/// seven eighths of the hair out (`BLEND_FROM` in `shaders/collide.glsl`). The root
/// pose is exact at the root and drifts from the skin with distance along the hair; the
/// blend's reads are dear on a CPU driver, and the vertices nearer the root measured the
/// same depths with it as without (docs/benchmark.md).
/// Tuned (docs/testing.md, "Tuned constants"), as is [`bone_to`].
pub fn blend_from(vertices: usize) -> usize {
    (7 * vertices.saturating_sub(1) / 8).max(1)
}

/// The last vertex of a strand of `vertices` that the root's bone carries back
/// (`Collider::root_bone`; `BONE_TO` in `shaders/collide.glsl`): the hair's first
/// eighth. Where the skin folds over a crease (an armpit, as the leg swings back), the
/// root pose, a blend of the root's bones, carries a vertex there back to the sheet the
/// hair grew from, outside, while the skin folded over it moves with one bone.
pub fn bone_to(vertices: usize) -> usize {
    vertices.saturating_sub(1) / 8
}

/// How a strand vertex is carried back to the rest pose (`CARRY_*` in
/// `shaders/collide.glsl`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Carry<T> {
    /// By the strand's root pose.
    Root,
    /// By the root's bone ([`Collider::root_bone`]): rest = backᵀ (m − t), `back` the
    /// inverse transpose of the bone's matrix, `t` its translation.
    Bone(M3<T>, V3<T>),
    /// By the skin's blend at the blend grid point nearest to the root pose's point.
    Blend,
}

/// A strand's root pose: rotation, rest root, skinned root (model space).
pub(super) type Pose<T> = (M3<T>, V3<T>, V3<T>);

/// The bones' capsules as posed in a substep and at the rest pose (each a pair of
/// ends, radius in the first's `w`, the child capsule's index in the second's).
#[derive(Clone, Copy)]
pub(super) struct Capsules<'a> {
    pub(super) posed: &'a [[glam::Vec4; 2]],
    pub(super) rest: &'a [[glam::Vec4; 2]],
}

/// How far a strand reaches from its root: its length, and the collision margin.
#[derive(Clone, Copy)]
pub(super) struct Reach<T> {
    pub(super) length: T,
    pub(super) margin: T,
}

/// A strand on a skinned body in one substep, as the collision of each of its vertices
/// sees it ([`Collider::push_out_skinned`]).
#[derive(Clone, Copy)]
pub(super) struct SkinnedStrand<'a, T> {
    /// The strand's root pose.
    pub pose: &'a Pose<T>,
    /// The bones' motions of this substep (three rows each), for the skin's blend.
    pub bones: &'a [[glam::Vec4; 3]],
    /// The capsules near the root ([`near_capsules`]).
    pub capsules: &'a [NearCapsule<T>],
    /// How far outside the body its vertices are kept (a fraction of its length).
    pub margin: T,
}

/// The body as the collision step sees it.
pub(super) struct Collider<'a, T> {
    pub sdf: &'a Sdf,
    /// A skinned body's blend of bones at each of the field's grid points (see
    /// [`crate::skinning::blend`]); empty: the root pose carries every vertex.
    pub blend: &'a [crate::skinning::blend::Packed],
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
/// Tuned (docs/testing.md, "Tuned constants").
pub const NEAR_CAPSULES: usize = 4;

/// How far, in strand lengths, a capsule's bone must move relative to a strand's root
/// for the capsule to reach its full radius (`near_capsules`). Chosen by the walking
/// critter's deepest vertex: a whole strand length lets hair into the skin near
/// joints, while a quarter or a tenth leave it as deep as capsules at full radius do.
/// Tuned (docs/testing.md, "Tuned constants").
pub const CAPSULE_RAMP: f32 = 0.25;

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
    Capsules {
        posed: capsules,
        rest,
    }: Capsules<'_>,
    Reach { length, margin }: Reach<T>,
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

/// A blended matrix's determinant below which it is taken as degenerate (the root pose
/// carries the vertex instead).
pub const MIN_DETERMINANT: f32 = 1e-6;

/// Substep `bones`' blended matrix `w Kₐ + (1 − w) K_b` of grid point `packed` (`Kₐ`
/// alone where `heaviest`), inverted: its inverse transpose (which carries the rest
/// field's gradient to model space) and its translation `t`, so that rest =
/// backᵀ (m − t); none where degenerate (`blend_inverse` in `shaders/collide.glsl`).
fn blend_inverse<T: Real>(
    bones: &[[glam::Vec4; 3]],
    packed: crate::skinning::blend::Packed,
    heaviest: bool,
) -> Option<(M3<T>, V3<T>)> {
    let (joints, share) = crate::skinning::blend::unpack(packed);
    let w = if heaviest { T::ONE } else { T::from_f32(share) };
    let v = T::ONE - w;
    let row = |i: usize| {
        let part = |k: usize, weight: T| {
            let r = bones
                .get(joints[k] as usize)
                .map_or(glam::Vec4::ZERO, |b| b[i]);
            [r.x, r.y, r.z, r.w].map(|c| T::from_f32(c) * weight)
        };
        let a = part(0, w);
        if heaviest {
            return a;
        }
        let b = part(1, v);
        [0, 1, 2, 3].map(|c| a[c] + b[c])
    };
    let (r0, r1, r2) = (row(0), row(1), row(2));
    let a0 = V3(r0[0], r1[0], r2[0]);
    let a1 = V3(r0[1], r1[1], r2[1]);
    let a2 = V3(r0[2], r1[2], r2[2]);
    let t = V3(r0[3], r1[3], r2[3]);
    let (x0, x1, x2) = (a1.cross(a2), a2.cross(a0), a0.cross(a1));
    let det = a0.dot(x0);
    if !greater(det, T::from_f32(MIN_DETERMINANT)) {
        return None;
    }
    let inv = T::ONE / det;
    Some((M3([x0.scale(inv), x1.scale(inv), x2.scale(inv)]), t))
}

impl<T: Real> Collider<'_, T> {
    /// The blend grid point nearest to rest-pose point `rest`, where it holds bones.
    fn texel(&self, rest: V3<T>) -> Option<crate::skinning::blend::Packed> {
        let packed =
            *crate::skinning::blend::nearest(self.sdf, rest).and_then(|at| self.blend.get(at))?;
        let (_, share) = crate::skinning::blend::unpack(packed);
        greater(T::from_f32(share), T::ZERO).then_some(packed)
    }

    /// The root's bone in a substep: the heaviest bone of the skin at the strand's rest
    /// root (its blend grid point), as the map [`Carry::Bone`]; where there is none, the
    /// root pose as the same map (`select_root_bone` in `shaders/collide.glsl`).
    pub fn root_bone(&self, pose: &Pose<T>, bones: &[[glam::Vec4; 3]]) -> Carry<T> {
        let (rotation, rest_root, root) = *pose;
        match self
            .texel(rest_root)
            .and_then(|packed| blend_inverse(bones, packed, true))
        {
            Some((back, t)) => Carry::Bone(back, t),
            None => Carry::Bone(rotation, root - rotation.mul_vec(rest_root)),
        }
    }

    /// Where model-space point `m` lies at the rest pose, and the map taking the rest
    /// field's gradient there to model space, carried as `carry` says: by the root
    /// `pose`; by the root's bone; or, where the blend grid point nearest to the root
    /// pose's point holds a blend of bones, by the inverse of the skin's blended matrix
    /// of this substep (`bones`), its inverse transpose carrying the gradient
    /// (`blend_back` in `shaders/collide.glsl`, the same arithmetic).
    fn carry_back(
        &self,
        m: V3<T>,
        pose: &Pose<T>,
        bones: &[[glam::Vec4; 3]],
        carry: Carry<T>,
    ) -> (V3<T>, M3<T>) {
        if let Carry::Bone(back, t) = carry {
            return (back.transpose_mul_vec(m - t), back);
        }
        let (rotation, rest_root, root) = *pose;
        let rest = rotation.transpose_mul_vec(m - root) + rest_root;
        if carry == Carry::Root {
            return (rest, rotation);
        }
        match self
            .texel(rest)
            .and_then(|packed| blend_inverse(bones, packed, false))
        {
            Some((back, t)) => (back.transpose_mul_vec(m - t), back),
            None => (rest, rotation),
        }
    }

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

    /// [`Collider::push_out`] on a skinned body: the rest pose's field carried as
    /// `carry` says from the `strand`'s root pose (sampled trilinearly: creases open and close as the body
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
        strand: &SkinnedStrand<'_, T>,
        arc: T,
        carry: Carry<T>,
        x: &mut V3<T>,
        previous: &mut V3<T>,
    ) {
        let SkinnedStrand {
            pose,
            bones,
            capsules,
            margin,
        } = *strand;
        let velocity = *x - *previous;
        let m0 = self.to_model.point(*x);
        let mut m = m0;
        let mut contact = None;
        for _ in 0..PROJECTIONS_SKINNED {
            let mut moved = false;
            let (rest, back) = self.carry_back(m, pose, bones, carry);
            if let Some((d, g)) = self.sdf.sample_trilinear(rest) {
                let len = g.length();
                if less(d, margin) && greater(len, min_length::<T>()) {
                    let mut n = back.mul_vec(g.scale(T::ONE / len));
                    if carry != Carry::Root {
                        // The blend's inverse transpose is not a rotation.
                        n = n.scale(T::ONE / n.length());
                    }
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

#[cfg(test)]
mod tests;
