#version 450
// Strands in compute, pass 6: each pixel of a tile walks the tile's list, sorted front
// to back by depth bin, takes each segment's exact coverage and keeps its NEAREST
// nearest fragments in depth order, a strand's fragments in the pixel merged into one;
// the rest are blended behind them as they come (strand_fine_list.glsl). At each of the
// tile's stops (where a depth bin ends) a pixel whose fragments let through less than
// OPAQUE_TRANSMIT stops. The fragments are blended front to back into the hair layer:
// the colour premultiplied by coverage, and the light let through. One workgroup per
// tile that lists something (listed_tile: the layer of a tile that lists nothing is left
// as it is, and the composite pass takes the target alone there), one invocation per
// pixel. The twin: render::strand_raster (draw,
// blend::PixelList), which takes the entries in the same order.
//
// Each pixel walks the list itself, with no barriers and no shared memory: where the
// invocations of a vector (a GPU's warp, a CPU driver's SIMD lanes) part ways in an
// `if`, all of them pay for both sides, and only a loop ends when none of them is left
// in it. So each pixel first searches the list for the next entry whose segment can
// reach it, and takes only that one: the dear part of a turn (the exact coverage and
// the sorted insertion) is paid once a fragment, not once an entry of the tile. The
// search reads its block's row (strand_sort.comp): one read skips ROW_RUN entries that
// cannot reach it. (A form that fetched the list a batch at a time into shared memory
// for every pixel to take whole was up to 3.5× slower on an NVIDIA H200 (the blob's
// frame) and several times slower on lavapipe: docs/compute-raster.md.)
//
// Every loop but the walk is unrolled: lavapipe ends any invocation whose loops have
// turned 65,535 times in all (Mesa's gallivm loop limiter), which a pixel of a dense
// tile could otherwise reach; so the walk counts its turns, and a pixel that would
// pass MAX_TURNS stops there, counted as stopped (it has met thousands of fragments,
// or searched a list of over a million entries).
// TILE, NEAREST, DEPTH_SAMPLES, DEPTH_BINS, ROW_RUN and OPAQUE_TRANSMIT are defined
// by the renderer.
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "strand_raster.glsl"
#include "strand_fine_list.glsl"

layout(local_size_x = TILE, local_size_y = TILE) in;

#if DEPTH_SAMPLES > 1
layout(set = SET_RASTER, binding = B_BODY_DEPTH) uniform sampler2DMS body_depth;
#else
layout(set = SET_RASTER, binding = B_BODY_DEPTH) uniform sampler2D body_depth;
#endif

// The most turns the walk's loops take in all, under lavapipe's 65,535 (a
// test lowers it).
#ifdef FUR_TEST_MAX_TURNS
const uint MAX_TURNS = FUR_TEST_MAX_TURNS;
#else
const uint MAX_TURNS = 60000u;
#endif

// Each pixel's counts are added this many times over (a test raises it to carry the
// frame's counts past 2^32).
#ifdef FUR_TEST_FRAGMENT_SCALE
const uint FRAGMENT_SCALE = FUR_TEST_FRAGMENT_SCALE;
#else
const uint FRAGMENT_SCALE = 1u;
#endif

// Adds n to the 64-bit count of words LOW and HIGH: an add that wraps the low word past
// 2^32 carries one into the high word. (A macro: a function cannot take a buffer's
// member for an atomic.)
#define ADD_WIDE(LOW, HIGH, n)                              \
    {                                                       \
        uint added = (n);                                   \
        uint before = atomicAdd(LOW, added);                \
        if (before + added < before) {                      \
            atomicAdd(HIGH, 1u);                            \
        }                                                   \
    }

// The pixel's list blended into the hair layer, and its fragments counted.
void finish(ivec2 p, ivec2 size) {
    hair_layer[p.y * size.x + p.x] = resolve_list();
    if (tail_count > 0u) {
        ADD_WIDE(raster_counts.tail_fragments, raster_counts.tail_fragments_high,
                 tail_count * FRAGMENT_SCALE)
    }
    if (fragment_count > 0u) {
        ADD_WIDE(raster_counts.fragments, raster_counts.fragments_high,
                 fragment_count * FRAGMENT_SCALE)
    }
}

float pixel_depth(ivec2 p) {
#if DEPTH_SAMPLES > 1
    float d = 0.0;
    [[unroll]] for (int i = 0; i < DEPTH_SAMPLES; ++i) {
        d = max(d, texelFetch(body_depth, p, i).r);
    }
    return d;
#else
    return texelFetch(body_depth, p, 0).r;
#endif
}

