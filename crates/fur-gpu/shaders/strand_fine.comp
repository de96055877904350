#version 450
// Strands in compute, pass 5: each pixel of a tile walks the tile's list, takes each
// segment's exact coverage and keeps its NEAREST nearest fragments in depth order, a
// strand's fragments in the pixel merged into one; the rest are blended in an
// order-free tail (strand_fine_list.glsl). The fragments are blended front to back
// into the hair layer: the colour premultiplied by coverage, and the light let
// through. One workgroup per tile, one invocation per pixel. The twin:
// render::strand_raster (rasterize, blend::PixelList), which takes the entries in the
// same order.
//
// Two forms, each the faster measured on its kind of device (docs/compute-raster.md):
// - BATCHED (GPUs): the workgroup walks the tile's list a batch at a time: each
//   invocation fetches one entry's segment and its two vertices (two dependent reads)
//   into shared memory, and every pixel then takes the whole batch from there;
// - not (CPU drivers): each pixel reads the list itself (the same addresses across the
//   workgroup), with no barriers, which a CPU driver runs slowly.
//
// Every loop but the walk is unrolled, and the walk takes UNROLL entries a turn:
// lavapipe ends any invocation whose loops have turned 65,535 times in all (Mesa's
// gallivm loop limiter), which a pixel of a dense tile would otherwise reach.
// TILE, NEAREST, DEPTH_SAMPLES and BATCHED are defined by the renderer.
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

// Entries a turn of the walk takes.
const uint UNROLL = 16u;

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

// Fetches entry `entry` of the pool into the batch's slot `slot`.
void fetch(uint entry, uint slot) {
    uvec2 segment = strand_segment_list[tile_entries[entry]];
    StrandVertex va = strand_vertex_list[segment.x];
    StrandVertex vb = strand_vertex_list[segment.x + 1u];
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
    ivec2 size = ivec2(frame.viewport.xy);
    // A pixel past the image's edge helps fetch the batches (every invocation reaches
    // every barrier) and draws nothing.
    bool inside = all(lessThan(p, size));
    float body = inside ? pixel_depth(p) : 0.0;
    vec2 centre = vec2(p) + 0.5;
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint count = tile_bins[tile].kept;
    uint offset = tile_bins[tile].offset;
    uint lane = gl_LocalInvocationIndex;
    for (uint base = 0u; base < count; base += BATCH) {
        if (base + lane < count) {
            fetch(offset + base + lane, lane);
        }
        barrier();
        uint batch = min(BATCH, count - base);
        if (inside) {
            for (uint first = 0u; first < batch; first += UNROLL) {
                [[unroll]] for (uint j = 0u; j < UNROLL; ++j) {
                    if (first + j < batch) {
                        take(first + j, centre, body);
                    }
                }
            }
        }
        barrier();
    }
    if (!inside) {
        return;
    }
    hair_layer[p.y * size.x + p.x] = resolve_list();
    if (tail_count > 0u) {
        atomicAdd(raster_counts.tail_fragments, tail_count);
    }
}
#else
// The fragment entry `entry` of the pool leaves in the pixel centred at `centre`, if
// it is in front of the body there.
void take(uint entry, vec2 centre, float body) {
    uvec2 segment = strand_segment_list[tile_entries[entry]];
    StrandVertex va = strand_vertex_list[segment.x];
    StrandVertex vb = strand_vertex_list[segment.x + 1u];
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

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(frame.viewport.xy);
    if (any(greaterThanEqual(p, size))) {
        return;
    }
    float body = pixel_depth(p);
    vec2 centre = vec2(p) + 0.5;
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint count = tile_bins[tile].kept;
    uint offset = tile_bins[tile].offset;
    for (uint base = 0u; base < count; base += UNROLL) {
        [[unroll]] for (uint j = 0u; j < UNROLL; ++j) {
            if (base + j < count) {
                take(offset + base + j, centre, body);
            }
        }
    }
    hair_layer[p.y * size.x + p.x] = resolve_list();
    if (tail_count > 0u) {
        atomicAdd(raster_counts.tail_fragments, tail_count);
    }
}
#endif
