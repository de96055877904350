#version 450
// Mesh (skin) pass: the model posed by the head transform. The world position goes on
// for shadows, the UV for a texture (TEXTURED, SHADOWS defined by the renderer).
#include "common.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#if TEXTURED
layout(location = 2) in vec2 in_uv;
#endif

layout(location = 0) out vec3 v_normal;
#if SHADOWS
layout(location = 1) out vec3 v_world;
#endif
#if TEXTURED
layout(location = 2) out vec2 v_uv;
#endif

void main() {
    vec4 world = frame.model * vec4(in_position, 1.0);
    v_normal = mat3(frame.model) * in_normal;
#if SHADOWS
    v_world = world.xyz;
#endif
#if TEXTURED
    v_uv = in_uv;
#endif
    gl_Position = frame.view_proj * world;
}
