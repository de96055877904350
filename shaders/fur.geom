#version 450
// Fur pass, geometry stage: emits one interpolated hair, the blend of its triangle's
// three master hairs at the point's barycentric coordinates plus a per-hair jitter.
//
// Compiled in two forms (the renderer defines LINES):
// - LINES = 1: a line strip. The hair's coverage of its pixels, width / pixel size,
//   travels as alpha: blended at one sample per pixel, a sample mask under MSAA.
//   For hairs under a pixel wide.
// - LINES = 0: a camera-facing ribbon of the hair's width.
// A hair is drawn by one form only: ribbons take the hairs at least `frame.drawing.ribbon_above_px`
// pixels wide at the root, lines the rest.
//
// Widths taper from root to tip and are never drawn under `frame.drawing.min_pixel_width` pixels. With
// thin-hair anti-aliasing (FLAG_THIN_HAIR_AA) a hair drawn wider than it is covers its
// pixels only by its true width: alpha = true width / drawn width, so a sub-pixel hair
// neither vanishes between samples nor darkens more than its width; without it such a
// hair is drawn opaque at the minimum width. With thickness compensation, hairs thinned
// out by the density LOD are widened by the same factor, so coverage is kept.
//
// Vertex LOD (frame.drawing.vertex_lod_px > 0, a tolerance in pixels): a strand vertex is left out
// when the segment that skips it passes within the tolerance of where the vertex would
// have been drawn, its width included. Straight hairs become a single segment, curled
// ones keep their curls; the root and the tip are always drawn where they are.
//
// With VERTEX_SHADING = 1 the lighting terms (shadow included) are evaluated here, per
// emitted vertex; otherwise per fragment. TEXTURED: the texture at the hair's root UV
// (blended from its triangle's corners by the evaluation stage) is its base colour.
// SHADOW_CASTER: the light's view of the fur for the shadow map, positions only.
// MARSCHNER: the fibre model instead of Kajiya–Kay (per vertex, its radiance).
// COMPUTE_RASTER: the strand is not emitted but written into the strand buffers the
// compute passes draw from (strand_raster.glsl), with the rasteriser discarded; its
// hairs and segments are counted as the emitted ones are. Under the Marschner model
// (DEFERRED_SHADING) a vertex's colour texel holds what lights it (tangent, base
// colour, coat: pack_shading) and a compute pass lights it (strand_shade.comp: a CPU
// driver runs this stage on one thread, a compute pass on all); Kajiya–Kay costs less
// here than a pass's reading and writing of each vertex, and a stage view's colours
// are made here.
// STRAND_VERTICES, LINES, VERTEX_SHADING, TEXTURED, SHADOWS, SHADOW_CASTER, MARSCHNER,
// COUNT_HAIRS and COMPUTE_RASTER are defined by the renderer.
#include "shading.glsl"
#if COMPUTE_RASTER
#define WRITES_STRANDS 1
#include "strand_raster.glsl"
#endif
#if COMPUTE_RASTER && STAGE_VIEW == 0 && MARSCHNER && !defined(FUR_TEST_LIGHT_IN_GEOMETRY)
#define DEFERRED_SHADING 1
#else
#define DEFERRED_SHADING 0
#endif

layout(points) in;
#if COMPUTE_RASTER
layout(points, max_vertices = 1) out;
#elif LINES
layout(line_strip, max_vertices = STRAND_VERTICES) out;
#else
layout(triangle_strip, max_vertices = 2 * STRAND_VERTICES) out;
#endif

layout(location = 0) in uvec3 e_hair[];
layout(location = 1) in vec3 e_bary[];
layout(location = 2) in uint e_keep[];

#if TEXTURED
layout(location = 3) in vec3 e_uv_lod[];         // root UV, texture level of detail
#endif

