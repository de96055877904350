#version 450
// Mesh (skin) pass: the model posed by the head transform.
#include "common.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 v_normal;

void main() {
    vec4 world = frame.model * vec4(in_position, 1.0);
    v_normal = mat3(frame.model) * in_normal;
    gl_Position = frame.view_proj * world;
}
