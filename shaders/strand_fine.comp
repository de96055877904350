#version 450
// Strands in compute, pass 6: each pixel of a tile walks the tile's list, sorted front
// to back by depth bin, takes each segment's exact coverage and keeps its NEAREST
// nearest fragments in depth order, a strand's fragments in the pixel merged into one;
// the rest are blended in an order-free tail (strand_fine_list.glsl). At each of the
// tile's stops (where a depth bin ends) a pixel whose fragments let through less than
// OPAQUE_TRANSMIT stops; in the batched form the tile stops once every pixel has. The
// fragments are blended front to back into the hair layer: the colour premultiplied by
// coverage, and the light let through. One workgroup per tile, one invocation per
// pixel. The twin: render::strand_raster (draw, blend::PixelList), which takes the
// entries in the same order.
//
// Two forms, each the faster measured on its kind of device (docs/compute-raster.md):
// - BATCHED (GPUs): the workgroup walks the tile's list a batch at a time: each
//   invocation fetches one entry's segment and its two vertices (two dependent reads)
//   into shared memory, and every pixel then takes the whole batch from there;
// - not (CPU drivers): each pixel walks the list itself, with no barriers, which a CPU
//   driver runs slowly. A CPU driver runs a vector of invocations through every branch
//   of an `if` (only a loop ends when none of them is left in it), so each pixel first
//   searches the list, one bit of the entry's mask (strand_sort.comp) an entry, for
//   the next entry whose segment can reach it, and takes only that one: the dear part
//   of a turn (the exact coverage and the sorted insertion) is paid once a fragment,
//   not once an entry of the tile.
//
// Every loop but the walk is unrolled, the batched walk takes UNROLL entries a turn and
// the per-pixel search tests SEARCH_UNROLL: lavapipe ends any invocation whose loops
// have turned 65,535 times in all (Mesa's gallivm loop limiter), which a pixel of a
// dense tile would otherwise reach; the per-pixel form counts its turns, and a pixel
// that would pass MAX_TURNS stops there, counted as stopped (it has met thousands of
// fragments, or searched a list of over a hundred thousand entries).
// TILE, NEAREST, DEPTH_SAMPLES, BATCHED, DEPTH_BINS and OPAQUE_TRANSMIT are defined by
// the renderer.
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

// Entries a turn of the batched form's walk takes, and of the per-pixel form's search
// tests (each of a turn's tests is paid by every pixel of a vector, found or not).
const uint UNROLL = 16u;
const uint SEARCH_UNROLL = 2u;

// The most turns the per-pixel form's loops take in all, under lavapipe's 65,535 (a
// test lowers it).
#ifdef FUR_TEST_MAX_TURNS
const uint MAX_TURNS = FUR_TEST_MAX_TURNS;
#else
const uint MAX_TURNS = 60000u;
#endif

// Where a pixel is in its walk of the tile's list: the next stop (the index where a
// depth bin ends), which of the tile's stops it is, and whether the pixel has stopped.
struct Walk {
    uint stop_at;
    uint next;
    bool done;
};

Walk start_walk(uint tile, uint count) {
    Walk walk;
    walk.next = 0u;
    walk.stop_at = tile_bins[tile].stop_count > 0u ? tile_bins[tile].stops[0] : count;
    walk.done = false;
    return walk;
}

// Whether the pixel stops before entry `i` of the list: at a stop, once opaque (and
// counted). Past a stop it is not at, the walk moves on to the next.
bool stops_at(inout Walk walk, uint tile, uint i) {
    if (i != walk.stop_at) {
        return false;
    }
    if (seen_transmit < OPAQUE_TRANSMIT) {
        walk.done = true;
        atomicAdd(raster_counts.pixels_stopped, 1u);
        return true;
    }
    walk.next += 1u;
    walk.stop_at = walk.next < tile_bins[tile].stop_count ? tile_bins[tile].stops[walk.next]
                                                          : 0xffffffffu;
    return false;
}

