// Strands drawn in compute: the buffers the fur pass's geometry stage writes its
// strands into and the compute passes bin, draw and composite them from, and the
// exact coverage of a pixel by a segment. The CPU twin is
// crates/fur-core/src/render/strand_raster/ (coverage.rs, blend.rs): the same
// arithmetic, step by step, which the tests compare.
#ifndef STRAND_RASTER_GLSL
#define STRAND_RASTER_GLSL

#ifndef B_RASTER_COUNTS
#error "raster shaders are compiled with binding_defines() (crates/fur-gpu/src/render/bindings.rs)"
#endif

// One end of a segment on the screen: pixels, the depth the mesh pass's depth
// buffer holds (NDC z), width in pixels; its lit colour (linear) and opacity.
struct StrandVertex {
    vec4 position;      // x, y (pixels), depth, width (pixels)
    vec4 color;         // rgb, alpha (before the lighting pass under the Marschner
                        // model: pack_shading's words, as floats' bits)
};

// What the passes counted, and the bin pass's indirect dispatch. The host reads it
// after the frame (`CountWords` in crates/fur-gpu/src/render/renderer/strand_counts_reset.rs).
layout(set = SET_RASTER, binding = B_RASTER_COUNTS, std430) buffer RasterCounts {
    uint vertices;          // strand vertices written
    uint segments;          // segments written
    uint bin_groups;        // the bin passes' workgroups (x of the indirect dispatch)
    uint bin_groups_y;      // 1
    uint bin_groups_z;      // 1
    uint hairs_lost;        // hairs that found the vertex or segment pool full
    uint hairs_clipped;     // hairs with a vertex behind the eye
    uint entries;           // (segment, tile) entries binned
    uint entries_lost;      // entries that found the entry pool full
    uint tail_fragments;    // fragments blended in a pixel's tail, not in order
    uint pixels_stopped;    // pixels that stopped, opaque, before their tile's list ended
    uint fragments;         // fragments the pixels took: in order, merged or in a tail
    uint tail_fragments_high; // each add that wrapped tail_fragments past 2^32 adds one
    uint fragments_high;    // each add that wrapped fragments past 2^32 adds one
    uint listed_groups;     // the sort and fine passes' workgroups: x, y of the indirect
    uint listed_groups_y;   //   dispatch over the tiles that list something (listed_tile)
    uint listed_groups_z;   // 1
    uint listed_tiles;      // the tiles that list something
} raster_counts;

// The pools the passes read in their loops are texel buffers: on a CPU driver a texel
// read is one gather across the invocations, where a storage-buffer read loops over
// them one by one.
// Per vertex, two texels of words: its position (x, y in pixels, the depth as NDC z,
// the width in pixels), then its colour (r, g, b, 1), as floats' bits. Under the
// Marschner model the geometry stage leaves in the colour's place what the lighting
// pass (strand_shade.comp) lights the vertex by (pack_shading), and that pass writes
// the colour over it; its world position the pass finds from its position on the
// screen (world_position).
#ifdef WRITES_STRANDS
// The geometry stage writes both pools as storage buffers over the same memory, never
// as texel buffers: Mesa 22.3's lavapipe (Debian 12) may compile a geometry stage that
// binds storage images (texel buffers among them) again at any draw
// (crates/fur-gpu/src/render/bindings.rs, `FrameBinding::Positions`).
layout(set = SET_RASTER, binding = B_STRAND_VERTICES_WRITTEN, std430) writeonly buffer StrandVerticesWritten {
    uvec4 written_vertices[];
};
#else
layout(set = SET_RASTER, binding = B_STRAND_VERTICES, rgba32ui) uniform uimageBuffer strand_vertices;
#endif

// A unit vector as a point of the octahedron unfolded onto [-1, 1]² (and back).
vec2 octahedral(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 p = n.xy;
    if (n.z < 0.0) {
        p = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    }
    return p;
}

vec3 from_octahedral(vec2 p) {
    vec3 n = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    float f = max(-n.z, 0.0);
    n.x += n.x >= 0.0 ? -f : f;
    n.y += n.y >= 0.0 ? -f : f;
    return normalize(n);
}

// What lights a vertex: its tangent (octahedral, two snorm16), its base colour and the
// coat's hair layers towards the light and above it (half floats).
uvec4 pack_shading(vec3 tangent, vec3 base, vec2 coat) {
    return uvec4(packSnorm2x16(octahedral(tangent)), packHalf2x16(base.rg),
                 packHalf2x16(vec2(base.b, coat.x)), packHalf2x16(vec2(coat.y, 0.0)));
}

