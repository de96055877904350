#version 450
// Mesh (skin) pass: Lambert plus ambient, so gaps in the fur read as dark skin.
#include "common.glsl"

layout(location = 0) in vec3 v_normal;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(v_normal);
    float lambert = max(dot(n, frame.light.xyz), 0.0) * frame.light.w;
    out_color = vec4(frame.skin_color.rgb * (frame.shading.w + frame.shading.x * lambert), 1.0);
}
