#version 450
// Stage view `density`, fragment stage: the level's colour; the body triangle's edges
// darkened where the triangle is at least six pixels across, and the generated
// triangles' edges (between the hair roots) lightly where those are at least three.

layout(location = 0) flat in vec3 g_colour;
layout(location = 1) noperspective in vec3 g_bary;
layout(location = 2) flat in vec3 g_outer;
layout(location = 3) flat in float g_pixels;
layout(location = 0) out vec4 out_colour;

void main() {
    vec3 width = fwidth(g_bary);
    vec3 pixels = g_bary / max(width, vec3(1e-6));   // to each edge, in pixels
    // Inner edges: one pixel, faded out as the generated triangles shrink.
    float inner = 1.0 - smoothstep(0.0, 1.0, min(pixels.x, min(pixels.y, pixels.z)));
    inner *= 1.0 - smoothstep(0.25, 0.4, max(width.x, max(width.y, width.z)));
    // The body triangle's edges it owns: a pixel and a half, on its side.
    vec3 far = mix(vec3(1e9), pixels, g_outer);
    float outer = 1.0 - smoothstep(1.0, 2.0, min(far.x, min(far.y, far.z)));
    outer *= smoothstep(4.0, 8.0, g_pixels);
    float dark = max(0.35 * inner, 0.7 * outer);
    out_colour = vec4(g_colour * (1.0 - dark), 1.0);
}
