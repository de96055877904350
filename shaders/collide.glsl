// Step 6 of simulate.comp, collision with the body, included where the step's state
// (the strand's private arrays, its root pose and length) is declared. The CPU
// reference is crates/fur-core/src/sim/collide.rs, with the same arithmetic.
#ifndef COLLIDE_GLSL
#define COLLIDE_GLSL

#include "sdf_sample.glsl"

// Step 6, collision with the body: a vertex closer than the margin (a fraction of the
// strand's own length, so short hairs on thin parts are not pushed past their own
// segments) to the surface moves
// out along the surface's normal to the margin. The move is not velocity (the previous
// position moves with it, so nothing pops out); of the vertex's velocity the part into
// the body is removed (an inelastic contact) and friction removes part of the sliding
// part. The root is never moved.
//
// A rigid body's surface is its field. A skinned body's is the rest pose's field
// carried by this strand's root pose (with the skin's blend: the hair's first eighth by
// its root's bone, its outer eighth by the blend), and the bones' capsules of substep
// k; each is a constraint of its own, projected in turn (crates/fur-core/src/sim/collide.rs:
// `Collider::push_out_skinned`).

// The capsules a strand collides with in a substep: the NEAR_CAPSULES nearest to its
// root within its reach (hair length and margin from the capsule's surface); nearest
// first, ties by index. Each capsule's radius is scaled by how far its bone (or the
// far end of its child bone, which the skin at its end bends with) moved relative to
// the strand's root pose, over CAPSULE_RAMP strand lengths, up to 1: the rest field
// carried by the root pose already holds what moved with the root
// (crates/fur-core/src/sim/collide.rs: `near_capsules`).
vec4 near_a[NEAR_CAPSULES];    // a, radius
vec4 near_ab[NEAR_CAPSULES];   // b − a, |b − a|²
float near_root[NEAR_CAPSULES]; // the root's distance from the axis
uint near_count;

void select_capsules(uint k, float reach) {
    float near_d[NEAR_CAPSULES];
    near_count = 0u;
    uint count = sim.capsule_count;
    for (uint c = 0u; c < count; ++c) {
        // The buffer holds the bind pose's capsules, then each substep's.
        vec4 ca = capsule(2u * ((k + 1u) * count + c));
        vec3 a = ca.xyz;
        vec3 b = capsule(2u * ((k + 1u) * count + c) + 1u).xyz;
        vec3 ab = b - a;
        float len2 = dot(ab, ab);
        float t = len2 > 0.0 ? clamp(dot(pose_root - a, ab) / len2, 0.0, 1.0) : 0.0;
        float dist = length(pose_root - (a + ab * t));
        // Out of reach at its full radius, out of reach at any (the scaling below only
        // shrinks it).
        if (!(dist - ca.w < reach)) {
            continue;
        }
        vec3 ra = pose_rotation * (capsule(2u * c).xyz - rest_root) + pose_root;
        vec3 rb = pose_rotation * (capsule(2u * c + 1u).xyz - rest_root) + pose_root;
        float moved = max(length(a - ra), length(b - rb));
        float child = capsule(2u * c + 1u).w;
#ifdef FUR_TEST_NO_CHILD_MOTION
        child = -1.0; // tests only: the child bone's motion ignored
#endif
        if (child >= 0.0) {
            // The skin at the capsule's far end bends with its child bone: the child's
            // far end counts too.
            uint j = uint(child);
            vec3 kb = capsule(2u * ((k + 1u) * count + j) + 1u).xyz;
            vec3 rk = pose_rotation * (capsule(2u * j + 1u).xyz - rest_root) + pose_root;
            moved = max(moved, length(kb - rk));
        }
        float ramp = CAPSULE_RAMP * strand_length;
        float radius = ca.w * (moved < ramp ? moved / ramp : 1.0);
        float d = dist - radius;
        if (!(d < reach)) {
            continue;
        }
        // Insertion at its rank among those kept (ties keep the index order), written
        // with constant indices only: access to a private array through a varying
        // index is dear on a CPU driver (docs/design.md).
        uint rank = 0u;
        [[unroll]] for (uint j = 0u; j < NEAR_CAPSULES; ++j) {
            rank += j < near_count && !(d < near_d[j]) ? 1u : 0u;
        }
        if (rank == NEAR_CAPSULES) {
            continue;
        }
        [[unroll]] for (uint j = NEAR_CAPSULES - 1u; j > 0u; --j) {
            if (j > rank) {
                near_d[j] = near_d[j - 1u];
                near_root[j] = near_root[j - 1u];
                near_a[j] = near_a[j - 1u];
                near_ab[j] = near_ab[j - 1u];
            }
        }
        [[unroll]] for (uint j = 0u; j < NEAR_CAPSULES; ++j) {
            if (j == rank) {
                near_d[j] = d;
                near_root[j] = dist;
                near_a[j] = vec4(a, radius);
                near_ab[j] = vec4(ab, len2);
            }
        }
        near_count = min(near_count + 1u, NEAR_CAPSULES);
    }
}

