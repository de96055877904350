#version 450
// Strands in compute, pass 5: each tile's list sorted front to back into DEPTH_BINS
// bins over the range of its segments' sort keys (a counting sort in shared memory;
// within a bin, in any order), written into the second entry pool at the same place,
// with the end of each bin that holds an entry: the stops where the fine pass's
// pixels may end their walk once opaque. One workgroup per tile. The twin:
// render::strand_raster::order (sort_by_depth).
// TILE, DEPTH_BINS are defined by the renderer.
#include "common.glsl"
#include "strand_raster.glsl"

const uint GROUP = TILE * TILE;

layout(local_size_x = GROUP) in;

// Per bin: its count, then where its next entry goes.
shared uint cursor[DEPTH_BINS];

// The bin of the segment entry `at` of the pool lists.
uint bin_of(uint at, float lo, float scale) {
    uvec2 segment = strand_segment(listed_entry(at));
    float a = vertex_position(segment.x).z;
    float b = vertex_position(segment.x + 1u).z;
    return depth_bin(depth_key(a, b), lo, scale);
}

void main() {
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint lane = gl_LocalInvocationIndex;
    uint count = tile_bins[tile].kept;
    uint offset = tile_bins[tile].offset;
    float lo = uintBitsToFloat(tile_bins[tile].near_lo);
    float scale = bin_scale(lo, uintBitsToFloat(tile_bins[tile].near_hi));
    for (uint b = lane; b < DEPTH_BINS; b += GROUP) {
        cursor[b] = 0u;
    }
    barrier();
    for (uint i = lane; i < count; i += GROUP) {
        atomicAdd(cursor[bin_of(offset + i, lo, scale)], 1u);
    }
    barrier();
    if (lane == 0u) {
        uint end = 0u;
        uint stops = 0u;
        for (uint b = 0u; b < DEPTH_BINS; ++b) {
            uint n = cursor[b];
            cursor[b] = end;
            end += n;
            if (n > 0u) {
                tile_bins[tile].stops[stops] = end;
                stops += 1u;
            }
        }
        tile_bins[tile].stop_count = stops;
    }
    barrier();
    for (uint i = lane; i < count; i += GROUP) {
        uint slot = atomicAdd(cursor[bin_of(offset + i, lo, scale)], 1u);
        imageStore(tile_order, int(offset + slot), uvec4(listed_entry(offset + i)));
    }
}
