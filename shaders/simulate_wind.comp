#version 450
// Step 5, wind (seed eq. 7–8). Per strand W = a W1 + (1−a) W2 + a W3 + (1−a) W4 with
// a = (strand mod 20)/20; each vertex moves by the part of W perpendicular to its
// tangent t, (t × W) × t (scaled by h² on the CPU). Tangents come from the positions
// before this step (all lanes read, barrier, then write).
#include "sim_common.glsl"

shared vec3 s_pos[GROUP_SIZE];

void main() {
    Lane l = lane();
    ivec2 t = texel(l);
    if (l.live) {
        s_pos[gl_LocalInvocationID.x] = imageLoad(current_positions, t).xyz;
    }
    barrier();
    if (!l.live || l.vertex == 0u) {
        return;
    }
    uint i = gl_LocalInvocationID.x;
    vec3 tangent = l.vertex + 1u < V ? s_pos[i] - s_pos[i + 1u] : s_pos[i - 1u] - s_pos[i];
    float len = length(tangent);
    if (!(len > MIN_LENGTH)) {
        return;
    }
    tangent = tangent * (1.0 / len);
    float a = float(l.strand % 20u) / 20.0;
    float b = 1.0 - a;
    vec4 w4[4] = steps[push.step].wind_h2;
    vec3 w = w4[0].xyz * a + w4[1].xyz * b + w4[2].xyz * a + w4[3].xyz * b;
    vec3 push_by = w - tangent * dot(w, tangent);
    imageStore(current_positions, t, vec4(s_pos[i] + push_by, 1.0));
}