// Blend grid points per field cell along each axis: BLEND_REFINE (crates/fur-core/src/skinning/blend.rs:
// REFINE, defined from Rust).

// The first vertex carried back through the skin's blend: from seven eighths of the hair
// out. The root pose is exact at the root and drifts from the skin with distance along
// the hair; the blend's reads are dear on a CPU driver, and vertices nearer the root
// measured the same depths with it and without (crates/fur-core/src/sim/collide.rs: BLEND_FROM).
const uint BLEND_FROM = (7u * (V - 1u)) / 8u;

// A blended matrix's determinant below which it is taken as degenerate: MIN_DETERMINANT
// (crates/fur-core/src/sim/collide.rs, defined from Rust).

// How a vertex is carried back to the rest pose (`collide`'s loops).
const uint CARRY_ROOT = 0u;  // by the strand's root pose
const uint CARRY_BONE = 1u;  // by the root's bone alone (select_root_bone)
const uint CARRY_BLEND = 2u; // by the skin's blend at the root pose's point

// The last vertex carried back by the root's bone: the hair's first eighth. Where the
// skin folds over a crease (an armpit, as the leg swings back), the blend of the root's
// bones (the root pose) carries a vertex there back to the sheet the hair grew from,
// outside, while the skin folded over it moves with one bone; the vertices beyond it
// measured the same depths either way (crates/fur-core/src/sim/collide.rs: BONE_TO).
const uint BONE_TO = (V - 1u) / 8u;

// Substep k's blended matrix w K_a + (1 − w) K_b of the bones in blend grid texel `b`
// (K_a alone where `heaviest`), inverted: false where degenerate; otherwise `back`, its
// inverse transpose (which carries the rest field's gradient to model space), and `t`,
// its translation, so that rest = transpose(back) · (m − t).
bool blend_inverse(uvec2 b, uint k, bool heaviest, out mat3 back, out vec3 t) {
    float w = heaviest ? 1.0 : uintBitsToFloat(b.y);
    float v = 1.0 - w;
    uint base = 3u * k * sim.joint_count;
    uint ja = base + 3u * (b.x & 0xffffu);
    vec4 r0 = imageLoad(bones, int(ja)) * w;
    vec4 r1 = imageLoad(bones, int(ja + 1u)) * w;
    vec4 r2 = imageLoad(bones, int(ja + 2u)) * w;
    if (!heaviest) {
        uint jb = base + 3u * (b.x >> 16u);
        r0 += imageLoad(bones, int(jb)) * v;
        r1 += imageLoad(bones, int(jb + 1u)) * v;
        r2 += imageLoad(bones, int(jb + 2u)) * v;
    }
    vec3 a0 = vec3(r0.x, r1.x, r2.x);
    vec3 a1 = vec3(r0.y, r1.y, r2.y);
    vec3 a2 = vec3(r0.z, r1.z, r2.z);
    t = vec3(r0.w, r1.w, r2.w);
    vec3 x0 = cross(a1, a2);
    vec3 x1 = cross(a2, a0);
    vec3 x2 = cross(a0, a1);
    float det = dot(a0, x0);
    back = mat3(1.0);
    if (!(det > MIN_DETERMINANT)) {
        return false;
    }
    float inv = 1.0 / det;
    back = mat3(x0 * inv, x1 * inv, x2 * inv);
    return true;
}

// The blend grid texel nearest to rest-pose point `rest`: false where it lies outside
// the grid or holds no bones.
bool blend_texel(vec3 rest, out uvec2 b) {
    b = uvec2(0u);
    vec3 g = (rest - sim.sdf_origin) * (sim.inverse_cell * float(BLEND_REFINE));
    vec3 last = vec3((sim.sdf_dims - 1u) * BLEND_REFINE);
    if (!(all(greaterThanEqual(g, vec3(0.0))) && all(lessThanEqual(g, last)))) {
        return false;
    }
    uvec3 at = uvec3(floor(g + 0.5));
    uvec4 texel = imageLoad(blend, ivec3(at.x >> 1u, at.yz));
    b = (at.x & 1u) != 0u ? texel.zw : texel.xy;
    return uintBitsToFloat(b.y) > 0.0;
}

