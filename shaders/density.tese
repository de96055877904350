#version 450
// Stage view `density`, tessellation evaluation: the same patches and levels as the fur
// pass (fur.vert, fur.tesc), tessellated into triangles instead of points. Every vertex
// the tessellator generates here is a point the fur pass turns into a hair (its root,
// the barycentric blend of the three master roots); the triangles between them show
// how densely the control stage divided each body triangle.
#include "common.glsl"

layout(triangles, equal_spacing, ccw) in;

layout(location = 0) in uint c_hair[];
layout(location = 1) patch in uint p_mask;   // the edges this triangle draws (fur.tesc)

layout(location = 0) out float e_level;    // the patch's inner level
layout(location = 1) out vec3 e_coord;     // where in the patch (gl_TessCoord)
layout(location = 2) out float e_pixels;   // the patch's shortest edge on screen, pixels
layout(location = 3) out uint e_mask;

vec2 screen(vec3 p) {
    vec4 c = frame.camera.view_proj * vec4(p, 1.0);
    return c.xy / max(abs(c.w), 1e-6) * 0.5 * frame.camera.viewport;
}

void main() {
    vec3 r0 = strand_vertex(c_hair[0], 0u);
    vec3 r1 = strand_vertex(c_hair[1], 0u);
    vec3 r2 = strand_vertex(c_hair[2], 0u);
    vec3 b = gl_TessCoord;
    vec3 root = b.x * r0 + b.y * r1 + b.z * r2;
    vec2 s0 = screen(r0), s1 = screen(r1), s2 = screen(r2);
    e_pixels = min(distance(s0, s1), min(distance(s1, s2), distance(s2, s0)));
    e_level = gl_TessLevelInner[0];
    e_coord = b;
    e_mask = p_mask;
    // A thousandth of the way to the eye: drawn over the body it lies on (the mesh
    // pass, which shows the culled triangles), never behind it.
    root += (frame.camera.eye - root) * 1e-3;
    gl_Position = frame.camera.view_proj * vec4(root, 1.0);
}