#if !SHADOW_CASTER
#if VERTEX_SHADING
layout(location = 0) out vec4 g_lit_along;        // ambient + diffuse, specular, tinted, along
#else
layout(location = 0) out vec4 g_tangent_along;    // world tangent, position along the hair
layout(location = 1) out vec3 g_world;            // world position
#if MARSCHNER
layout(location = 5) out vec2 g_coat;             // hair layers towards the light and above (coat_layers)
#endif
#endif
layout(location = 2) out float g_coverage;
#if TEXEL_TO_FRAGMENT
layout(location = 3) out vec3 g_texel;            // the texture at the root (linear)
#endif
#if COVERAGE_SAMPLES > 1
layout(location = 4) flat out uint g_seed;        // the hair's, for its coverage dither
#endif
#endif


const uint V = uint(STRAND_VERTICES);
#if TEXTURED && !SHADOW_CASTER
vec3 texel;                    // the texture at the hair's root
#endif
uint hair_seed;

vec3 P[STRAND_VERTICES];       // the hair's vertices, world space
float W[STRAND_VERTICES];      // its width at each as drawn, world units
float C[STRAND_VERTICES];      // its coverage of the width drawn (alpha)
float S[STRAND_VERTICES];      // the world size of a pixel at each

vec3 blended(uvec3 h, vec3 b, uint k) {
    return b.x * strand_vertex(h.x, k) + b.y * strand_vertex(h.y, k) + b.z * strand_vertex(h.z, k);
}

float along(uint k) {
    return float(k) / float(V - 1u);
}

// The hair's true width at vertex k: `thickness` at the root, tapering to a fifth.
float true_width(float thickness, uint k) {
    return thickness * (1.0 - 0.8 * along(k));
}

// Whether the segment a → c draws every vertex between within `tolerance` pixels of
// where it is: its position, and its width (coverage) as well.
bool skippable(uint a, uint c, float tolerance) {
    for (uint m = a + 1u; m < c; ++m) {
        float f = float(m - a) / float(c - a);
        float off = distance(mix(P[a], P[c], f), P[m]) + abs(mix(W[a], W[c], f) - W[m]);
        if (off > tolerance * S[m]) {
            return false;
        }
    }
    return true;
}

#if MARSCHNER && !SHADOW_CASTER
vec3 coat_normal;              // the skin's outward normal under the hair
float coat_height;             // the coat's height there: the hair's tip above its root
float coat_curvature;          // the skin's curvature there, 1 / radius (0: flat or hollow)

// The coat's estimate of the hair layers around vertex k, for the Marschner model: x,
// between it and the light (without a shadow map): the light's path out of the coat,
// a shell of the coat's height on a skin of the coat's curvature, at the layer spacing
// the shadow map also assumes (frame.shadow.layers_per_unit layers per unit); the skin stops light
// whose path passes through it. y, above it along the skin's normal: what stands between
// it and the sky (the environment's light). Both capped at MAX_LAYERS, as the map's
// count is. The twin, render::marschner::coat_layers, derives x.
vec2 coat_layers(uint k) {
    float c = dot(coat_normal, frame.lighting.direction);
    float h = dot(P[k] - P[0], coat_normal);
    float above = min(max(coat_height - h, 0.0) * frame.shadow.layers_per_unit, MAX_LAYERS);
    float a = 1.0 + coat_curvature * h;
    if (c < 0.0 && a * a * (1.0 - c * c) < 1.0) {
        return vec2(MAX_LAYERS, above);
    }
    float q = max(coat_height - h, 0.0) * (2.0 + coat_curvature * (coat_height + h));
    float path = q / max(a * c + sqrt(a * a * c * c + coat_curvature * q), 1e-12);
    return vec2(min(path * frame.shadow.layers_per_unit, MAX_LAYERS), above);
}

