#version 450
#extension GL_EXT_control_flow_attributes : require
// The simulation of one frame: every substep of Han & Harada for one master strand per
// invocation. The strand lives in private arrays from the first load to the last store,
// and the named steps run in the paper's order inside each substep, then collision:
//   integrate → global shape → local shape → edge length → wind → collision.
// Steps a scene does not use are compiled out (STEPS, a specialization constant).
//
// Ping-pong: the frame reads current = positions[k] and previous = positions[1 − k],
// and writes the new current into positions[1 − k] and the new previous into
// positions[k]; the CPU then flips k. Each texel is read and written by its own strand's
// invocation only, so no barrier is needed inside the dispatch.
#include "sim_common.glsl"

layout(constant_id = 2) const uint STEPS = 0x1fu;
// Shared with Rust, defined for this shader from the Rust constants
// (crates/fur-gpu/src/sim/kernel.rs: kernel_defines), never typed here: the STEPS bits STEP_INTEGRATE, STEP_GLOBAL,
// STEP_LOCAL, STEP_LENGTH, STEP_WIND, STEP_COLLISION; BODY_SKINNED (the body is skinned:
// each strand's rest shape follows its own root pose from the skinning pass before the
// head transform); SLEEP (strands at rest sleep, see the end of main; compiled out with
// wind, which never stops); BODY_BLEND (a skinned body's collision carries vertices back
// through the skin's blend of bones, not the root pose alone); PROJECTIONS and
// PROJECTIONS_SKINNED (projections onto the collision margin per vertex and substep on a
// rigid and a skinned body, crates/fur-core/src/sim/collide.rs); SLEEP_ULPS, REST_MOTION (of the
// strand's own length a frame) and REST_GRAVITY (of g Δt², a free vertex's first frame
// from rest): a strand whose root stayed put to SLEEP_ULPS of its coordinates and whose
// other vertices moved by no more than that, or than the slow motion, sleeps
// (crates/fur-core/src/sim/cpu.rs); PROBE (the simulation view: see `probe` below).
#if !defined(STEP_GLOBAL) || !defined(SLEEP_ULPS) || !defined(PROJECTIONS)
#error "simulate.comp is compiled with kernel_defines() (crates/fur-gpu/src/sim/kernel.rs)"
#endif

vec3 x[V];   // current positions, world space
vec3 p[V];   // positions one substep ago

// Substep k's root pose of this strand: x ↦ R (x − r) + q (shaders/skin.comp).
mat3 pose_rotation;
vec3 pose_root;
vec3 rest_root;
float strand_length;   // this strand's rest length (collision and sleep only)

// The strand rides along with its root: every vertex (and its previous position) is
// carried by the change of the root pose since the last substep, in model space under
// this substep's head transform, before the forces act. The body's motion then never
// stretches the hair (a paw moves many times a short hair's segment in one step); the
// simulation keeps the hair's own motion in the root's frame (TressFX's velocity shock
// propagation at full strength). crates/fur-core/src/sim/cpu.rs: `ride`.
void ride(uint strand, Step st) {
    uint o = 3u * strand;
    vec4 c0 = imageLoad(last_poses, int(o));
    vec4 c1 = imageLoad(last_poses, int(o + 1u));
    vec4 c2 = imageLoad(last_poses, int(o + 2u));
    mat3 last_rotation = mat3(c0.xyz, c1.xyz, c2.xyz);
    vec3 last_root = vec3(c0.w, c1.w, c2.w);
    // An unchanged pose carries nothing: skipping keeps a held pose exactly at rest
    // (the map below is the identity only up to rounding).
    if (pose_rotation == last_rotation && pose_root == last_root) {
        return;
    }
    mat3 turn = pose_rotation * transpose(last_rotation);
    for (uint i = 1u; i < V; ++i) {
        vec3 m = (st.head_inverse * vec4(x[i], 1.0)).xyz;
        x[i] = (st.head * vec4(turn * (m - last_root) + pose_root, 1.0)).xyz;
        vec3 mp = (st.head_inverse * vec4(p[i], 1.0)).xyz;
        p[i] = (st.head * vec4(turn * (mp - last_root) + pose_root, 1.0)).xyz;
    }
    imageStore(last_poses, int(o), vec4(pose_rotation[0], pose_root.x));
    imageStore(last_poses, int(o + 1u), vec4(pose_rotation[1], pose_root.y));
    imageStore(last_poses, int(o + 2u), vec4(pose_rotation[2], pose_root.z));
}