// The fragment the segment of strand `strand` from `va` to `vb` leaves in the pixel
// centred at `centre`, if it is in front of the body there. Its colour is held to
// [0, 1] first, as the fixed-function rasteriser's 8-bit target holds each sample's: a
// highlight brighter than white covers its share of the pixel with white.
void take_segment(uint strand, StrandVertex va, StrandVertex vb, vec2 centre, float body) {
    vec2 foot = strand_footprint(centre, va.position.xy, vb.position.xy, va.position.w,
                                 vb.position.w);
    vec4 c = mix(va.color, vb.color, foot.y);
    float alpha = foot.x * c.a;
    if (alpha > MIN_ALPHA) {
        float depth = mix(va.position.z, vb.position.z, foot.y);
        if (depth < body) {
            add_fragment(depth, strand, min(alpha, 1.0), clamp(c.rgb, 0.0, 1.0));
        }
    }
}

// The pixel of the tile that invocation `i` draws: each run of eight invocations (a
// CPU driver's SIMD vector: lavapipe's eight lanes) a block of 4×2 pixels, whose lanes
// share blocks of the masks and so walk nearly the same entries, where a row of eight
// would each walk their own (a vector walks until its last lane is done). A GPU's
// warp of 32 takes the same pixels either way: four rows of an 8×8 tile.
uvec2 pixel_in_tile(uint i) {
#if TILE >= 4
    uint vector = i / 8u;
    uint lane = i % 8u;
    uint across = TILE / 4u;
    return uvec2(vector % across * 4u + lane % 4u, vector / across * 2u + lane / 4u);
#else
    return uvec2(i % TILE, i / TILE);
#endif
}

void main() {
    uint tile;
    uvec2 at;
    if (!listed_tile(tile, at)) {
        return;
    }
    uvec2 local = pixel_in_tile(gl_LocalInvocationIndex);
    ivec2 p = ivec2(at * TILE + local);
    ivec2 size = ivec2(frame.camera.viewport);
    if (any(greaterThanEqual(p, size))) {
        return;
    }
    uint count = tile_bins[tile].kept;
    // The sort cut the list to nothing (the scatter stopped early): left as it is too.
    if (count == 0u) {
        return;
    }
    float body = pixel_depth(p);
    vec2 centre = vec2(p) + 0.5;
    uint offset = tile_bins[tile].offset;
    uint bit = mask_bit(local);
    // The tile's depth bins, as the sort cut them (bin_of in strand_sort.comp). The list
    // holds them in order, so where the entry a pixel finds next lies in a later bin than
    // the last it took, a bin has ended between them: an opaque pixel stops there (the
    // tile's stops, found from its entries: no table of them is kept, whose read in
    // the loop a CPU driver would make invocation by invocation).
    float lo = uintBitsToFloat(tile_bins[tile].near_lo);
    float scale = bin_scale(lo, uintBitsToFloat(tile_bins[tile].near_hi));
    uint bin = 0u;
    bool done = false;
    uint i = 0u;
    // The loops' turns, held under lavapipe's limit (MAX_TURNS).
    uint turns = 0u;
    while (i < count && !done) {
        // The next entry that can reach the pixel: the rest leave nothing in it.
        bool found = false;
        while (!found && i < count) {
            turns += 1u;
            // In a whole run, the pixel's block's row from entry i on; past the whole
            // runs, entry i's own mask, the pixel's bit of it. One read either way.
            uint run = i / ROW_RUN * ROW_RUN;
            bool in_rows = run + ROW_RUN <= count;
            uint word = imageLoad(tile_order, int(offset + (in_rows ? run + bit : i))).y;
            uint reach = in_rows ? word >> (i - run) : (word >> bit) & 1u;
            if (reach != 0u) {
                i += uint(findLSB(reach));
                found = true;
            } else {
                i = in_rows ? run + ROW_RUN : i + 1u;
            }
        }
        if (!found) {
            break;
        }
        turns += 1u;
        if (turns > MAX_TURNS) {
            done = true;
            break;
        }
        uvec2 segment = strand_segment(imageLoad(tile_order, int(offset + i)).x);
        StrandVertex va = strand_vertex(segment.x);
        StrandVertex vb = strand_vertex(segment.x + 1u);
        uint entry_bin = depth_bin(depth_key(va.position.z, vb.position.z), lo, scale);
        if (entry_bin > bin && seen_transmit < OPAQUE_TRANSMIT) {
            done = true;
        } else {
            bin = entry_bin;
            take_segment(segment.y, va, vb, centre, body);
            i += 1u;
        }
    }
    // Counted once the walk is over (an atomic in the loop is paid on every turn).
    if (done) {
        atomicAdd(raster_counts.pixels_stopped, 1u);
    }
    finish(p, size);
}