// Sets coat_normal, coat_height and coat_curvature for the hair between masters h.
void find_coat(uvec3 h) {
    vec3 r[3] = vec3[3](strand_vertex(h.x, 0u), strand_vertex(h.y, 0u), strand_vertex(h.z, 0u));
    // The masters leave the skin along its normal: their first segments say which way
    // is out, stand in for the face's normal where the face is degenerate, and turn
    // with the skin: across a sphere of radius R they differ by the roots' offsets / R.
    vec3 d[3] = vec3[3](normalize(strand_vertex(h.x, 1u) - r[0]),
                        normalize(strand_vertex(h.y, 1u) - r[1]),
                        normalize(strand_vertex(h.z, 1u) - r[2]));
    vec3 out_dir = d[0] + d[1] + d[2];
    vec3 n = cross(r[1] - r[0], r[2] - r[0]);
    if (dot(n, n) < 1e-20) {
        n = out_dir;
    }
    n = normalize(n);
    coat_normal = dot(n, out_dir) < 0.0 ? -n : n;
    coat_height = max(dot(P[V - 1u] - P[0], coat_normal), 0.0);
    float turn = 0.0;
    float spread = 0.0;
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3;
        turn += dot(d[j] - d[i], r[j] - r[i]);
        spread += dot(r[j] - r[i], r[j] - r[i]);
    }
    coat_curvature = spread > 0.0 ? max(turn / spread, 0.0) : 0.0;   // twin: render::marschner::skin_curvature
#ifdef FUR_TEST_FLAT_COAT
    coat_curvature = 0.0;   // test only: flat skin everywhere, which tests/coat.rs must reject
#endif
}
#endif

#if !SHADOW_CASTER && VERTEX_SHADING
vec4 lit_along;                // the lit vertex, computed once for both ribbon sides
#endif
#if MARSCHNER && !SHADOW_CASTER && (!VERTEX_SHADING || DEFERRED_SHADING)
vec2 vertex_coat;              // the vertex's coat_layers, computed once for both sides
#endif
#if STAGE_VIEW != 0 && STAGE_VIEW != STAGE_SHADOW
vec3 view_colour;              // the stage view's colour of this hair
#endif

// The texture at the hair's root (white without one).
vec3 root_texel() {
#if TEXTURED && !SHADOW_CASTER
    return texel;
#else
    return vec3(1.0);
#endif
}

// Writes every output of vertex k. GLSL leaves outputs undefined after EmitVertex, so
// this runs before each one, the ribbon's second side included.
void write_outputs(uint k, vec3 t) {
#if !SHADOW_CASTER
#if VERTEX_SHADING
    g_lit_along = lit_along;
#else
    g_tangent_along = vec4(t, along(k));
    g_world = P[k];
#if MARSCHNER
    g_coat = vertex_coat;
#endif
#endif
    g_coverage = C[k];
#if TEXEL_TO_FRAGMENT
    g_texel = texel;
#endif
#if COVERAGE_SAMPLES > 1
    g_seed = hair_seed;
#endif
#endif
}

#if COMPUTE_RASTER
float TW[STRAND_VERTICES];            // the hair's true width at each
vec4 kept_position[STRAND_VERTICES];  // x, y (pixels), depth (NDC z), width (pixels)
uvec4 kept_color[STRAND_VERTICES];    // its colour (its floats' bits); deferred: pack_shading
uint kept_count = 0u;
bool behind_eye = false;

// Keeps vertex k (tangent t) as the compute passes draw it: on the screen, its width
// in pixels (its true width with thin-hair anti-aliasing, the drawn width otherwise;
// coverage does the rest), and what the lighting pass lights it by, or in a stage
// view its colour (lit_along).
void keep_vertex(uint k, vec3 t) {
    vec4 clip = frame.camera.view_proj * vec4(P[k], 1.0);
    behind_eye = behind_eye || clip.w <= 1e-6;
    vec3 ndc = clip.xyz / max(clip.w, 1e-6);
    vec2 pixel = (ndc.xy * 0.5 + 0.5) * frame.camera.viewport;
    bool thin_hair_aa = (frame.drawing.flags & FLAG_THIN_HAIR_AA) != 0u;
    float width = (thin_hair_aa ? TW[k] : W[k]) / S[k];
#if DEFERRED_SHADING
    uvec4 color = pack_shading(t, hair_base(along(k), root_texel()), vertex_coat);
#elif STAGE_VIEW != 0 || MARSCHNER
    uvec4 color = floatBitsToUint(vec4(lit_along.xyz, 1.0));
#else
    uvec4 color = floatBitsToUint(vec4(hair_color(lit_along.xyz, along(k), root_texel()), 1.0));
#endif
    kept_position[kept_count] = vec4(pixel, ndc.z, width);
    kept_color[kept_count] = color;
    kept_count += 1u;
}

