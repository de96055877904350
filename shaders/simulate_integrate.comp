#version 450
// Step 1, integrate: Verlet with gravity and damping,
//   x_new = x + r (x − x_prev) + g h²,
// written over x_prev (the ping-pong: the previous image becomes the current one).
// The root follows the head transform and is never simulated.
#include "sim_common.glsl"

void main() {
    Lane l = lane();
    if (!l.live) {
        return;
    }
    ivec2 t = texel(l);
    vec3 next;
    if (l.vertex == 0u) {
        next = head_point(imageLoad(rest_positions, t).xyz);
    } else {
        vec3 x = imageLoad(current_positions, t).xyz;
        vec3 x_prev = imageLoad(previous_positions, t).xyz;
        vec4 g = steps[push.step].gravity_h2;
        next = x + (x - x_prev) * g.w + g.xyz;
    }
    imageStore(previous_positions, t, vec4(next, 1.0));
}
