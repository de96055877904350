#version 450
// Step 3, local shape constraint (Han & Harada §4.2), iterated. Walking root to tip
// with the current frame F (starting from H · F₀), segment i's target end is
// x_i + F v_i; the correction S_L (target − x_{i+1}) is split evenly between both ends
// (all of it to x_1, as the root is pinned), then F turns onto the corrected segment.
// The walk is sequential along a strand: one lane per strand walks it in shared memory.
#include "sim_common.glsl"

shared vec3 s_pos[GROUP_SIZE];

void main() {
    Lane l = lane();
    ivec2 t = texel(l);
    if (l.live) {
        s_pos[gl_LocalInvocationID.x] = imageLoad(current_positions, t).xyz;
    }
    barrier();
    if (l.live && l.vertex == 0u) {
        float s_l = sim.stiffness.y;
        mat3 root = mat3(root_frames[3u * l.strand].xyz, root_frames[3u * l.strand + 1u].xyz,
                         root_frames[3u * l.strand + 2u].xyz);
        mat3 head = mat3(steps[push.step].head);
        for (uint it = 0u; it < sim.counts.w; ++it) {
            mat3 frame = head * root;
            for (uint i = 0u; i + 1u < V; ++i) {
                vec3 v = imageLoad(rest_local, strand_texel(l.strand, i, V, sim.counts.y)).xyz;
                vec3 xi = s_pos[l.base + i];
                vec3 xj = s_pos[l.base + i + 1u];
                // F (v − Fᵀ(x_j − x_i)) equals x_i + F v − x_j for orthonormal F and is
                // exactly zero at rest (simulate_rest.comp computed v the same way).
                vec3 delta = (frame * (v - transpose(frame) * (xj - xi))) * s_l;
                if (i == 0u) {
                    xj = xj + delta;
                } else {
                    xi = xi - delta * 0.5;
                    xj = xj + delta * 0.5;
                }
                s_pos[l.base + i] = xi;
                s_pos[l.base + i + 1u] = xj;
                frame = advance_frame(frame, transpose(frame) * (xj - xi));
            }
        }
    }
    barrier();
    if (l.live && l.vertex > 0u) {
        imageStore(current_positions, t, vec4(s_pos[gl_LocalInvocationID.x], 1.0));
    }
}
