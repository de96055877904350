#version 450
// Strands in compute, pass 6: the hair layer over what the target's scope drew (the
// body and the background, resolved): colour = hair + transmittance × target, written
// sRGB-encoded into an image the size of the target, which is then copied onto it.
// (Compositing with a draw after the compute passes crashes Mesa 22.3's lavapipe once
// the simulation has run in the same command buffer.) One invocation per pixel.
// TILE and TILES_VIEW are defined by the renderer.
#include "common.glsl"
#include "strand_raster.glsl"

layout(local_size_x = TILE, local_size_y = TILE) in;

layout(set = SET_RASTER, binding = B_TARGET_COLOR) uniform sampler2D target_color;
layout(set = SET_RASTER, binding = B_COMPOSITED, rgba8) uniform writeonly image2D composited;

// Linear to sRGB, as an sRGB attachment stores it.
vec3 encode_srgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// The tiles view's colour for a tile listing `entries` segments
// (render::stage::tile_colour).
vec3 tile_colour(uint entries) {
    if (entries == 0u) {
        return vec3(EMPTY_TILE);
    }
    float t = clamp(log2(float(entries)) / log2(TILE_ENTRIES_FULL_SCALE), 0.0, 1.0);
    return hue((1.0 - t) * (2.0 / 3.0));
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(frame.camera.viewport);
    if (any(greaterThanEqual(p, size))) {
        return;
    }
#if TILES_VIEW
    // `--show tiles`: each tile in the colour of the segments it lists; tiles of 8
    // pixels or more outlined, darker.
    uint columns = (uint(size.x) + TILE - 1u) / TILE;
    uint tile = (uint(p.y) / TILE) * columns + uint(p.x) / TILE;
    vec3 c = tile_colour(tile_bins[tile].kept);
    if (TILE >= 8u && (uint(p.x) % TILE == 0u || uint(p.y) % TILE == 0u)) {
        c *= 0.5;
    }
    imageStore(composited, p, vec4(encode_srgb(c), 1.0));
    return;
#endif
    vec3 under = texelFetch(target_color, p, 0).rgb;
    // A tile that lists nothing has no hair: the fine pass left its layer unwritten.
    if (tile_bins[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x].kept == 0u) {
        imageStore(composited, p, vec4(encode_srgb(under), 1.0));
        return;
    }
    vec4 hair = hair_layer[p.y * size.x + p.x];
    imageStore(composited, p, vec4(encode_srgb(hair.rgb + hair.a * under), 1.0));
}
