#version 450
// Strands in compute, pass 1: each tile's farthest body depth (the mesh pass's depth,
// the farthest of a pixel's samples), and its bin emptied (its key range too). One workgroup per tile,
// one invocation per pixel. TILE, DEPTH_SAMPLES are defined by the renderer.
#include "common.glsl"
#include "strand_raster.glsl"

// The workgroup: an invocation a pixel of the tile, or on a CPU driver one SIMD vector
// (compute_raster.rs, tile_group), each invocation taking every GROUP-th pixel.
const uint GROUP = TILE_GROUP;
layout(local_size_x = GROUP) in;

#if DEPTH_SAMPLES > 1
layout(set = SET_RASTER, binding = B_BODY_DEPTH) uniform sampler2DMS body_depth;
#else
layout(set = SET_RASTER, binding = B_BODY_DEPTH) uniform sampler2D body_depth;
#endif

// The farthest depth of the tile's pixels, as its bits (non-negative floats order as
// their bits do).
shared uint farthest;

// The farthest depth of pixel p's samples.
float pixel_depth(ivec2 p) {
#if DEPTH_SAMPLES > 1
    float d = 0.0;
    for (int i = 0; i < DEPTH_SAMPLES; ++i) {
        d = max(d, texelFetch(body_depth, p, i).r);
    }
    return d;
#else
    return texelFetch(body_depth, p, 0).r;
#endif
}

void main() {
    ivec2 corner = ivec2(gl_WorkGroupID.xy) * TILE;
    ivec2 size = ivec2(frame.camera.viewport);
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        farthest = 0u;
    }
    barrier();
    float depth = 0.0;
    for (uint k = me; k < TILE * TILE; k += GROUP) {
        ivec2 p = corner + ivec2(k % TILE, k / TILE);
        depth = max(depth, all(lessThan(p, size)) ? pixel_depth(p) : 0.0);
    }
    atomicMax(farthest, floatBitsToUint(max(depth, 0.0)));
    barrier();
    if (me == 0u) {
        uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
        tile_bins[tile].body_far = uintBitsToFloat(farthest);
        tile_bins[tile].count = 0u;
        tile_bins[tile].offset = 0u;
        tile_bins[tile].kept = 0u;
        tile_bins[tile].cursor = 0u;
        tile_bins[tile].near_lo = 0x7f800000u; // +infinity: no key yet
        tile_bins[tile].near_hi = 0u;
        tile_bins[tile].lead = 0u;
        tile_bins[tile].second_cursor = 0u;
    }
}
