#version 450
// Strands in compute, pass 5: each tile's list sorted front to back into DEPTH_BINS
// bins over the range of its segments' sort keys (a counting sort in shared memory;
// within a bin, in any order), written into the second entry pool at the same place.
// Where a bin ends, the fine pass's pixels may end their walk once opaque; they find
// those ends from their entries' bins (strand_fine.comp), and so does the capture the
// tests hold to the twin's (raster_capture.rs). One workgroup per tile that lists
// something (listed_tile). The twin: render::strand_raster::order (sort_by_depth).
// Each entry is written with the mask of the tile's blocks its segment can reach; then
// each whole run of ROW_RUN entries has its masks turned into the blocks' rows (a bit an
// entry: strand_raster.glsl), which the fine pass's pixels search by, ROW_RUN entries a
// read.
// TILE, DEPTH_BINS and ROW_RUN are defined by the renderer.
#extension GL_EXT_control_flow_attributes : require
#define ORDER_COHERENT
#include "common.glsl"
#include "strand_raster.glsl"

// The workgroup: an invocation a pixel of the tile, or on a CPU driver one SIMD
// vector (compute_raster.rs, tile_group), each invocation taking every GROUP-th entry.
const uint GROUP = TILE_GROUP;

layout(local_size_x = GROUP) in;

// Per bin: its count, then where its next entry goes.
shared uint cursor[DEPTH_BINS];

// The entries the workgroup turns into rows at a time (whole runs), and each
// invocation's share of them.
const uint BATCH = GROUP < ROW_RUN ? ROW_RUN : GROUP;
const uint PER_LANE = BATCH / GROUP;

// The blocks of the tile whose corner is `corner` (pixels) that the segment a–b, its
// box widened by half its larger width `half_w` on either side, meets: a bit per block
// (mask_bit), tested along the four axes that separate a rectangle from one it does not
// meet (the segment's axis, across it, x and y). Where a block's bit is clear, the
// footprint of every pixel in it is 0 (strand_footprint).
uint block_mask(vec2 corner, vec2 a, vec2 b, float half_w) {
    vec2 d = b - a;
    float len = length(d);
    if (isnan(len) || len < 1e-3) {
        return 0u;
    }
    vec2 u = d / len;
    vec2 n = vec2(-u.y, u.x);
    const vec2 half_block = 0.5 * vec2(BLOCK_X, BLOCK_Y);
    // The block's half-extent along the axis and across it; the box's along x and y.
    float along_reach = dot(half_block, abs(u));
    float across_reach = dot(half_block, abs(n));
    vec2 widen = half_w * abs(n) + half_block;
    vec2 lo = min(a, b) - widen;
    vec2 hi = max(a, b) + widen;
    uint mask = 0u;
    [[unroll]] for (uint by = 0u; by < MASK_Y; ++by) {
        [[unroll]] for (uint bx = 0u; bx < MASK_X; ++bx) {
            vec2 centre = corner + (vec2(bx, by) + 0.5) * vec2(BLOCK_X, BLOCK_Y);
            vec2 q = centre - a;
            float s = dot(q, u);
            float across = dot(q, n);
            bool meets = abs(across) < half_w + across_reach && s > -along_reach
                && s < len + along_reach && all(lessThan(lo, centre))
                && all(greaterThan(hi, centre));
            mask |= meets ? 1u << (by * MASK_X + bx) : 0u;
        }
    }
    return mask;
}

// The place in its tile's list of the i-th entry the scatter wrote, whose first part
// (`first_part` written) starts the list and whose second starts at `lead`.
uint written(uint i, uint first_part, uint lead) {
    return i < first_part ? i : lead + (i - first_part);
}

// The bin of the segment entry `at` of the pool lists.
uint bin_of(uint at, float lo, float scale) {
    uvec2 segment = strand_segment(listed_entry(at));
    float a = vertex_position(segment.x).z;
    float b = vertex_position(segment.x + 1u).z;
    return depth_bin(depth_key(a, b), lo, scale);
}

