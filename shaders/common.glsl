// Declarations shared by the mesh and fur passes. `Frame` is `FrameUniforms` of
// crates/fur-core/src/render/frame_block.rs (std140), a struct per purpose, declared for
// GLSL from there; the set and binding numbers are defines from
// crates/fur-gpu/src/render/bindings.rs. A test there checks both against the compiled
// SPIR-V.
#ifndef COMMON_GLSL
#define COMMON_GLSL

#ifndef B_FRAME_UNIFORMS
#error "render shaders are compiled with binding_defines() (crates/fur-gpu/src/render/bindings.rs)"
#endif

#include "strands.glsl"

// Variants the renderer may leave undefined.
#ifndef TEXTURED
#define TEXTURED 0
#endif
#ifndef SHADOWS
#define SHADOWS 0
#endif
#ifndef SHADOW_CASTER
#define SHADOW_CASTER 0
#endif
#ifndef COMPUTE_RASTER
#define COMPUTE_RASTER 0
#endif
#ifndef COVERAGE_SAMPLES
#define COVERAGE_SAMPLES 0
#endif
// The stage view (`--show`): 0 lit (the final image), or one of STAGE_MASTERS,
// STAGE_INTERPOLATED, STAGE_DENSITY, STAGE_LOD, STAGE_SIMULATION, STAGE_SHADOW,
// STAGE_OWNERSHIP, defined from the Rust numbers
// (crates/fur-core/src/render/stage.rs: stage_defines), never typed here.
#ifndef STAGE_VIEW
#define STAGE_VIEW 0
#endif
#ifndef STAGE_OWNERSHIP
#error "render shaders are compiled with shader_defines() (crates/fur-core/src/render/uniforms.rs)"
#endif

// The `Frame` uniform block and its structs (camera, lighting, drawing, strands,
// shadow, fibre): made from their Rust declarations (crates/fur-core/src/render/frame_block.rs),
// never typed here.
#include "frame_block.glsl"

// The flags of drawing.flags (FLAG_CULL, FLAG_THICKNESS_COMPENSATION, FLAG_COUNT,
// FLAG_THIN_HAIR_AA) and lighting.flags (FLAG_SECONDARY_HIGHLIGHT, FLAG_NO_*) are
// defined for every render shader from the Rust constants (crates/fur-core/src/render/uniforms.rs: shader_defines), never typed here.
#ifndef FLAG_CULL
#error "render shaders are compiled with shader_defines() (crates/fur-core/src/render/uniforms.rs)"
#endif

// Read with texelFetch, as a texture, never as a storage image (why:
// `FrameBinding::Positions` in crates/fur-gpu/src/render/bindings.rs).
layout(set = SET_FRAME, binding = B_STRAND_POSITIONS) uniform sampler2D strand_positions;

layout(set = SET_BODY, binding = B_OWNERSHIP, std430) readonly buffer Ownership {
    uint owner_mask[];
};

#if COUNT_HAIRS
// What the fur pass drew (its geometry stage counts hairs and segments, its
// tessellation control stage the triangles it culls). With a capture buffer bound
// (`fur export-frame`; `captured` is empty otherwise), every counted hair is also
// written out as drawn: per hair 2 · STRAND_VERTICES + 1 vec4s
// (crates/fur-gpu/src/render/renderer/capture.rs reads them), in the order the atomic
// hands out.
layout(set = SET_FRAME, binding = B_HAIR_COUNTERS, std430) buffer Counters {
    uint hairs_drawn;
    uint segments_drawn;
    uint triangles_culled;
    uint unused;
    vec4 captured[];
} counters;
#endif

vec3 strand_vertex(uint strand, uint vertex) {
    return texelFetch(strand_positions, strand_texel(strand, vertex, frame.strands.vertices_per_strand, frame.strands.strands_per_row), 0).xyz;
}

// Density level of detail at point p: 1 up to the full-density distance D, then
// (D / d)² so that hairs per pixel stay roughly constant.
float lod_factor(vec3 p) {
    float d = max(distance(p, frame.camera.eye), 1e-6);
    float r = frame.drawing.lod_distance / d;
    return min(1.0, r * r);
}

uint hash_u32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// A saturated colour for hue h in [0, 1) (the stage views' colour scales).
vec3 hue(float h) {
    return clamp(abs(mod(h * 6.0 + vec3(0.0, 4.0, 2.0), 6.0) - 3.0) - 1.0, 0.0, 1.0);
}

// Uniform in [0, 1).
float hash_unit(uint x) {
    return float(hash_u32(x) >> 8) / 16777216.0;
}

#endif
