#version 450
// Fur pass, vertex stage: each triangle corner's master hair, read from the triangle
// list (the pass draws 3 vertices per triangle, unindexed), and the triangle's index.
// The triangle is passed down explicitly: lavapipe (Mesa 22.3) restarts gl_PrimitiveID
// in the tessellation stages every few hundred patches, so a triangle's per-triangle
// data (ownership mask, corner UVs, rest lengths) cannot be found through it.

#ifndef B_INDICES
#error "render shaders are compiled with binding_defines() (crates/fur-gpu/src/render/bindings.rs)"
#endif

layout(set = SET_BODY, binding = B_INDICES, std430) readonly buffer Indices {
    uint mesh_indices[];
};

layout(location = 0) out uint v_hair;
layout(location = 1) out uint v_triangle;

void main() {
    v_hair = mesh_indices[gl_VertexIndex];
    v_triangle = uint(gl_VertexIndex) / 3u;
}