void load_pose(uint strand, uint k) {
    if ((STEPS & BODY_SKINNED) != 0u) {
        uint o = 3u * (k * sim.strand_count + strand);
        vec4 c0 = imageLoad(root_poses, int(o));
        vec4 c1 = imageLoad(root_poses, int(o + 1u));
        vec4 c2 = imageLoad(root_poses, int(o + 2u));
        pose_rotation = mat3(c0.xyz, c1.xyz, c2.xyz);
        pose_root = vec3(c0.w, c1.w, c2.w);
    }
}

// Rest point `rest` of this strand carried by the body to world space: H x for a rigid
// body, H (R (x − r) + q) for a skinned one (crates/fur-core/src/sim/cpu.rs: `Carrier::point`).
vec3 body_point(Step st, vec3 rest) {
    if ((STEPS & BODY_SKINNED) != 0u) {
        return (st.head * vec4(pose_rotation * (rest - rest_root) + pose_root, 1.0)).xyz;
    }
    return (st.head * vec4(rest, 1.0)).xyz;
}

// The rotation part of body_point.
mat3 body_rotation(Step st) {
    if ((STEPS & BODY_SKINNED) != 0u) {
        return mat3(st.head) * pose_rotation;
    }
    return mat3(st.head);
}

// Step 1, integrate: Verlet with gravity and damping, x' = x + r (x − x_prev) + g h².
// The root follows the head transform and is never simulated.
void integrate(uint strand, Step st) {
    vec3 root = body_point(st, rest_root);
    p[0] = x[0];
    x[0] = root;
    for (uint i = 1u; i < V; ++i) {
        vec3 next = x[i] + (x[i] - p[i]) * st.gravity_h2.w + st.gravity_h2.xyz;
        p[i] = x[i];
        x[i] = next;
    }
}

// Step 2, global shape: x += S_G (H x_rest − x) for vertices 1..=cutoff.
void global_shape(uint strand, Step st) {
    uint cutoff = min(sim.global_cutoff, V - 1u);
    for (uint i = 1u; i <= cutoff; ++i) {
        vec3 target = body_point(st, imageLoad(rest_positions, strand_texel(strand, i, V, sim.strands_per_row)).xyz);
        x[i] = x[i] + (target - x[i]) * sim.global_stiffness;
    }
}

// Step 3, local shape (Han & Harada §4.2), iterated. Walking root to tip with the frame F
// (starting from H · F₀, or H R · F₀ on a skinned body), segment i's correction S_L F (vᵢ − Fᵀ(xᵢ₊₁ − xᵢ)) is split
// evenly between its ends (all of it to x₁, the root being pinned), then F turns onto
// the corrected segment. F (v − Fᵀd) equals xᵢ + F v − xᵢ₊₁ for an orthonormal F and is
// exactly zero at rest (simulate_rest.comp computed v with the same arithmetic).
void local_shape(uint strand, Step st) {
    float s_l = sim.local_stiffness;
    mat3 root = mat3(root_frames[3u * strand].xyz, root_frames[3u * strand + 1u].xyz,
                     root_frames[3u * strand + 2u].xyz);
    mat3 head = body_rotation(st);
    for (uint it = 0u; it < sim.local_iterations; ++it) {
        mat3 frame = head * root;
        for (uint i = 0u; i + 1u < V; ++i) {
            vec3 v = imageLoad(rest_local, strand_texel(strand, i, V, sim.strands_per_row)).xyz;
            vec3 xi = x[i];
            vec3 xj = x[i + 1u];
            vec3 delta = (frame * (v - transpose(frame) * (xj - xi))) * s_l;
            if (i == 0u) {
                xj = xj + delta;
            } else {
                xi = xi - delta * 0.5;
                xj = xj + delta * 0.5;
            }
            x[i] = xi;
            x[i + 1u] = xj;
            frame = advance_frame(frame, transpose(frame) * (xj - xi));
        }
    }
}

// Step 4, edge length, iterated: even segments, then odd ones. Segment (p1, p2) with
// rest length d: n = (p1 − p2)/|p1 − p2|, Δ = (|p1 − p2| − d) n, p1 −= Δ/2, p2 += Δ/2
// (the root has inverse mass 0, so p2 takes all of Δ on the first segment).
void edge_length(uint strand) {
    for (uint it = 0u; it < sim.length_iterations; ++it) {
        for (uint parity = 0u; parity < 2u; ++parity) {
            for (uint i = parity; i + 1u < V; i += 2u) {
                float rest = imageLoad(rest_positions, strand_texel(strand, i + 1u, V, sim.strands_per_row)).w;
                vec3 xi = x[i];
                vec3 xj = x[i + 1u];
                vec3 d = xi - xj;
                float len = length(d);
                vec3 delta = len > MIN_LENGTH ? d * (1.0 / len) * (len - rest) : vec3(0.0);
                if (i == 0u) {
                    xj = xj + delta;
                } else {
                    xi = xi - delta * 0.5;
                    xj = xj + delta * 0.5;
                }
                x[i] = xi;
                x[i + 1u] = xj;
            }
        }
    }
}

