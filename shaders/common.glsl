// Declarations shared by the mesh and fur passes. `Frame` is `FrameUniforms` of
// crates/fur-core/src/render/frame_block.rs (std140), a struct per purpose; the set and binding numbers are
// defines from crates/fur-gpu/src/render/bindings.rs. A test there checks both against
// the compiled SPIR-V.
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

// What every pass projects with.
struct Camera {
    mat4 view_proj;               // world to clip space
    mat4 model;                   // the head transform H, model to world
    vec3 eye;                     // the camera's position, world space
    float pixel_at_unit_distance; // world size of a pixel at distance 1 from the eye
    vec2 viewport;                // the target's width and height, pixels
};

// The light and the hair's and skin's colours.
struct Lighting {
    vec3 direction;               // unit vector towards the light
    float intensity;
    vec3 root_color;
    float root_occlusion;         // darkening at the root, 0..1
    vec3 tip_color;
    float kd;                     // Kajiya–Kay's diffuse weight
    vec3 skin_color;
    float ks;                     // Kajiya–Kay's specular weight
    float shininess;              // Kajiya–Kay's specular exponent
    float ambient;
    vec2 primary_shift;           // cos, sin of the primary highlight's shift
    vec2 secondary_shift;         // cos, sin of the secondary highlight's shift
    float secondary_shininess;
    float secondary_strength;
    uint flags;                   // FLAG_SECONDARY_HIGHLIGHT, FLAG_NO_R … FLAG_NO_COAT
};

// How dense, wide and detailed the fur pass draws.
struct Drawing {
    float density;                // hairs per unit area at full density
    float lod_distance;           // full density closer than this
    float max_level;              // the device's largest tessellation level
    float cull_margin;            // back-facing when cos(normal, view) < -cull_margin
    float hair_width;             // at the root, scene units
    float min_pixel_width;
    float jitter;                 // random tip offset, scene units
    float length_jitter;
    float ribbon_above_px;        // hairs at least this wide at the root are ribbons
    float vertex_lod_px;          // vertex LOD tolerance, pixels (0: every vertex)
    float texels;                 // the fur texture's texels (0: none)
    float arrow_scale;            // the simulation view's arrows, times their length
    uint fixed_level;             // the tessellation level everywhere (0: adaptive)
    uint flags;                   // FLAG_CULL, FLAG_THICKNESS_COMPENSATION, FLAG_COUNT, FLAG_THIN_HAIR_AA
};

// The master strands' texture.
struct Strands {
    uint vertices_per_strand;
    uint strands_per_row;
    float stub_length;            // a master whose tip is this close to its root is a bald stub
};

// The light's way through the fur.
struct Shadow {
    mat4 light_view_proj;         // world to the shadow map's clip space (orthographic)
    float opacity;                // the light each hair layer stops
    float layers_per_unit;        // hair layers per scene unit (the coat's estimate)
    float layers_per_depth;       // hair layers per unit of the map's depth
    float depth_bias;             // in the map's depth units
    float skin_layers;            // hair layers over the skin (mesh.frag)
};

// The Marschner model's fibre.
struct Fibre {
    float r_exponent;             // −1/(2 sd²) of the R lobe (render::marschner::shader_terms)
    float r_norm;                 // 1/(√(2π) sd) of the R lobe
    float f0;                     // reflectance at normal incidence
    float colour_scale;           // 1/d(β_n) of the colour mapping
    float cuticle_tilt;           // radians
    // The dual-scattering table (render::dual_scattering::table): node (angle i,
    // colour j) at DS_NODE_VEC4S (i · DS_COLOUR_NODES + j): [a_f, β_f², Ā_b, Δ_b],
    // [σ_b², a_b, α, β²].
    vec4 table[DS_NODE_VEC4S * DS_ANGLE_NODES * DS_COLOUR_NODES];
};

layout(set = SET_FRAME, binding = B_FRAME_UNIFORMS, std140) uniform Frame {
    Camera camera;
    Lighting lighting;
    Drawing drawing;
    Strands strands;
    Shadow shadow;
    Fibre fibre;
} frame;

// The flags of drawing.flags (FLAG_CULL, FLAG_THICKNESS_COMPENSATION, FLAG_COUNT,
// FLAG_THIN_HAIR_AA) and lighting.flags (FLAG_SECONDARY_HIGHLIGHT, FLAG_NO_*) are
// defined for every render shader from the Rust constants (crates/fur-core/src/render/uniforms.rs: shader_defines), never typed here.
#ifndef FLAG_CULL
#error "render shaders are compiled with shader_defines() (crates/fur-core/src/render/uniforms.rs)"
#endif

layout(set = SET_FRAME, binding = B_STRAND_POSITIONS, rgba32f) uniform readonly image2D strand_positions;

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
    return imageLoad(strand_positions, strand_texel(strand, vertex, frame.strands.vertices_per_strand, frame.strands.strands_per_row)).xyz;
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
