#version 450
// Fur pass, tessellation evaluation in point mode: every generated point is one
// interpolated hair, produced exactly once per patch. Points on a patch's corners and
// edges are also produced by the neighbouring patches; only the triangle that owns
// that corner or edge (bit mask from the CPU) keeps them, so no hair is drawn twice.
// The hair's root (the barycentric blend of the three master roots) becomes the
// point's position; the geometry shader blends the rest of the strand.
#include "common.glsl"

layout(triangles, equal_spacing, ccw, point_mode) in;

layout(location = 0) in uint c_hair[];
layout(location = 1) patch in uint p_mask;

layout(location = 0) out uvec3 e_hair;
layout(location = 1) out vec3 e_bary;
layout(location = 2) out uint e_keep;

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
    vec3 root = b.x * strand_vertex(c_hair[0], 0u) + b.y * strand_vertex(c_hair[1], 0u)
              + b.z * strand_vertex(c_hair[2], 0u);
    gl_Position = frame.view_proj * vec4(root, 1.0);
}