// Step 5, wind (seed eq. 7–8). W = a W1 + (1−a) W2 + a W3 + (1−a) W4 with
// a = (strand mod 20)/20; each vertex moves by the part of W across its unit tangent t,
// (t × W) × t (scaled by h² on the CPU). Tangents come from the positions before this
// step, so the walk keeps the previous vertex's old position.
void wind(uint strand, Step st) {
    float a = float(strand % 20u) / 20.0;
    float b = 1.0 - a;
    vec3 w = st.wind_h2[0].xyz * a + st.wind_h2[1].xyz * b + st.wind_h2[2].xyz * a + st.wind_h2[3].xyz * b;
    vec3 before = x[0];
    for (uint i = 1u; i < V; ++i) {
        vec3 tangent = i + 1u < V ? x[i] - x[i + 1u] : before - x[i];
        before = x[i];
        float len = length(tangent);
        if (len > MIN_LENGTH) {
            tangent = tangent * (1.0 / len);
            x[i] = x[i] + (w - tangent * dot(w, tangent));
        }
    }
}

#include "collide.glsl"

bool pushed[V];       // PROBE: whether collision moved the vertex this frame
vec3 arrow_from[V];   // PROBE: the vertices before the step drawn as arrows

// PROBE with arrows: whether named step `bit` of substep `s` is the one whose correction
// the simulation view draws (the frame's last substep).
bool arrow_step(uint bit, uint s) {
    return (STEPS & PROBE) != 0u && sim.probe_step == bit && s + 1u == push.count;
}

void arrow_begin(uint bit, uint s) {
    if (arrow_step(bit, s)) {
        for (uint i = 0u; i < V; ++i) {
            arrow_from[i] = x[i];
        }
    }
}

void arrow_end(uint bit, uint s, uint strand) {
    if (arrow_step(bit, s)) {
        for (uint i = 0u; i < V; ++i) {
            arrows[strand * V + i] = vec4(x[i] - arrow_from[i], 0.0);
        }
    }
}

// PROBE with arrows: no correction (the strand sleeps: the frame is undone).
void arrows_none(uint strand) {
    if ((STEPS & PROBE) != 0u && sim.probe_step != 0u) {
        for (uint i = 0u; i < V; ++i) {
            arrows[strand * V + i] = vec4(0.0);
        }
    }
}

// PROBE: the w the simulation view reads for vertex i, 1 + its distance from its rest
// shape carried by the body (this frame's last pose) as a fraction of the strand's
// rest length, negated when collision pushed it this frame; 1 without the probe.
float probe(uint strand, uint i, Step st) {
    if ((STEPS & PROBE) == 0u) {
        return 1.0;
    }
    vec3 rest = body_point(st, imageLoad(rest_positions, strand_texel(strand, i, V, sim.strands_per_row)).xyz);
    float w = 1.0 + distance(x[i], rest) / max(strand_length, MIN_LENGTH);
    return pushed[i] ? -w : w;
}

