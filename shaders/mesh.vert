#version 450
// Mesh (skin) pass: the model posed by the head transform. The world position goes on
// for shadows, the UV for a texture (TEXTURED, SHADOWS defined by the renderer).
#include "common.glsl"

#if !BODY_SKINNED
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#endif
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

#if BODY_SKINNED
// The posed body of the skinning pass (shaders/skin.comp): position, normal per vertex.
layout(set = SET_BODY, binding = B_POSED, std430) readonly buffer Posed {
    vec4 posed[];
};
// The triangle list: a textured mesh is drawn one vertex per corner, unindexed.
layout(set = SET_BODY, binding = B_INDICES, std430) readonly buffer Indices {
    uint mesh_indices[];
};
#endif

void main() {
#if BODY_SKINNED
#if TEXTURED
    uint v = mesh_indices[gl_VertexIndex];
#else
    uint v = uint(gl_VertexIndex);
#endif
    vec3 position = posed[2u * v].xyz;
    vec3 normal = posed[2u * v + 1u].xyz;
#else
    vec3 position = in_position;
    vec3 normal = in_normal;
#endif
    vec4 world = frame.camera.model * vec4(position, 1.0);
    v_normal = mat3(frame.camera.model) * normal;
#if SHADOWS
    v_world = world.xyz;
#endif
#if TEXTURED
    v_uv = in_uv;
#ifdef FUR_TEST_MIRROR_U
    v_uv.x = 1.0 - v_uv.x; // test only: a mirrored u that tests/looks.rs must reject
#endif
#endif
    gl_Position = frame.camera.view_proj * world;
}