// The pixel's list blended into the hair layer, and its tail counted.
void finish(ivec2 p, ivec2 size) {
    hair_layer[p.y * size.x + p.x] = resolve_list();
    if (tail_count > 0u) {
        atomicAdd(raster_counts.tail_fragments, tail_count);
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

#if BATCHED
// The entries of a batch: one per invocation.
const uint BATCH = TILE * TILE;

// The batch: each entry's ends (x, y of both), widths and depths (both ends), colours,
// and strand.
shared vec4 batch_ends[BATCH];
shared vec4 batch_shape[BATCH];
shared vec4 batch_color_a[BATCH];
shared vec4 batch_color_b[BATCH];
shared uint batch_strand[BATCH];
// The tile's pixels still walking (inside the image and not yet stopped).
shared uint open_pixels;

// Fetches entry `entry` of the pool into the batch's slot `slot`.
void fetch(uint entry, uint slot) {
    uvec2 segment = strand_segment(ordered_entry(entry));
    StrandVertex va = strand_vertex(segment.x);
    StrandVertex vb = strand_vertex(segment.x + 1u);
    batch_ends[slot] = vec4(va.position.xy, vb.position.xy);
    batch_shape[slot] = vec4(va.position.w, vb.position.w, va.position.z, vb.position.z);
    batch_color_a[slot] = va.color;
    batch_color_b[slot] = vb.color;
    batch_strand[slot] = segment.y;
}

// The fragment the batch's entry `slot` leaves in the pixel centred at `centre`, if it
// is in front of the body there.
void take(uint slot, vec2 centre, float body) {
    vec4 ends = batch_ends[slot];
    vec4 shape = batch_shape[slot];
    vec2 foot = strand_footprint(centre, ends.xy, ends.zw, shape.x, shape.y);
    if (foot.x <= 0.0) {
        return;
    }
    vec4 c = mix(batch_color_a[slot], batch_color_b[slot], foot.y);
    float alpha = foot.x * c.a;
    if (alpha > MIN_ALPHA) {
        float depth = mix(shape.z, shape.w, foot.y);
        if (depth < body) {
            add_fragment(depth, batch_strand[slot], min(alpha, 1.0), c.rgb);
        }
    }
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(frame.camera.viewport);
    // A pixel past the image's edge helps fetch the batches (every invocation reaches
    // every barrier) and draws nothing.
    bool inside = all(lessThan(p, size));
    float body = inside ? pixel_depth(p) : 0.0;
    vec2 centre = vec2(p) + 0.5;
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint count = tile_bins[tile].kept;
    uint offset = tile_bins[tile].offset;
    uint lane = gl_LocalInvocationIndex;
    if (lane == 0u) {
        ivec2 corner = ivec2(gl_WorkGroupID.xy) * int(TILE);
        ivec2 span = clamp(size - corner, ivec2(0), ivec2(TILE));
        open_pixels = uint(span.x * span.y);
    }
    Walk walk = start_walk(tile, count);
    walk.done = !inside;
    for (uint base = 0u; base < count; base += BATCH) {
        if (base + lane < count) {
            fetch(offset + base + lane, lane);
        }
        barrier();
        uint batch = min(BATCH, count - base);
        if (!walk.done) {
            for (uint first = 0u; first < batch && !walk.done; first += UNROLL) {
                [[unroll]] for (uint j = 0u; j < UNROLL; ++j) {
                    if (first + j < batch && !walk.done) {
                        if (!stops_at(walk, tile, base + first + j)) {
                            take(first + j, centre, body);
                        } else {
                            atomicAdd(open_pixels, 0xffffffffu);
                        }
                    }
                }
            }
        }
        barrier();
        // Every pixel of the tile opaque: the rest of the list cannot show. (Read by
        // all between two barriers, written only after the next.)
        if (open_pixels == 0u) {
            break;
        }
    }
    if (!inside) {
        return;
    }
    finish(p, size);
}
#else
// The fragment segment `s` leaves in the pixel centred at `centre`, if it is in front
// of the body there.
void take_segment(uint s, vec2 centre, float body) {
    uvec2 segment = strand_segment(s);
    StrandVertex va = strand_vertex(segment.x);
    StrandVertex vb = strand_vertex(segment.x + 1u);
    vec2 foot = strand_footprint(centre, va.position.xy, vb.position.xy, va.position.w,
                                 vb.position.w);
    vec4 c = mix(va.color, vb.color, foot.y);
    float alpha = foot.x * c.a;
    if (alpha > MIN_ALPHA) {
        float depth = mix(va.position.z, vb.position.z, foot.y);
        if (depth < body) {
            add_fragment(depth, segment.y, min(alpha, 1.0), c.rgb);
        }
    }
}

// The segment of entry `entry` if it can leave a fragment in the pixel of the tile
// whose bit of the entry's mask is `bit`, NO_SEGMENT if not: whether its segment's box
// meets the pixel's block (the sort pass's block_mask); where it does not, the
// footprint's area is 0, so `take` would keep nothing.
uint reaching(uint entry, uint bit) {
    uvec2 e = imageLoad(tile_order, int(entry)).xy;
    return ((e.y >> bit) & 1u) != 0u ? e.x : NO_SEGMENT;
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(frame.camera.viewport);
    if (any(greaterThanEqual(p, size))) {
        return;
    }
    float body = pixel_depth(p);
    vec2 centre = vec2(p) + 0.5;
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint count = tile_bins[tile].kept;
    uint offset = tile_bins[tile].offset;
    uint bit = mask_bit(gl_LocalInvocationID.xy);
    uint stop_count = tile_bins[tile].stop_count;
    Walk walk = start_walk(tile, count);
    uint i = 0u;
    // The loops' turns, held under lavapipe's limit (MAX_TURNS).
    uint turns = 0u;
    while (i < count && !walk.done) {
        // The next entry that can reach the pixel: the rest leave nothing in it.
        bool found = false;
        uint segment = NO_SEGMENT;
        while (!found && i < count) {
            turns += 1u;
            [[unroll]] for (uint j = 0u; j < SEARCH_UNROLL; ++j) {
                if (!found && i < count) {
                    segment = reaching(offset + i, bit);
                    if (segment != NO_SEGMENT) {
                        found = true;
                    } else {
                        i += 1u;
                    }
                }
            }
        }
        if (!found) {
            break;
        }
        turns += 1u;
        if (turns > MAX_TURNS) {
            walk.done = true;
            break;
        }
        // The stops passed since the last entry taken: the pixel has met nothing since.
        while (walk.stop_at <= i && !walk.done) {
            turns += 1u;
            if (seen_transmit < OPAQUE_TRANSMIT) {
                walk.done = true;
            } else {
                walk.next += 1u;
                walk.stop_at = walk.next < stop_count ? tile_bins[tile].stops[walk.next]
                                                      : 0xffffffffu;
            }
        }
        if (!walk.done) {
            take_segment(segment, centre, body);
            i += 1u;
        }
    }
    // Counted once the walk is over (an atomic in the loop is paid on every turn).
    if (walk.done) {
        atomicAdd(raster_counts.pixels_stopped, 1u);
    }
    finish(p, size);
}
#endif
