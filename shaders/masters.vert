#version 450
// The master hairs' views, as line strips, one instance per master hair and one vertex
// per strand vertex, read from the positions the simulation last wrote (world space).
// `masters`: each hair in its master index's colour. `simulation`: each vertex by how
// far the simulation moved it from rest, from the kernel's probe in the position's w
// (1 + the distance as a fraction of the hair's length, negated where collision pushed
// it; shaders/simulate.comp), white where pushed.
#include "common.glsl"

layout(location = 0) out vec3 v_colour;

void main() {
    uint strand = uint(gl_InstanceIndex);
    vec4 p = texelFetch(strand_positions, strand_texel(strand, uint(gl_VertexIndex), frame.strands.vertices_per_strand, frame.strands.strands_per_row), 0);
    gl_Position = frame.camera.view_proj * vec4(p.xyz, 1.0);
#if STAGE_VIEW == STAGE_SIMULATION
    // Blue at rest through green to red at DISPLACEMENT_FULL_SCALE of the length
    // (crates/fur-core/src/render/stage.rs: displacement_colour).
    float t = clamp((abs(p.w) - 1.0) / DISPLACEMENT_FULL_SCALE, 0.0, 1.0);
    v_colour = p.w < 0.0 ? vec3(1.0) : hue((1.0 - t) * (2.0 / 3.0));
#else
    // Golden-ratio steps of hue: masters with neighbouring indices differ in colour.
    v_colour = hue(fract(float(strand) * 0.6180339887));
#endif
}
