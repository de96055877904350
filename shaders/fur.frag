#version 450
// Fur pass, fragment stage: the hair's colour from its Kajiya–Kay terms (interpolated
// from the strand vertices with VERTEX_SHADING, evaluated here otherwise) and its
// root-to-tip ramp (see shading.glsl). Alpha is the hair's coverage of the pixel (1 for
// ribbons): blended at one sample per pixel, alpha to coverage under MSAA.
#include "shading.glsl"

#if VERTEX_SHADING
layout(location = 0) in vec4 g_lit_along_coverage;
#else
layout(location = 0) in vec4 g_tangent_along;
layout(location = 1) in vec4 g_world_coverage;
#endif
layout(location = 0) out vec4 out_color;

void main() {
#if VERTEX_SHADING
    vec4 v = g_lit_along_coverage;
    out_color = vec4(hair_color(v.xy, v.z), v.w);
#else
    vec2 lit = kajiya_kay(normalize(g_tangent_along.xyz), g_world_coverage.xyz);
    out_color = vec4(hair_color(lit, g_tangent_along.w), g_world_coverage.w);
#endif
}
