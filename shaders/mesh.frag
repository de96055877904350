#version 450
// Mesh (skin) pass: Lambert plus ambient, so gaps in the fur read as dark skin. With a
// texture the skin takes its colour, darkened as the skin colour is to the tip colour;
// with shadows the fur over the skin shades it.
#include "shading.glsl"

layout(location = 0) in vec3 v_normal;
#if SHADOWS
layout(location = 1) in vec3 v_world;
#else
const vec3 v_world = vec3(0.0);
#endif
#if TEXTURED
layout(location = 2) in vec2 v_uv;
#endif
layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(v_normal);
#if STAGE_VIEW == STAGE_DENSITY
    // The density view: grey diagonal stripes, four pixels wide, lit only enough to
    // read the shape. The density pass covers every triangle that gets hairs, so the
    // stripes that show are the triangles the tessellation control stage culled.
    float stripe = mod(floor((gl_FragCoord.x + gl_FragCoord.y) * 0.25), 2.0);
    float shape = 0.6 + 0.4 * abs(dot(n, frame.lighting.direction));
    out_color = vec4(vec3(0.1 + 0.2 * stripe) * shape, 1.0);
    return;
#endif
    float lambert = max(dot(n, frame.lighting.direction), 0.0) * frame.lighting.intensity * light_through_fur(v_world);
    float sky = 1.0;
#if !SHADOWS
    // Under the Marschner model without a shadow map, the coat's estimate: the skin
    // lies under frame.shadow.skin_layers hair layers (its mean height), which the light crosses
    // slanted by its angle to the skin and the sky straight down; each passes 1 − α
    // unscattered. 0 layers otherwise (skin_layers of crates/fur-core/src/render/uniforms.rs).
    float depth = frame.shadow.skin_layers;
    float slant = max(dot(n, frame.lighting.direction), 1e-3);
    lambert *= through(1.0 - frame.shadow.opacity, min(depth / slant, MAX_LAYERS));
    sky = through(1.0 - frame.shadow.opacity, min(depth, MAX_LAYERS));
#endif
    vec3 skin = frame.lighting.skin_color;
#if TEXTURED
    skin = texture(albedo, v_uv).rgb * min(skin / max(frame.lighting.tip_color, vec3(1e-4)), vec3(1.0));
#endif
    out_color = vec4(skin * (frame.lighting.ambient * sky + frame.lighting.kd * lambert), 1.0);
}
