#version 450
// Fur pass, geometry stage: emits one interpolated hair as a camera-facing ribbon,
// tapered from root to tip and never thinner than `frame.hair.y` pixels.
// STRAND_VERTICES is defined by the renderer when it compiles this stage.
#include "common.glsl"

layout(points) in;
layout(triangle_strip, max_vertices = 2 * STRAND_VERTICES) out;

layout(location = 0) in uvec3 e_hair[];
layout(location = 1) in vec3 e_bary[];
layout(location = 2) in uint e_keep[];

layout(location = 0) out vec4 g_tangent_along;   // world tangent, position along the hair

vec3 blended(uvec3 h, vec3 b, uint k) {
    return b.x * strand_vertex(h.x, k) + b.y * strand_vertex(h.y, k) + b.z * strand_vertex(h.z, k);
}

void main() {
    if (e_keep[0] == 0u) {
        return;
    }
    uvec3 h = e_hair[0];
    vec3 b = e_bary[0];
    uint V = uint(STRAND_VERTICES);
    uint seed = hash_u32(uint(gl_PrimitiveIDIn) * 0x9e3779b9u
                         ^ hash_u32(floatBitsToUint(b.x) ^ hash_u32(floatBitsToUint(b.y))));
    vec3 jitter = (vec3(hash_unit(seed), hash_unit(seed + 1u), hash_unit(seed + 2u)) * 2.0 - 1.0)
                * frame.hair.z;
    float length_scale = 1.0 - frame.hair.w * hash_unit(seed + 3u);

    vec3 root = blended(h, b, 0u);
    vec3 next = root + (blended(h, b, 1u) - root) * length_scale;
    vec3 p = root;
    vec3 t = vec3(0.0, 1.0, 0.0);
    for (uint k = 0u; k < V; ++k) {
        if (k + 1u < V) {
            vec3 d = next - p;
            if (dot(d, d) > 1e-24) {
                t = normalize(d);
            }
        }
        float along = float(k) / float(V - 1u);
        vec3 world = p + jitter * along;
        vec3 to_eye = frame.eye.xyz - world;
        float dist = length(to_eye);
        vec3 side = cross(t, to_eye);
        float side_len = length(side);
        side = side_len > 1e-12 ? side / side_len : vec3(1.0, 0.0, 0.0);
        float width = max(frame.hair.x * (1.0 - 0.8 * along), frame.hair.y * frame.eye.w * dist);
        g_tangent_along = vec4(t, along);
        gl_Position = frame.view_proj * vec4(world - side * (0.5 * width), 1.0);
        EmitVertex();
        g_tangent_along = vec4(t, along);
        gl_Position = frame.view_proj * vec4(world + side * (0.5 * width), 1.0);
        EmitVertex();
        p = next;
        if (k + 2u < V) {
            next = root + (blended(h, b, k + 2u) - root) * length_scale;
        }
    }
    EndPrimitive();
}
