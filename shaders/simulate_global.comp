#version 450
// Step 2, global shape constraint: x += S_G (H x_rest − x) for vertices 1..=cutoff.
#include "sim_common.glsl"

void main() {
    Lane l = lane();
    if (!l.live || l.vertex == 0u || l.vertex > sim.counts.z) {
        return;
    }
    ivec2 t = texel(l);
    vec3 x = imageLoad(current_positions, t).xyz;
    vec3 target = head_point(imageLoad(rest_positions, t).xyz);
    x = x + (target - x) * sim.stiffness.x;
    imageStore(current_positions, t, vec4(x, 1.0));
}
