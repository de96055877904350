#version 450
// Once, at start-up: the rest data of the local and length constraints, computed with
// the very arithmetic the simulation steps use, so that the rest pose is an exact
// fixed point of a step on this device (crates/fur-core/src/sim/rest.rs is the CPU twin).
// One invocation per strand walks it root to tip:
//   F₀ = R(x → x̂₁ − x̂₀),  vᵢ = Fᵢᵀ (xᵢ₊₁ − xᵢ),  Fᵢ₊₁ = Fᵢ R(x → v̂ᵢ),
//   rest length of segment i = |xᵢ₊₁ − xᵢ| (stored in rest_positions[i + 1].w).
#define REST_ACCESS
#include "sim_common.glsl"

void main() {
    uint strand = gl_GlobalInvocationID.x;
    if (strand >= sim.strand_count) {
        return;
    }
    uint spr = sim.strands_per_row;
    vec3 x0 = imageLoad(rest_positions, strand_texel(strand, 0u, V, spr)).xyz;
    vec3 x1 = imageLoad(rest_positions, strand_texel(strand, 1u, V, spr)).xyz;
    float first = length(x1 - x0);
    mat3 frame = rotation_from_x(first > MIN_LENGTH ? (x1 - x0) * (1.0 / first) : vec3(1.0, 0.0, 0.0));
    root_frames[3u * strand] = vec4(frame[0], 0.0);
    root_frames[3u * strand + 1u] = vec4(frame[1], 0.0);
    root_frames[3u * strand + 2u] = vec4(frame[2], 0.0);
    vec3 xi = x0;
    imageStore(rest_positions, strand_texel(strand, 0u, V, spr), vec4(x0, 0.0));
    for (uint i = 0u; i + 1u < V; ++i) {
        ivec2 next = strand_texel(strand, i + 1u, V, spr);
        vec3 xj = imageLoad(rest_positions, next).xyz;
        vec3 v = transpose(frame) * (xj - xi);
        imageStore(rest_local, strand_texel(strand, i, V, spr), vec4(v, 0.0));
        imageStore(rest_positions, next, vec4(xj, length(xi - xj)));
        frame = advance_frame(frame, v);
        xi = xj;
    }
}
