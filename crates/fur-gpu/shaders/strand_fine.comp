#version 450
// Strands in compute, pass 5: each pixel of a tile walks the tile's list, takes each
// segment's exact coverage and keeps its NEAREST nearest fragments in depth order, a
// strand's fragments in the pixel merged into one; the rest are blended in an
// order-free tail. The fragments are blended front to back into the hair layer: the
// colour premultiplied by coverage, and the light let through. One workgroup per tile,
// one invocation per pixel, each reading the tile's list (the same addresses across
// the workgroup). The twin: render::strand_raster (rasterize, blend::PixelList).
//
// Every loop but the walk is unrolled, and the walk takes UNROLL entries a turn:
// lavapipe ends any invocation whose loops have turned 65,535 times in all (Mesa's
// gallivm loop limiter), which a pixel of a dense tile would otherwise reach.
// TILE, NEAREST, DEPTH_SAMPLES are defined by the renderer.
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "strand_raster.glsl"

layout(local_size_x = TILE, local_size_y = TILE) in;

#if DEPTH_SAMPLES > 1
layout(set = SET_RASTER, binding = B_BODY_DEPTH) uniform sampler2DMS body_depth;
#else
layout(set = SET_RASTER, binding = B_BODY_DEPTH) uniform sampler2D body_depth;
#endif

// Entries of the list a turn of the walk takes.
const uint UNROLL = 16u;

float k_depth[NEAREST];
uint k_strand[NEAREST];
float k_alpha[NEAREST];
vec3 k_color[NEAREST];
uint k_count = 0u;
vec3 tail_weighted = vec3(0.0);
float tail_alpha_sum = 0.0;
float tail_transparency = 1.0;
uint tail_count = 0u;

// Whether (d, s) comes before (e, t): nearer, or as near with a smaller strand.
bool nearer(float d, uint s, float e, uint t) {
    return d < e || (d == e && s < t);
}

void into_tail(float alpha, vec3 color) {
    tail_weighted += color * alpha;
    tail_alpha_sum += alpha;
    tail_transparency *= 1.0 - alpha;
    tail_count += 1u;
}

// blend::PixelList::add.
void add_fragment(float depth, uint strand, float alpha, vec3 color) {
    int same = -1;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        if (i < k_count && k_strand[i] == strand) {
            same = int(i);
        }
    }
    if (same >= 0) {
        uint at = uint(same);
        float total = k_alpha[at] + alpha;
        vec3 merged_color = (k_color[at] * k_alpha[at] + color * alpha) / total;
        float merged_depth = min(k_depth[at], depth);
        // Only its depth fell: move it nearer past the ones now behind it.
        uint to = at;
        bool moving = true;
        [[unroll]] for (int j = int(NEAREST) - 1; j >= 1; --j) {
            if (uint(j) <= at && moving) {
                if (nearer(merged_depth, strand, k_depth[j - 1], k_strand[j - 1])) {
                    k_depth[j] = k_depth[j - 1];
                    k_strand[j] = k_strand[j - 1];
                    k_alpha[j] = k_alpha[j - 1];
                    k_color[j] = k_color[j - 1];
                    to = uint(j - 1);
                } else {
                    moving = false;
                }
            }
        }
        k_depth[to] = merged_depth;
        k_strand[to] = strand;
        k_alpha[to] = min(total, 1.0);
        k_color[to] = merged_color;
        return;
    }
    // The list is sorted: the fragment goes after every one nearer than it.
    uint at = 0u;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        if (i < k_count && nearer(k_depth[i], k_strand[i], depth, strand)) {
            at += 1u;
        }
    }
    if (at >= NEAREST) {
        into_tail(alpha, color);
        return;
    }
    if (k_count == NEAREST) {
        into_tail(k_alpha[NEAREST - 1u], k_color[NEAREST - 1u]);
        k_count -= 1u;
    }
    [[unroll]] for (int j = int(NEAREST) - 1; j >= 1; --j) {
        if (uint(j) <= k_count && uint(j) > at) {
            k_depth[j] = k_depth[j - 1];
            k_strand[j] = k_strand[j - 1];
            k_alpha[j] = k_alpha[j - 1];
            k_color[j] = k_color[j - 1];
        }
    }
    k_depth[at] = depth;
    k_strand[at] = strand;
    k_alpha[at] = alpha;
    k_color[at] = color;
    k_count += 1u;
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
    vec3 color = vec3(0.0);
    float transmit = 1.0;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        if (i < k_count) {
            color += transmit * k_alpha[i] * k_color[i];
            transmit *= 1.0 - k_alpha[i];
        }
    }
    if (tail_alpha_sum > 0.0) {
        color += transmit * (1.0 - tail_transparency) * tail_weighted / tail_alpha_sum;
        transmit *= tail_transparency;
    }
    hair_layer[p.y * size.x + p.x] = vec4(color, transmit);
    if (tail_count > 0u) {
        atomicAdd(raster_counts.tail_fragments, tail_count);
    }
}
