// Strand-texture addressing, shared by the fur pass and the simulation.
// Strand s occupies texels [(s % per_row) * V, +V) of row s / per_row.
#ifndef STRANDS_GLSL
#define STRANDS_GLSL

ivec2 strand_texel(uint strand, uint vertex, uint vertices_per_strand, uint strands_per_row) {
    return ivec2((strand % strands_per_row) * vertices_per_strand + vertex, strand / strands_per_row);
}

#endif