// Per segment: its first vertex (the second follows it) and its strand.
#ifdef WRITES_STRANDS
layout(set = SET_RASTER, binding = B_STRAND_SEGMENTS_WRITTEN, std430) writeonly buffer StrandSegmentsWritten {
    uvec2 written_segments[];
};

// The vertices the pool holds.
uint vertex_room() {
    return uint(written_vertices.length()) / 2u;
}

uint segment_room() {
    return uint(written_segments.length());
}
#else
layout(set = SET_RASTER, binding = B_STRAND_SEGMENTS, rg32ui) uniform uimageBuffer strand_segments;

// The vertices the pool holds.
uint vertex_room() {
    return uint(imageSize(strand_vertices)) / 2u;
}

uint segment_room() {
    return uint(imageSize(strand_segments));
}

vec4 vertex_position(uint v) {
    return uintBitsToFloat(imageLoad(strand_vertices, int(2u * v)));
}

// The world point whose projection is `position` (vertex_position: pixels and NDC z).
vec3 world_position(vec4 position) {
    vec2 ndc = position.xy / frame.camera.viewport * 2.0 - 1.0;
    vec4 world = frame.camera.inverse_view_proj * vec4(ndc, position.z, 1.0);
    return world.xyz / world.w;
}

StrandVertex strand_vertex(uint v) {
    return StrandVertex(uintBitsToFloat(imageLoad(strand_vertices, int(2u * v))),
                        uintBitsToFloat(imageLoad(strand_vertices, int(2u * v + 1u))));
}

uvec2 strand_segment(uint s) {
    return imageLoad(strand_segments, int(s)).xy;
}
#endif

// Per tile: the body's farthest depth in it, its entries counted, where its list
// starts in the entry pool, how many it keeps, and the cursor the scatter fills by;
// the range of its segments' sort keys (their bits: render::strand_raster::order),
// which its depth bins cut (where each bin ends in the sorted list is found from the
// entries: strand_fine.comp); and on a CPU driver, whose scatter runs as two
// workgroups, one for each half of the segments (strand_bin.comp, SERIAL_SCATTER), the
// entries of the first half's segments, after which the second half's are listed, and
// the second half's cursor.
struct TileBin {
    float body_far;
    uint count;
    uint offset;
    uint kept;
    uint cursor;
    uint near_lo;
    uint near_hi;
    uint lead;
    uint second_cursor;
    // Not this tile's: the index of the scan's i-th tile that lists something, in the
    // i-th tile's place (listed_tile).
    uint listed;
};

layout(set = SET_RASTER, binding = B_TILE_BINS, std430) buffer TileBins {
    TileBin tile_bins[];
};

layout(set = SET_RASTER, binding = B_TILE_ENTRIES, r32ui) uniform uimageBuffer tile_entries;

// The widest row of the indirect dispatch over the tiles that list something (every
// device's least maxComputeWorkGroupCount): the scan passes that many a row.
const uint LISTED_ROW = 65535u;

#if defined(TILE) && !defined(WRITES_STRANDS)
// In the passes dispatched over the tiles that list something (the sort and the fine
// raster: a tile that lists nothing has nothing to sort or draw, and lavapipe pays a
// start for every workgroup), the tile the workgroup takes: its index in tile_bins and
// its column and row of the screen's tiles; false for a workgroup past the list's end.
bool listed_tile(out uint tile, out uvec2 at) {
    uint i = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (i >= raster_counts.listed_tiles) {
        return false;
    }
    tile = tile_bins[i].listed;
    uint columns = (uint(frame.camera.viewport.x) + TILE - 1u) / TILE;
    at = uvec2(tile % columns, tile / columns);
    return true;
}
#endif

uint listed_entry(uint at) {
    return imageLoad(tile_entries, int(at)).x;
}

// The entry pool again, each tile's list sorted front to back by depth bin: each
// entry its segment, and a word of the masks of the tile's blocks the segments can
// reach (block_mask, strand_sort.comp): in each whole run of ROW_RUN entries from the
// list's start, the word at the run's place `b` is block b's row (bit j: the run's
// entry j reaches block b); in the run left over at the end, each entry's own mask.
// The sort pass reads back what it wrote (ORDER_COHERENT). ROW_RUN is defined by the
// renderer (render::strand_raster::order::ROW_RUN).
#ifdef ORDER_COHERENT
layout(set = SET_RASTER, binding = B_TILE_ORDER, rg32ui) coherent uniform uimageBuffer tile_order;
#else
layout(set = SET_RASTER, binding = B_TILE_ORDER, rg32ui) uniform uimageBuffer tile_order;
#endif

