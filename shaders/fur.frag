#version 450
// Fur pass, fragment stage: the hair's colour from its lighting terms (interpolated
// from the strand vertices with VERTEX_SHADING, evaluated here otherwise, shadow
// included) and its root-to-tip ramp (see shading.glsl).
//
// Coverage: the hair's true width over the width it is drawn at (1 for hairs drawn at
// their true width). At one sample per pixel it is alpha, blended. Under MSAA
// (COVERAGE_SAMPLES > 1) it becomes a count of the pixel's samples, dithered by a hash
// of the pixel and the hair so that it is exact on average: n = floor(c · N + u), u
// uniform in [0, 1), starting at a hashed sample. Fixed-function alpha to coverage
// rounds instead (lavapipe covers one sample of four for any alpha above 0), which
// makes a hair drawn twice as wide at half the alpha twice as dark.
// VERTEX_SHADING, TEXTURED, SHADOWS, MARSCHNER and COVERAGE_SAMPLES are defined by the
// renderer.
#include "shading.glsl"

#if VERTEX_SHADING
layout(location = 0) in vec4 g_lit_along;          // ambient + diffuse, specular, tinted (Marschner: radiance), along
#else
layout(location = 0) in vec4 g_tangent_along;      // world tangent, along
layout(location = 1) in vec3 g_world;
#if MARSCHNER
layout(location = 5) in vec2 g_coat;
#endif
#endif
layout(location = 2) in float g_coverage;
#if TEXEL_TO_FRAGMENT
layout(location = 3) in vec3 g_texel;
#endif
#if COVERAGE_SAMPLES > 1
layout(location = 4) flat in uint g_seed;
#endif
layout(location = 0) out vec4 out_color;

void main() {
#if TEXEL_TO_FRAGMENT
    vec3 texel = g_texel;
#else
    vec3 texel = vec3(1.0);
#endif
#if STAGE_VIEW != 0
    // A stage view: the geometry stage's colour, unlit (always per vertex).
    vec3 color = g_lit_along.xyz;
#elif MARSCHNER
    // The fibre model's radiance (per vertex: interpolated). No root occlusion: the
    // coat's layers already darken what lies deep in it.
#if VERTEX_SHADING
    vec3 radiance = g_lit_along.xyz;
    float along = g_lit_along.w;
#else
    float along = g_tangent_along.w;
    vec3 radiance = marschner(normalize(g_tangent_along.xyz), g_world, hair_base(along, texel), g_coat);
#endif
    vec3 color = radiance;
#else
#if VERTEX_SHADING
    vec3 lit = g_lit_along.xyz;
    float along = g_lit_along.w;
#else
    vec3 lit = kajiya_kay(normalize(g_tangent_along.xyz), g_world, light_through_fur(g_world));
    float along = g_tangent_along.w;
#endif
    vec3 color = hair_color(lit, along, texel);
#endif
#if COVERAGE_SAMPLES > 1
    const uint N = uint(COVERAGE_SAMPLES);
    uint h = hash_u32(g_seed ^ hash_u32(uint(gl_FragCoord.x) | (uint(gl_FragCoord.y) << 16u)));
    uint count = min(uint(g_coverage * float(N) + hash_unit(h)), N);
    uint mask = (1u << count) - 1u;
    uint first = (h >> 28u) % N;
    gl_SampleMask[0] = int(((mask << first) | (mask >> (N - first))) & ((1u << N) - 1u));
    out_color = vec4(color, 1.0);
#else
    out_color = vec4(color, g_coverage);
#endif
}