void main() {
    uint strand = gl_GlobalInvocationID.x;
    if (strand >= sim.strand_count) {
        return;
    }
    rest_root = imageLoad(rest_positions, strand_texel(strand, 0u, V, sim.strands_per_row)).xyz;
    if (push.place != 0u) {
        // Placement: the strand at its rest shape carried by the body, not moving.
        Step st = steps[push.step];
        load_pose(strand, 0u);
        if ((STEPS & BODY_SKINNED) != 0u) {
            imageStore(last_poses, int(3u * strand), vec4(pose_rotation[0], pose_root.x));
            imageStore(last_poses, int(3u * strand + 1u), vec4(pose_rotation[1], pose_root.y));
            imageStore(last_poses, int(3u * strand + 2u), vec4(pose_rotation[2], pose_root.z));
        }
        for (uint i = 0u; i < V; ++i) {
            ivec2 t = strand_texel(strand, i, V, sim.strands_per_row);
            vec3 posed = body_point(st, imageLoad(rest_positions, t).xyz);
            imageStore(previous_positions, t, vec4(posed, 1.0));
            imageStore(current_positions, t, vec4(posed, 1.0));
        }
        return;
    }
    for (uint i = 0u; i < V; ++i) {
        ivec2 t = strand_texel(strand, i, V, sim.strands_per_row);
        x[i] = imageLoad(current_positions, t).xyz;
        p[i] = imageLoad(previous_positions, t).xyz;
    }
    if ((STEPS & (STEP_COLLISION | SLEEP | PROBE)) != 0u) {
        // The collision margin and the slow motion at rest are fractions of this
        // strand's own rest length.
        strand_length = 0.0;
        for (uint i = 1u; i < V; ++i) {
            strand_length += imageLoad(rest_positions, strand_texel(strand, i, V, sim.strands_per_row)).w;
        }
    }
    for (uint i = 0u; i < V; ++i) {
        pushed[i] = false;
    }
    for (uint s = 0u; s < push.count; ++s) {
        Step st = steps[push.step + s];
        load_pose(strand, s);
        if ((STEPS & BODY_SKINNED) != 0u) {
            ride(strand, st);
        }
        // Each step between arrow_begin and arrow_end, run or compiled out (a step that
        // does not run corrects nothing: its arrows are zero).
        arrow_begin(STEP_INTEGRATE, s);
        integrate(strand, st);
        arrow_end(STEP_INTEGRATE, s, strand);
        arrow_begin(STEP_GLOBAL, s);
        if ((STEPS & STEP_GLOBAL) != 0u) {
            global_shape(strand, st);
        }
        arrow_end(STEP_GLOBAL, s, strand);
        arrow_begin(STEP_LOCAL, s);
        if ((STEPS & STEP_LOCAL) != 0u) {
            local_shape(strand, st);
        }
        arrow_end(STEP_LOCAL, s, strand);
        arrow_begin(STEP_LENGTH, s);
        if ((STEPS & STEP_LENGTH) != 0u) {
            edge_length(strand);
        }
        arrow_end(STEP_LENGTH, s, strand);
        arrow_begin(STEP_WIND, s);
        if ((STEPS & STEP_WIND) != 0u) {
            wind(strand, st);
        }
        arrow_end(STEP_WIND, s, strand);
        arrow_begin(STEP_COLLISION, s);
        if ((STEPS & STEP_COLLISION) != 0u) {
            if ((STEPS & PROBE) != 0u) {
                vec3 before[V];
                for (uint i = 0u; i < V; ++i) {
                    before[i] = x[i];
                }
                collide(st, push.step + s, sim.collision_margin * strand_length);
                for (uint i = 0u; i < V; ++i) {
                    pushed[i] = pushed[i] || any(notEqual(x[i], before[i]));
                }
            } else {
                collide(st, push.step + s, sim.collision_margin * strand_length);
            }
        }
        arrow_end(STEP_COLLISION, s, strand);
    }
    // Sleep: a strand whose root did not move this frame and whose other vertices moved
    // by no more than rounding noise (SLEEP_ULPS of its largest coordinate) or slow
    // motion (REST_MOTION of its length, REST_GRAVITY of what gravity moves a free
    // vertex in a frame from rest) goes back where it started, not moving. Constant
    // targets otherwise leave it dithering by an ulp forever, and hair pressed into a
    // crease by gravity creeping (crates/fur-core/src/sim/cpu.rs: `sleep`).
    bool asleep = false;
    if ((STEPS & SLEEP) != 0u) {
        float root_moved = 0.0;
        float moved = 0.0;
        float extent = 0.0;
        for (uint i = 0u; i < V; ++i) {
            vec3 was = imageLoad(current_positions, strand_texel(strand, i, V, sim.strands_per_row)).xyz;
            vec3 d = abs(x[i] - was);
            float m = max(d.x, max(d.y, d.z));
            if (i == 0u) {
                root_moved = m;
            } else {
                moved = max(moved, m);
            }
            vec3 a = abs(was);
            extent = max(extent, max(a.x, max(a.y, a.z)));
        }
        float noise = SLEEP_ULPS * 1.1920929e-7 * extent;
        float frame_gravity = length(steps[push.step].gravity_h2.xyz) * float(push.count * push.count);
        float slow = min(REST_MOTION * strand_length, REST_GRAVITY * frame_gravity);
        asleep = root_moved <= noise && moved <= max(noise, slow);
#ifdef FUR_TEST_NO_SLEEP
        asleep = false;   // test hook: the variant without sleep (tests/skinning.rs)
#endif
    }
    for (uint i = 0u; i < V; ++i) {
        ivec2 t = strand_texel(strand, i, V, sim.strands_per_row);
        if (asleep) {
            if (i == 0u) {
                arrows_none(strand);
            }
            // The new current is where the frame started; the new previous is already
            // there (current_positions holds the frame's start).
            imageStore(previous_positions, t, imageLoad(current_positions, t));
        } else {
            imageStore(previous_positions, t, vec4(x[i], probe(strand, i, steps[push.step + push.count - 1u])));
            imageStore(current_positions, t, vec4(p[i], 1.0));
        }
    }
}