// The root's bone in substep k: the heaviest bone of the skin at the strand's rest root
// (its blend grid point), as the map rest = transpose(bone_back) · (m − bone_t); where
// there is none, the root pose as the same map (crates/fur-core/src/sim/collide.rs: `root_bone`).
mat3 bone_back;
vec3 bone_t;
void select_root_bone(uint k) {
    uvec2 b;
    if (!(blend_texel(rest_root, b) && blend_inverse(b, k, true, bone_back, bone_t))) {
        bone_back = pose_rotation;
        bone_t = pose_root - pose_rotation * rest_root;
    }
}

// Where model-space point m lies at the rest pose (returned), with the map taking the
// rest field's gradient there to model space (`back`), carried as `carry` says (each
// of `collide`'s loops passes one constant: CARRY_ROOT alone without BODY_BLEND)
// (crates/fur-core/src/sim/collide.rs: `carry_back`): by the root pose; by the root's bone; or, where
// the blend grid point nearest to the root pose's point holds a blend of bones, by the
// inverse of the skin's blended matrix of substep k.
vec3 blend_back(vec3 m, uint k, uint carry, out mat3 back) {
#ifdef FUR_TEST_NO_ROOT_BONE
    // Test only: the hair's first eighth carried by the root pose, as before the root's
    // bone (tests/skinning/depth.rs must then see the crease's hair go deeper).
    if (carry == CARRY_BONE) {
        carry = CARRY_ROOT;
    }
#endif
    if (carry == CARRY_BONE) {
        back = bone_back;
        return transpose(bone_back) * (m - bone_t);
    }
    vec3 rest = transpose(pose_rotation) * (m - pose_root) + rest_root;
    back = pose_rotation;
    uvec2 b;
    mat3 blended;
    vec3 t;
    if (carry == CARRY_ROOT || !blend_texel(rest, b) || !blend_inverse(b, k, false, blended, t)) {
        return rest;
    }
    back = blended;
    return transpose(blended) * (m - t);
}

// The rest field's constraint on m, carried as `carry` says.
void push_field(inout vec3 m, uint k, float margin, uint carry, inout bool touched,
                inout vec3 contact, inout bool moved) {
    float d;
    vec3 g;
    mat3 back;
    vec3 r = blend_back(m, k, carry, back);
    if (sdf_sample_trilinear(r, d, g) && d < margin) {
        float len = length(g);
        if (len > MIN_LENGTH) {
            vec3 n = back * (g * (1.0 / len));
            if (carry != CARRY_ROOT) {
                // The blend's inverse transpose is not a rotation.
                n = n * (1.0 / length(n));
            }
            m = m + n * (margin - d);
            contact = touched ? contact : n;
            touched = true;
            moved = true;
        }
    }
}

// Moves model-space point m out to the margin of the skinned body (the rest field
// carried by the root pose, then the selected capsules, in turn, PROJECTIONS_SKINNED
// rounds at most), for a vertex `arc` along the hair from its root: a capsule pushes
// it no farther from its axis than the root's distance plus `arc`, as far as the
// vertex can get while attached (a root inside a capsule's radius, in a crease the
// capsule overfills, would otherwise have its first vertices pushed into the skin
// beside it). Returns the first contact's normal (model space) in `contact`, or false
// without contact. The round stays a loop at one round: written straight, the
// same arithmetic measured slower on lavapipe.
bool push_out_skinned(inout vec3 m, uint k, float arc, float margin, uint carry, out vec3 contact) {
    bool touched = false;
    contact = vec3(0.0);
    for (uint j = 0u; j < PROJECTIONS_SKINNED; ++j) {
        bool moved = false;
        push_field(m, k, margin, carry, touched, contact, moved);
        [[unroll]] for (uint c = 0u; c < NEAR_CAPSULES; ++c) {
            if (c >= near_count) {
                break;
            }
            vec3 a = near_a[c].xyz;
            vec3 ab = near_ab[c].xyz;
            float len2 = near_ab[c].w;
            float t = len2 > 0.0 ? clamp(dot(m - a, ab) / len2, 0.0, 1.0) : 0.0;
            vec3 off = m - (a + ab * t);
            float dist = length(off);
            // No farther out than a vertex `arc` along the hair from its root can reach.
#ifdef FUR_TEST_NO_REACH
            // Test only: every capsule pushes out to its full radius, however far the
            // vertex is along the hair (tests/skinning/depth.rs must then fail).
            float dc = dist - near_a[c].w;
#else
            float dc = dist - min(near_a[c].w, near_root[c] + arc);
#endif
            if (dc < margin && dist > MIN_LENGTH) {
                vec3 n = off * (1.0 / dist);
                m = m + n * (margin - dc);
                contact = touched ? contact : n;
                touched = true;
                moved = true;
            }
        }
        if (!moved) {
            break;
        }
    }
    return touched;
}