void main() {
    uint tile;
    uvec2 at;
    if (!listed_tile(tile, at)) {
        return;
    }
    uint lane = gl_LocalInvocationIndex;
    // The entries the scatter wrote: the first `kept` slots, unless one of its
    // invocations stopped at lavapipe's loop limit (strand_bin.comp) before taking
    // some; those are counted lost and the sorted list ends where the written ones do.
    // On a CPU driver the list is in two parts, the first half of the segments' from
    // its start and the second half's from `lead`, and each part may end early.
    uint kept = tile_bins[tile].kept;
#if SERIAL_SCATTER
    uint lead = min(tile_bins[tile].lead, kept);
    uint first_part = min(tile_bins[tile].cursor, lead);
    uint count = first_part + min(tile_bins[tile].second_cursor, kept - lead);
#else
    uint lead = kept;
    uint first_part = min(tile_bins[tile].cursor, kept);
    uint count = first_part;
#endif
    uint offset = tile_bins[tile].offset;
    barrier();
    if (lane == 0u && count < kept) {
        tile_bins[tile].kept = count;
        atomicAdd(raster_counts.entries_lost, kept - count);
        atomicAdd(raster_counts.entries, 0u - (kept - count));
    }
    // An empty tile has nothing to sort.
    if (count == 0u) {
        return;
    }
    float lo = uintBitsToFloat(tile_bins[tile].near_lo);
    float scale = bin_scale(lo, uintBitsToFloat(tile_bins[tile].near_hi));
    for (uint b = lane; b < DEPTH_BINS; b += GROUP) {
        cursor[b] = 0u;
    }
    barrier();
    for (uint i = lane; i < count; i += GROUP) {
        atomicAdd(cursor[bin_of(offset + written(i, first_part, lead), lo, scale)], 1u);
    }
    barrier();
    // Each bin's count becomes where its entries start.
    if (lane == 0u) {
        uint end = 0u;
        for (uint b = 0u; b < DEPTH_BINS; ++b) {
            uint n = cursor[b];
            cursor[b] = end;
            end += n;
        }
    }
    barrier();
    vec2 corner = vec2(at * TILE);
    for (uint i = lane; i < count; i += GROUP) {
        uint s = listed_entry(offset + written(i, first_part, lead));
        uvec2 segment = strand_segment(s);
        vec4 a = vertex_position(segment.x);
        vec4 b = vertex_position(segment.x + 1u);
        uint slot = atomicAdd(cursor[depth_bin(depth_key(a.z, b.z), lo, scale)], 1u);
        uint mask = block_mask(corner, a.xy, b.xy, 0.5 * max(a.w, b.w));
        imageStore(tile_order, int(offset + slot), uvec4(s, mask, 0u, 0u));
    }
    // The whole runs' masks turned into rows, a batch at a time: each invocation builds
    // its words of the batch (the word at a run's place b: block b's row) from the
    // run's masks, read from the pool, and writes them in place once every invocation
    // has read its own (shared memory and its atomics cost a CPU driver a turn per
    // invocation; a texel read is one gather). The run left over keeps its masks.
    memoryBarrierImage();
    barrier();
    uint whole = count / ROW_RUN * ROW_RUN;
    for (uint base = 0u; base < whole; base += BATCH) {
        // An invocation's places in the batch all lie in one run (a batch is one run
        // when the workgroup is at most a run, and an invocation has one place when it
        // is more), whose masks it reads once.
        uint run = (base + lane) / ROW_RUN * ROW_RUN;
        uint masks[ROW_RUN];
        [[unroll]] for (uint j = 0u; j < ROW_RUN; ++j) {
            masks[j] = run < whole ? imageLoad(tile_order, int(offset + run + j)).y : 0u;
        }
        uint segments[PER_LANE];
        uint rows[PER_LANE];
        [[unroll]] for (uint k = 0u; k < PER_LANE; ++k) {
            uint place = base + lane + k * GROUP;
            uint block = place - run;
            uint row = 0u;
            if (place < whole) {
                segments[k] = imageLoad(tile_order, int(offset + place)).x;
                [[unroll]] for (uint j = 0u; j < ROW_RUN; ++j) {
                    row |= ((masks[j] >> block) & 1u) << j;
                }
            }
            rows[k] = row;
        }
        memoryBarrierImage();
        barrier();
        [[unroll]] for (uint k = 0u; k < PER_LANE; ++k) {
            uint place = base + lane + k * GROUP;
            if (place < whole) {
                imageStore(tile_order, int(offset + place), uvec4(segments[k], rows[k], 0u, 0u));
            }
        }
        // No barrier here: the next batch reads only its own entries, which no
        // invocation has written yet.
    }
}
