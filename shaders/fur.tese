#version 450
// Fur pass, tessellation evaluation in point mode: every generated point is one
// interpolated hair, produced exactly once per patch. Points on a patch's corners and
// edges are also produced by the neighbouring patches; only the triangle that owns
// that corner or edge (bit mask from the CPU) keeps them, so no hair is drawn twice.
// The hair's root (the barycentric blend of the three master roots) becomes the
// point's position; the geometry shader blends the rest of the strand.
// TEXTURED: the root's UV is the same blend of the triangle's corner UVs, and the
// texture level of detail matches the texels per hair.
#include "common.glsl"

layout(triangles, equal_spacing, ccw, point_mode) in;

layout(location = 0) in uint c_hair[];
layout(location = 1) patch in uint p_mask;
#if TEXTURED
layout(location = 2) patch in uint p_triangle;   // this patch's triangle (see fur.vert)
#endif

layout(location = 0) out uvec3 e_hair;
layout(location = 1) out vec3 e_bary;
layout(location = 2) out uint e_keep;

#if TEXTURED
layout(set = SET_BODY, binding = B_CORNER_UVS, std430) readonly buffer CornerUvs {
    vec2 corner_uv[];   // three per triangle
};
layout(location = 3) out vec3 e_uv_lod;
#endif

void main() {
    vec3 b = gl_TessCoord;
    uint keep = 1u;
    for (int k = 0; k < 3; ++k) {
        if (b[k] == 1.0) {
            keep = (p_mask >> k) & 1u;               // a corner: a master hair
        }
    }
    if (b.x != 1.0 && b.y != 1.0 && b.z != 1.0) {
        for (int k = 0; k < 3; ++k) {
            if (b[k] == 0.0) {
                keep = (p_mask >> (3 + k)) & 1u;     // on the edge opposite corner k
            }
        }
    }
    e_hair = uvec3(c_hair[0], c_hair[1], c_hair[2]);
    e_bary = b;
    e_keep = keep;
#if TEXTURED
    uint t = 3u * p_triangle;
    vec2 u0 = corner_uv[t], u1 = corner_uv[t + 1u], u2 = corner_uv[t + 2u];
    // Texels per hair: the triangle's texture area over the ~3n²/4 hairs of inner level n.
    float n = max(gl_TessLevelInner[0], 1.0);
    float uv_area = 0.5 * abs(cross(vec3(u1 - u0, 0.0), vec3(u2 - u0, 0.0)).z);
    float texels = uv_area * frame.drawing.texels / max(0.75 * n * n, 1.0);
    e_uv_lod = vec3(b.x * u0 + b.y * u1 + b.z * u2, 0.5 * log2(max(texels, 1.0)));
#ifdef FUR_TEST_MIRROR_U
    e_uv_lod.x = 1.0 - e_uv_lod.x; // test only: a mirrored u that tests/looks.rs must reject
#endif
#endif
    vec3 root = b.x * strand_vertex(c_hair[0], 0u) + b.y * strand_vertex(c_hair[1], 0u)
              + b.z * strand_vertex(c_hair[2], 0u);
    gl_Position = frame.camera.view_proj * vec4(root, 1.0);
}