// Collision of vertex i with the body, carried back to the rest pose as `carry` says
// (see BONE_TO and BLEND_FROM).
void collide_vertex(Step st, uint k, float margin, uint i, uint carry) {
    // One read of each array per vertex, and on a skinned body one unconditional
    // write: a varying index into a private array is dear on a CPU driver, a masked
    // write more so (docs/design.md). The rigid body writes back only what it moved,
    // which measured cheaper there.
    vec3 xi = x[i];
    vec3 pi = p[i];
    vec3 velocity = xi - pi;
    vec3 contact = vec3(0.0);
    bool touched = false;
    if ((STEPS & BODY_SKINNED) != 0u) {
        vec3 m0 = (st.head_inverse * vec4(xi, 1.0)).xyz;
        vec3 m = m0;
        vec3 normal;
        float arc = float(i) * strand_length / float(V - 1u);
        if (push_out_skinned(m, k, arc, margin, carry, normal)) {
            // The contact's normal is the direction of the whole push: with the
            // field and a capsule both touching, the first one's normal would leave
            // the velocity into the other, and hair squeezed between them would
            // creep (crates/fur-core/src/sim/collide.rs: `push_out_skinned`).
            vec3 push = m - m0;
            float len = length(push);
            if (len > MIN_LENGTH) {
                normal = push * (1.0 / len);
            }
            xi = xi + mat3(st.head) * push;
            contact = mat3(st.head) * normal;
            touched = true;
        }
    } else {
        // The first contact's normal splits the velocity; a few more projections
        // settle a vertex that one step along a curved field leaves short of the
        // margin.
        for (uint j = 0u; j < PROJECTIONS; ++j) {
            float d;
            vec3 gradient;
            if (!sdf_sample((st.head_inverse * vec4(xi, 1.0)).xyz, d, gradient) || !(d < margin)) {
                break;
            }
            float len = length(gradient);
            if (!(len > MIN_LENGTH)) {
                break;
            }
            vec3 n = mat3(st.head) * (gradient * (1.0 / len));
            xi = xi + n * (margin - d);
            if (!touched) {
                contact = n;
                touched = true;
            }
        }
    }
    if (touched) {
        float normal = dot(velocity, contact);
        vec3 tangential = velocity - contact * normal;
        vec3 kept = tangential * (1.0 - sim.friction) + contact * max(normal, 0.0);
        pi = xi - kept;
    }
    if ((STEPS & BODY_SKINNED) != 0u || touched) {
        x[i] = xi;
        p[i] = pi;
    }
}

void collide(Step st, uint k, float margin) {
    if ((STEPS & BODY_SKINNED) != 0u) {
        select_capsules(k, strand_length + margin);
    }
    if ((STEPS & BODY_BLEND) == 0u) {
        for (uint i = 1u; i < V; ++i) {
            collide_vertex(st, k, margin, i, CARRY_ROOT);
        }
    } else {
        // A loop for each way of carrying, so that each vertex's code holds only its
        // own: a branch is no saving on a CPU driver, which runs both sides of it
        // under a mask.
        uint from = max(BLEND_FROM, 1u);
        if (BONE_TO > 0u) {
            select_root_bone(k);
        }
        for (uint i = 1u; i <= BONE_TO; ++i) {
            collide_vertex(st, k, margin, i, CARRY_BONE);
        }
        for (uint i = BONE_TO + 1u; i < from; ++i) {
            collide_vertex(st, k, margin, i, CARRY_ROOT);
        }
        for (uint i = from; i < V; ++i) {
            collide_vertex(st, k, margin, i, CARRY_BLEND);
        }
    }
}

#endif
