#version 450
// Strands in compute, pass 3: where each tile's list starts in the entry pool (the
// counts before it summed) and how many entries it keeps: all, unless the pool runs
// out, and then what is left, the rest counted as lost; and the list of the tiles that
// list something, which the sort and fine passes are dispatched over (listed_tile).
// One workgroup; each invocation sums a run of tiles, the runs' sums are scanned in
// shared memory.
#include "common.glsl"
#include "strand_raster.glsl"

layout(local_size_x = GROUP_SIZE) in;

shared uint sums[GROUP_SIZE];

// a + b, held at the largest uint rather than wrapping.
uint sat_add(uint a, uint b) {
    uint c = a + b;
    return c < a ? 0xffffffffu : c;
}

void main() {
    uint tiles = uint(tile_bins.length());
    uint capacity = uint(imageSize(tile_entries));
    uint me = gl_LocalInvocationIndex;
    uint run = (tiles + GROUP_SIZE - 1u) / GROUP_SIZE;
    uint first = min(me * run, tiles);
    uint last = min(first + run, tiles);
    uint sum = 0u;
    for (uint t = first; t < last; ++t) {
        sum = sat_add(sum, tile_bins[t].count);
    }
    sums[me] = sum;
    barrier();
    // Inclusive scan (Hillis–Steele) of the runs' sums.
    for (uint step = 1u; step < GROUP_SIZE; step *= 2u) {
        uint add = me >= step ? sums[me - step] : 0u;
        barrier();
        sums[me] = sat_add(sums[me], add);
        barrier();
    }
    uint offset = sums[me] == 0xffffffffu ? 0xffffffffu : sums[me] - sum;
    uint kept_total = 0u;
    uint lost_total = 0u;
    uint listed = 0u;
    for (uint t = first; t < last; ++t) {
        uint count = tile_bins[t].count;
        uint room = offset < capacity ? capacity - offset : 0u;
        uint kept = min(count, room);
        tile_bins[t].offset = min(offset, capacity);
        tile_bins[t].kept = kept;
        kept_total += kept;
        lost_total += count - kept;
        listed += kept > 0u ? 1u : 0u;
        offset = sat_add(offset, count);
    }
    atomicAdd(raster_counts.entries, kept_total);
    atomicAdd(raster_counts.entries_lost, lost_total);
    // The run's tiles that list something, in places of the list it takes at once
    // (each tile is drawn on its own, so the runs' order in the list is free).
    uint at = atomicAdd(raster_counts.listed_tiles, listed);
    for (uint t = first; t < last; ++t) {
        if (tile_bins[t].kept > 0u) {
            tile_bins[at].listed = t;
            at += 1u;
        }
    }
    memoryBarrierBuffer();
    barrier();
    if (me == 0u) {
        uint n = atomicAdd(raster_counts.listed_tiles, 0u);
        raster_counts.listed_groups = min(n, LISTED_ROW);
        raster_counts.listed_groups_y = (n + LISTED_ROW - 1u) / LISTED_ROW;
    }
}