// Writes the kept vertices and their segments into the strand buffers (the strand
// named by its first vertex), or counts the
// hair lost when they are full or clipped when a vertex lies behind the eye.
void write_strand() {
    if (behind_eye) {
        atomicAdd(raster_counts.hairs_clipped, 1u);
        return;
    }
    uint first = atomicAdd(raster_counts.vertices, kept_count);
    uint segments = kept_count - 1u;
    uint first_segment = atomicAdd(raster_counts.segments, segments);
    uint room = segment_room();
    if (first + kept_count > vertex_room() || first_segment + segments > room) {
        atomicAdd(raster_counts.hairs_lost, 1u);
        // Its segments that fit are marked as none, so that the bin passes skip them.
        for (uint i = 0u; i < segments && first_segment + i < room; ++i) {
            written_segments[first_segment + i] = uvec2(NO_SEGMENT);
        }
        return;
    }
    for (uint i = 0u; i < kept_count; ++i) {
        written_vertices[2u * (first + i)] = floatBitsToUint(kept_position[i]);
        written_vertices[2u * (first + i) + 1u] = kept_color[i];
    }
    for (uint i = 0u; i < segments; ++i) {
        written_segments[first_segment + i] = uvec2(first + i, first);
    }
    // The bin passes' workgroups, at most the dispatch limit every device has (each
    // invocation then takes every so-many-th segment).
    atomicMax(raster_counts.bin_groups,
              min((first_segment + segments + GROUP_SIZE - 1u) / GROUP_SIZE, 65535u));
}
#endif

void emit_vertex(uint k, vec3 t) {
#if DEFERRED_SHADING
    vertex_coat = coat_layers(k);
#elif STAGE_VIEW == STAGE_SHADOW && MARSCHNER
    // The Marschner model's light through the fibres, in their colour.
    lit_along = vec4(light_through_fibres(t, P[k], hair_base(along(k), root_texel()), coat_layers(k)),
                     along(k));
#elif STAGE_VIEW == STAGE_SHADOW
    lit_along = vec4(vec3(light_through_fur(P[k])), along(k));
#elif STAGE_VIEW != 0
    lit_along = vec4(view_colour, along(k));
#elif !SHADOW_CASTER && VERTEX_SHADING && MARSCHNER
    lit_along = vec4(marschner(t, P[k], hair_base(along(k), root_texel()), coat_layers(k)), along(k));
#elif !SHADOW_CASTER && VERTEX_SHADING
    lit_along = vec4(kajiya_kay(t, P[k], light_through_fur(P[k])), along(k));
#elif MARSCHNER && !SHADOW_CASTER
    vertex_coat = coat_layers(k);
#endif
#if COMPUTE_RASTER
    keep_vertex(k, t);
#elif LINES
    write_outputs(k, t);
    gl_Position = frame.camera.view_proj * vec4(P[k], 1.0);
    EmitVertex();
#else
    vec3 side = cross(t, frame.camera.eye - P[k]);
    float side_len = length(side);
    side = side_len > 1e-12 ? side * (0.5 * W[k] / side_len) : vec3(0.5 * W[k], 0.0, 0.0);
    write_outputs(k, t);
    gl_Position = frame.camera.view_proj * vec4(P[k] - side, 1.0);
    EmitVertex();
    write_outputs(k, t);
    gl_Position = frame.camera.view_proj * vec4(P[k] + side, 1.0);
    EmitVertex();
#endif
}

