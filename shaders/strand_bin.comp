#version 450
// Strands in compute, passes 2 and 4: each segment walks the tiles it can touch (the
// rows its widened axis crosses, in each the columns of the part of the axis inside
// it; render::strand_raster::bin::tiles_touched) and, in a tile the body does not hide
// it from, is counted and its sort key taken into the tile's range (SCATTER 0) or
// written into the tile's list (SCATTER 1). One
// invocation per segment (or every so-many-th), dispatched indirectly by the count the
// geometry stage left.
// On a CPU driver (SERIAL_SCATTER) the scatter is two workgroups, one for each half of
// the segments, and each tile's list is in two parts: the first half's entries from
// its start, the second half's after them (the count pass counts the first half's
// entries into the tile's `lead`). A workgroup's invocations run in one fixed order on
// one thread, and no two workgroups append to one part, so each tile lists its segments
// in the same order every frame and every run, and the image is the same bytes
// (workgroups that share a list append to it in whatever order their threads reach
// it, and the order within a depth bin decides how a pixel's tail blends). Each
// segment is read once. (Cut into bands of tile rows instead, each workgroup read
// every segment, and the scatter cost about a quarter more: docs/compute-raster.md.)
// Its invocations each take every 1024th segment of their half and count their
// loops' turns: one that would pass lavapipe's limit (MAX_TURNS) stops, and the sort
// pass counts the entries it left unwritten as lost (they never took a slot).
// TILE, SCATTER, SERIAL_SCATTER and SCATTER_GROUPS are defined by the renderer.
#include "common.glsl"
#include "strand_raster.glsl"

#if SERIAL_SCATTER && SCATTER_GROUPS != 2
#error "a CPU driver's scatter is two workgroups, one for each half of the segments"
#endif

#if SCATTER && SERIAL_SCATTER
layout(local_size_x = 1024) in;
#else
layout(local_size_x = GROUP_SIZE) in;
#endif

// The loops' turns, held under lavapipe's 65,535 (the banded scatter's
// invocations each walk a share of the segments; a test lowers it).
#ifdef FUR_TEST_BIN_TURNS
const uint MAX_TURNS = FUR_TEST_BIN_TURNS;
#else
const uint MAX_TURNS = 60000u;
#endif
uint turns = 0u;
// The first of the second half's segments (SERIAL_SCATTER).
uint second_half = 0u;

void bin_segment(uint s) {
    uvec2 segment = strand_segment(s);
    if (segment.x == NO_SEGMENT) {
        return;
    }
    vec4 a = vertex_position(segment.x);
    vec4 b = vertex_position(segment.x + 1u);
    float radius = 0.5 * max(a.w, b.w) + 0.70710678;
    float near = min(a.z, b.z);
#if !SCATTER
    // Non-negative floats order as their bits do.
    uint key = floatBitsToUint(depth_key(a.z, b.z));
#endif
    float size = float(TILE);
    uint columns = (uint(frame.camera.viewport.x) + TILE - 1u) / TILE;
    uint rows = (uint(frame.camera.viewport.y) + TILE - 1u) / TILE;
    float y_lo = min(a.y, b.y) - radius;
    float y_hi = max(a.y, b.y) + radius;
    if (isnan(y_lo) || isinf(y_lo) || isnan(y_hi) || isinf(y_hi) || isnan(a.x) || isinf(a.x)
        || isnan(b.x) || isinf(b.x)) {
        return;
    }
    float first_row = max(floor(y_lo / size), 0.0);
    float last_row = min(floor(y_hi / size), float(rows) - 1.0);
    if (first_row > last_row) {
        return;
    }
    for (uint row = uint(first_row); row <= uint(last_row); ++row) {
        turns += 1u;
        float lo = float(row) * size - radius;
        float hi = float(row + 1u) * size + radius;
        float x0;
        float x1;
        float dy = b.y - a.y;
        if (abs(dy) < 1e-6) {
            x0 = min(a.x, b.x);
            x1 = max(a.x, b.x);
        } else {
            float p = a.x + (b.x - a.x) * clamp((lo - a.y) / dy, 0.0, 1.0);
            float q = a.x + (b.x - a.x) * clamp((hi - a.y) / dy, 0.0, 1.0);
            x0 = min(p, q);
            x1 = max(p, q);
        }
        float first_col = max(floor((x0 - radius) / size), 0.0);
        float last_col = min(floor((x1 + radius) / size), float(columns) - 1.0);
        if (first_col > last_col) {
            continue;
        }
        for (uint column = uint(first_col); column <= uint(last_col); ++column) {
            turns += 1u;
#if SCATTER
            // (The count pass walks every pair: what the scatter leaves unwritten is
            // counted against it.)
            if (turns > MAX_TURNS) {
                return;
            }
#endif
            uint tile = row * columns + column;
            if (near >= tile_bins[tile].body_far) {
                continue;
            }
#if SCATTER && SERIAL_SCATTER
            // This half's part of the tile's list.
            uint slot = s < second_half
                ? atomicAdd(tile_bins[tile].cursor, 1u)
                : tile_bins[tile].lead + atomicAdd(tile_bins[tile].second_cursor, 1u);
#elif SCATTER
            uint slot = atomicAdd(tile_bins[tile].cursor, 1u);
#endif
#if SCATTER
            if (slot < tile_bins[tile].kept) {
                imageStore(tile_entries, int(tile_bins[tile].offset + slot), uvec4(s));
            }
#else
            atomicAdd(tile_bins[tile].count, 1u);
#if SERIAL_SCATTER
            if (s < second_half) {
                atomicAdd(tile_bins[tile].lead, 1u);
            }
#endif
            atomicMin(tile_bins[tile].near_lo, key);
            atomicMax(tile_bins[tile].near_hi, key);
#endif
        }
    }
}

void main() {
    uint segments = min(raster_counts.segments, segment_room());
    second_half = (segments + 1u) / 2u;
#if SCATTER && SERIAL_SCATTER
    // This workgroup's half of the segments.
    uint first = gl_WorkGroupID.x * second_half + gl_LocalInvocationID.x;
    uint end = min((gl_WorkGroupID.x + 1u) * second_half, segments);
    uint stride = gl_WorkGroupSize.x;
#else
    uint first = gl_GlobalInvocationID.x;
    uint end = segments;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
#endif
    for (uint s = first; s < end && (SCATTER == 0 || turns <= MAX_TURNS); s += stride) {
        turns += 1u;
        bin_segment(s);
    }
}
