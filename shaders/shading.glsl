// Kajiya–Kay lighting with a root-to-tip colour ramp. The lighting terms are evaluated
// per strand vertex in the geometry stage or per fragment; the colour ramp always per
// fragment, so that it stays exact however few vertices a hair is drawn with.
//   diffuse  = Kd · sin(t, l)
//   specular = Ks · ((t·l)(t·e) + sin(t, l) sin(t, e))^p
// t: unit hair tangent, l: unit vector towards the light, e: unit vector from the eye
// towards the point (with e pointing this way the formula peaks on the mirror cone).
// The CPU copy of this model is `render::kajiya_kay`.
#ifndef SHADING_GLSL
#define SHADING_GLSL

#include "common.glsl"

// x: ambient + diffuse · intensity, y: specular · intensity.
vec2 kajiya_kay(vec3 t, vec3 world) {
    vec3 e = normalize(world - frame.eye.xyz);
    vec3 l = frame.light.xyz;
    float tl = dot(t, l);
    float te = dot(t, e);
    float sin_tl = sqrt(max(1.0 - tl * tl, 0.0));
    float sin_te = sqrt(max(1.0 - te * te, 0.0));
    float diffuse = frame.shading.x * sin_tl;
    float specular = frame.shading.y * pow(max(tl * te + sin_tl * sin_te, 0.0), frame.shading.z);
    return vec2(frame.shading.w + diffuse * frame.light.w, specular * frame.light.w);
}

// The colour of a hair `along` (0 at the root, 1 at the tip) of the way with lighting
// terms `lit`: base colour and root occlusion ramp from root to tip.
vec3 hair_color(vec2 lit, float along) {
    vec3 base = mix(frame.root_color.rgb, frame.tip_color.rgb, along);
    float occlusion = mix(1.0 - frame.root_color.w, 1.0, along);
    return occlusion * (base * lit.x + vec3(lit.y));
}

#endif