#if COUNT_HAIRS
// Writes hair number `index` into the capture buffer, when one is bound and has room:
// every vertex before the vertex LOD (position, true width), then each vertex's base
// colour (the ramp and texture, unlit) and drawn width, then the hair's seed, its form
// (0 lines, 1 ribbons) and its root width before the taper (`thickness`).
void capture(uint index, float thickness) {
    const uint stride = 2u * V + 1u;
    if (uint(counters.captured.length()) < (index + 1u) * stride) {
        return;
    }
    uint at = index * stride;
    for (uint k = 0u; k < V; ++k) {
        counters.captured[at + k] = vec4(P[k], true_width(thickness, k));
        counters.captured[at + V + k] = vec4(hair_base(along(k), root_texel()), W[k]);
    }
    counters.captured[at + 2u * V] = vec4(uintBitsToFloat(hair_seed), float(1 - LINES), thickness, 0.0);
}
#endif

void main() {
    if (e_keep[0] == 0u) {
        return;
    }
    uvec3 h = e_hair[0];
    vec3 b = e_bary[0];
    vec3 root = blended(h, b, 0u);
    float pixel = frame.camera.pixel_at_unit_distance;                    // world size of a pixel at distance 1
    float thickness = frame.drawing.hair_width;
    if ((frame.drawing.flags & FLAG_THICKNESS_COMPENSATION) != 0u) {
        thickness /= lod_factor(root);
    }
    float root_pixel = pixel * distance(root, frame.camera.eye);
    float root_pixels = max(thickness / root_pixel, frame.drawing.min_pixel_width);
#if COMPUTE_RASTER
    // Every hair: the compute passes draw any width.
#elif LINES
    if (root_pixels >= frame.drawing.ribbon_above_px) {
        return;
    }
#else
    if (root_pixels < frame.drawing.ribbon_above_px) {
        return;
    }
#endif
    // The hair's seed: its three master hairs and its place between them, which name it
    // on any device and in any order of drawing. (Not gl_PrimitiveIDIn: after
    // tessellation its value is the driver's own; Mesa 25's lavapipe hands over a
    // different one at each draw of the same frame.)
    uint seed = hash_u32(hash_u32(h.x ^ hash_u32(h.y ^ hash_u32(h.z))) * 0x9e3779b9u
                         ^ hash_u32(floatBitsToUint(b.x) ^ hash_u32(floatBitsToUint(b.y))));
    hair_seed = seed;
    vec3 jitter = (vec3(hash_unit(seed), hash_unit(seed + 1u), hash_unit(seed + 2u)) * 2.0 - 1.0)
                * frame.drawing.jitter;
    // The tip's random offset is at most JITTER_SHARE of the hair's own reach, so the
    // short hair of a thin part (an ear, a leg) is not scattered into a tuft.
    float reach = distance(blended(h, b, V - 1u), root);
    jitter *= min(1.0, JITTER_SHARE * reach / max(length(jitter), 1e-20));
    float length_scale = 1.0 - frame.drawing.length_jitter * hash_unit(seed + 3u);
    if (h.x == h.y && h.y == h.z) {
        // A drawn groom's guide is drawn as it is (fur.tesc).
        jitter = vec3(0.0);
        length_scale = 1.0;
    }

#if TEXTURED && !SHADOW_CASTER
    texel = textureLod(albedo, e_uv_lod[0].xy, e_uv_lod[0].z).rgb;
#endif
    bool thin_hair_aa = (frame.drawing.flags & FLAG_THIN_HAIR_AA) != 0u;
    for (uint k = 0u; k < V; ++k) {
        vec3 p = k == 0u ? root : root + (blended(h, b, k) - root) * length_scale;
        P[k] = p + jitter * along(k);
        S[k] = pixel * distance(P[k], frame.camera.eye);
        float width = true_width(thickness, k);
#if COMPUTE_RASTER
        TW[k] = width;
#endif
        W[k] = max(width, frame.drawing.min_pixel_width * S[k]);
#if LINES
        // A line is a pixel wide: it covers the pixel by the hair's width.
        C[k] = min((thin_hair_aa ? width : W[k]) / S[k], 1.0);
#else
        C[k] = thin_hair_aa ? width / W[k] : 1.0;
#endif
    }

#if MARSCHNER && !SHADOW_CASTER
    find_coat(h);
#endif
    float tolerance = frame.drawing.vertex_lod_px;
#if defined(FUR_TEST_DROP_TIP) || defined(FUR_TEST_DROP_ROOT)
    // Test only: a vertex LOD that loses the tip (or the root), drawing it where its
    // neighbour is; tests/render_levers.rs must reject it.
    if (tolerance > 0.0) {
#ifdef FUR_TEST_DROP_TIP
        P[V - 1u] = P[V - 2u];
#else
        P[0] = P[1];
#endif
    }
#endif
#if STAGE_VIEW == STAGE_INTERPOLATED || STAGE_VIEW == STAGE_OWNERSHIP
    // Flat per source triangle: its three master hairs name it.
    view_colour = hue(hash_unit(hash_u32(h.x ^ hash_u32(h.y ^ hash_u32(h.z)))));
#if STAGE_VIEW == STAGE_OWNERSHIP
    // Where the point lies, from its barycentric coordinates (exact zeros on the
    // patch's edges): inside dim, on an edge bright, at a corner white. Only the
    // owner of a shared edge or corner draws its points, so the colour there is the
    // owner's.
    uint zeros = uint(b.x == 0.0) + uint(b.y == 0.0) + uint(b.z == 0.0);
    view_colour = zeros >= 2u ? vec3(1.0) : zeros == 1u ? view_colour : 0.3 * view_colour;
#endif
#elif STAGE_VIEW == STAGE_LOD
    // Hue: the share of the strand's segments the vertex LOD keeps (red all, through
    // yellow and green, to blue for one); brightness: the density LOD's thinning here
    // (full where every hair is drawn, darker as distance thins them).
    uint kept = 0u;
    for (uint at = 0u; at + 1u < V;) {
        uint next = at + 1u;
        if (tolerance > 0.0) {
            while (next + 1u < V && skippable(at, next + 1u, tolerance)) {
                next += 1u;
            }
        }
        at = next;
        kept += 1u;
    }
    float share = V > 2u ? float(kept - 1u) / float(V - 2u) : 1.0;
    view_colour = hue(0.66 * (1.0 - share)) * mix(0.25, 1.0, lod_factor(root));
#endif
    vec3 t = vec3(0.0, 1.0, 0.0);
    uint segments = 0u;
    uint k = 0u;
    while (true) {
        // The tangent of the strand's own segment here (the tip keeps the last one).
        if (k + 1u < V) {
            vec3 d = P[k + 1u] - P[k];
            if (dot(d, d) > 1e-24) {
                t = normalize(d);
            }
        }
        emit_vertex(k, t);
        if (k + 1u >= V) {
            break;
        }
        uint next = k + 1u;
        if (tolerance > 0.0) {
            while (next + 1u < V && skippable(k, next + 1u, tolerance)) {
                next += 1u;
            }
        }
        k = next;
        segments += 1u;
    }
#if COMPUTE_RASTER
    write_strand();
#else
    EndPrimitive();
#endif
#if COUNT_HAIRS
    if ((frame.drawing.flags & FLAG_COUNT) != 0u) {
        uint index = atomicAdd(counters.hairs_drawn, 1u);
        atomicAdd(counters.segments_drawn, segments);
        capture(index, thickness);
    }
#endif
}
