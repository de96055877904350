#version 450
// Strands in compute, the lighting under the Marschner model: each strand vertex of
// the lit frame takes its colour from what the geometry stage left in its colour's
// place (strand_raster.glsl: pack_shading: its tangent, its base colour and the coat's
// hair layers) and its world position, found from where it lies on the screen. The
// same lighting as the fixed-function backend's per-vertex shading (shading.glsl:
// marschner, through the shadow map with SHADOWS), run here because a compute pass
// runs on every core of a CPU driver, where the geometry stage runs on one (fur.geom
// says why Kajiya–Kay stays there). Each invocation lights every so-many-th vertex:
// dispatched by the bin passes' count (one invocation a segment), or on a CPU driver
// as a few workgroups (raster_steps.rs: lighting_groups).
// SHADOWS is defined by the renderer. Test only: with FUR_TEST_LIGHT_IN_GEOMETRY the
// geometry stage lights the strands and this pass leaves them (tests/compute_raster).
#undef MARSCHNER
#define MARSCHNER 1
#include "shading.glsl"
#include "strand_raster.glsl"

layout(local_size_x = GROUP_SIZE) in;

void main() {
#ifdef FUR_TEST_LIGHT_IN_GEOMETRY
    return;
#endif
    uint count = min(raster_counts.vertices, vertex_room());
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint v = gl_GlobalInvocationID.x; v < count; v += stride) {
        vec3 world = world_position(vertex_position(v));
        uvec4 packed = imageLoad(strand_vertices, int(2u * v + 1u));
        vec3 t = from_octahedral(unpackSnorm2x16(packed.x));
        vec2 bz = unpackHalf2x16(packed.z);
        vec3 base = vec3(unpackHalf2x16(packed.y), bz.x);
        vec3 color = marschner(t, world, base, vec2(bz.y, unpackHalf2x16(packed.w).x));
        imageStore(strand_vertices, int(2u * v + 1u), floatBitsToUint(vec4(color, 1.0)));
    }
}
