#version 450
// Step 4, edge-length constraint, iterated. Each pass fixes even segments, then odd
// ones, so no vertex is written by two lanes at once; a workgroup barrier follows
// every pass. Segment (p1, p2) with rest length d:
//   n = (p1 − p2)/|p1 − p2|,  Δ = (|p1 − p2| − d) n,  p1 −= Δ/2,  p2 += Δ/2
// (the root has inverse mass 0, so p2 takes all of Δ on the first segment).
#include "sim_common.glsl"

shared vec3 s_pos[GROUP_SIZE];

void main() {
    Lane l = lane();
    ivec2 t = texel(l);
    float rest_next = 0.0;
    if (l.live) {
        s_pos[gl_LocalInvocationID.x] = imageLoad(current_positions, t).xyz;
        if (l.vertex + 1u < V) {
            rest_next = imageLoad(rest_positions, strand_texel(l.strand, l.vertex + 1u, V, sim.counts.y)).w;
        }
    }
    barrier();
    for (uint it = 0u; it < sim.counts2.x; ++it) {
        for (uint parity = 0u; parity < 2u; ++parity) {
            if (l.live && l.vertex + 1u < V && (l.vertex & 1u) == parity) {
                uint a = gl_LocalInvocationID.x;
                vec3 p1 = s_pos[a];
                vec3 p2 = s_pos[a + 1u];
                vec3 d = p1 - p2;
                float len = length(d);
                if (len > MIN_LENGTH) {
                    vec3 n = d * (1.0 / len);
                    vec3 delta = n * (len - rest_next);
                    if (l.vertex == 0u) {
                        s_pos[a + 1u] = p2 + delta;
                    } else {
                        s_pos[a] = p1 - delta * 0.5;
                        s_pos[a + 1u] = p2 + delta * 0.5;
                    }
                }
            }
            barrier();
        }
    }
    if (l.live && l.vertex > 0u) {
        imageStore(current_positions, t, vec4(s_pos[gl_LocalInvocationID.x], 1.0));
    }
}
