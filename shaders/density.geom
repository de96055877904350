#version 450
// Stage view `density`, geometry stage: emits each triangle the tessellator generated,
// flat in the colour of its patch's inner level, with barycentric coordinates for the
// fragment stage to outline it, and which of its edges lie on an edge of the body
// triangle that this triangle draws (each shared edge is outlined once, by the
// triangle that owns its hairs).
#include "common.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(location = 0) in float e_level[];
layout(location = 1) in vec3 e_coord[];
layout(location = 2) in float e_pixels[];
layout(location = 3) in uint e_mask[];

layout(location = 0) flat out vec3 g_colour;
layout(location = 1) noperspective out vec3 g_bary;
layout(location = 2) flat out vec3 g_outer;   // per edge (opposite corner k): on the body triangle's edge
layout(location = 3) flat out float g_pixels;

// Blue at level 1 through green to red at the device's largest level (frame.drawing.max_level),
// evenly in log₂ of the level (crates/fur-core/src/render/stage.rs: level_colour).
vec3 level_colour(float level, float max_level) {
    float t = clamp(log2(max(level, 1.0)) / log2(max(max_level, 2.0)), 0.0, 1.0);
    return hue((1.0 - t) * (2.0 / 3.0));
}

void main() {
    vec3 colour = level_colour(e_level[0], frame.drawing.max_level);
    // The edge opposite corner k joins corners k+1 and k+2: it lies on the patch's edge
    // opposite patch corner c when both have barycentric coordinate c at zero, and is
    // outlined when the patch owns that edge (bit 3 + c of its mask).
    vec3 outer = vec3(0.0);
    for (int k = 0; k < 3; ++k) {
        vec3 a = e_coord[(k + 1) % 3], b = e_coord[(k + 2) % 3];
        for (int c = 0; c < 3; ++c) {
            if (a[c] == 0.0 && b[c] == 0.0 && ((e_mask[0] >> (3 + c)) & 1u) != 0u) {
                outer[k] = 1.0;
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        gl_Position = gl_in[k].gl_Position;
        g_colour = colour;
        g_bary = vec3(0.0);
        g_bary[k] = 1.0;
        g_outer = outer;
        g_pixels = e_pixels[0];
        EmitVertex();
    }
    EndPrimitive();
}
