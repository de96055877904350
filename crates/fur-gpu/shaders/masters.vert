#version 450
// Stage view `masters`: the master hairs as line strips, one instance per master hair
// and one vertex per strand vertex, read from the positions the simulation last wrote
// (world space), each coloured by its master index.
#include "common.glsl"

layout(location = 0) out vec3 v_colour;

void main() {
    uint strand = uint(gl_InstanceIndex);
    gl_Position = frame.view_proj * vec4(strand_vertex(strand, uint(gl_VertexIndex)), 1.0);
    // Golden-ratio steps of hue: masters with neighbouring indices differ in colour.
    v_colour = hue(fract(float(strand) * 0.6180339887));
}