#ifdef TILE
// The mask's grid: MASK_X × MASK_Y blocks of BLOCK_X × BLOCK_Y pixels cover a tile, at
// most 32 (one pixel a block up to 4×4 tiles).
const uint MASK_X = TILE < 8u ? TILE : 8u;
const uint MASK_Y = TILE < 32u / MASK_X ? TILE : 32u / MASK_X;
const uint BLOCK_X = TILE / MASK_X;
const uint BLOCK_Y = TILE / MASK_Y;

// The bit of the mask that holds the pixel `p` of a tile (its place in the tile).
uint mask_bit(uvec2 p) {
    return (p.y / BLOCK_Y) * MASK_X + p.x / BLOCK_X;
}
#endif

// A segment's sort key: its nearer end's depth, at least 0 (order::depth_key).
float depth_key(float a, float b) {
    return max(min(a, b), 0.0);
}

// The bin of `key` in a tile whose keys start at `lo`, `scale` bins a unit of depth
// (order::bin_scale, order::depth_bin). DEPTH_BINS is defined by the renderer
// (render::strand_raster::order::DEPTH_BINS).
float bin_scale(float lo, float hi) {
    return hi > lo ? float(DEPTH_BINS) / (hi - lo) : 0.0;
}

uint depth_bin(float key, float lo, float scale) {
    float b = (key - lo) * scale;
    return b > 0.0 ? min(uint(b), uint(DEPTH_BINS) - 1u) : 0u;
}

// Per pixel: the hair's colour premultiplied by its coverage, and the light it lets
// through (1 where no hair is).
layout(set = SET_RASTER, binding = B_HAIR_LAYER, std430) buffer HairLayer {
    vec4 hair_layer[];
};

// The mean of x clamped to [lo, hi] as x runs evenly from p to q.
float mean_clamped(float p, float q, float lo, float hi) {
    float u = min(p, q);
    float v = max(p, q);
    float span = v - u;
    if (span < 1e-6) {
        return clamp(0.5 * (p + q), lo, hi);
    }
    float below = max(min(lo, v) - u, 0.0);
    float above = max(v - max(hi, u), 0.0);
    float m = max(u, lo);
    float n = min(v, hi);
    float inside = n > m ? 0.5 * (n * n - m * m) : 0.0;
    return (lo * below + inside + hi * above) / span;
}

// The signed area between the edge p → q and the right side x = 0.5 of the pixel
// [-0.5, 0.5]², within its rows, x clamped to its columns.
float edge_area(vec2 p, vec2 q) {
    float dy = q.y - p.y;
    if (dy == 0.0) {
        return 0.0;
    }
    float ya = max(-0.5, min(p.y, q.y));
    float yb = min(0.5, max(p.y, q.y));
    if (yb <= ya) {
        return 0.0;
    }
    float slope = (q.x - p.x) / dy;
    float xa = p.x + (ya - p.y) * slope;
    float xb = p.x + (yb - p.y) * slope;
    return sign(dy) * (yb - ya) * (0.5 - mean_clamped(xa, xb, -0.5, 0.5));
}

// The area of the pixel centred at `centre` inside the segment a–b of widths wa, wb
// (x), and the parameter of the axis point nearest the centre (y).
vec2 strand_footprint(vec2 centre, vec2 a, vec2 b, float wa, float wb) {
    vec2 d = b - a;
    float len = length(d);
    if (isnan(len) || len < 1e-3) {
        return vec2(0.0);
    }
    vec2 u = d / len;
    vec2 n = vec2(-u.y, u.x);
    vec2 p = centre - a;
    float s = dot(p, u);
    float across = dot(p, n);
    float t = clamp(s / len, 0.0, 1.0);
    const float reach = 0.70710678;
    float half_w = 0.5 * max(wa, wb);
    if (abs(across) >= half_w + reach || s <= -reach || s >= len + reach) {
        return vec2(0.0, t);
    }
    vec2 qa = a - centre;
    vec2 qb = b - centre;
    vec2 c0 = qa - 0.5 * wa * n;
    vec2 c1 = qb - 0.5 * wb * n;
    vec2 c2 = qb + 0.5 * wb * n;
    vec2 c3 = qa + 0.5 * wa * n;
    float area = edge_area(c0, c1) + edge_area(c1, c2) + edge_area(c2, c3) + edge_area(c3, c0);
    return vec2(min(abs(area), 1.0), t);
}

// A segment slot left empty (its hair found a pool full).
const uint NO_SEGMENT = 0xffffffffu;

// Fragments fainter than this are not kept (render::strand_raster::MIN_ALPHA).
const float MIN_ALPHA = 1.0 / 1024.0;

#endif
