#version 450
// Fur pass, fragment stage: Kajiya–Kay lighting with a root-to-tip colour ramp.
//   diffuse  = Kd · sin(t, l)
//   specular = Ks · ((t·l)(t·e) + sin(t, l) sin(t, e))^p
// t: unit hair tangent, l: unit vector towards the light, e: unit vector from the eye
// towards the fragment (with e pointing this way the formula peaks on the mirror cone).
// The CPU copy of this model is `render::kajiya_kay`.
#include "common.glsl"

layout(location = 0) in vec4 g_tangent_along;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 t = normalize(g_tangent_along.xyz);
    float along = g_tangent_along.w;
    vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
    vec4 world = frame.inv_view_proj * vec4(ndc, gl_FragCoord.z, 1.0);
    vec3 e = normalize(world.xyz / world.w - frame.eye.xyz);
    vec3 l = frame.light.xyz;

    float tl = dot(t, l);
    float te = dot(t, e);
    float sin_tl = sqrt(max(1.0 - tl * tl, 0.0));
    float sin_te = sqrt(max(1.0 - te * te, 0.0));
    float diffuse = frame.shading.x * sin_tl;
    float specular = frame.shading.y * pow(max(tl * te + sin_tl * sin_te, 0.0), frame.shading.z);

    vec3 base = mix(frame.root_color.rgb, frame.tip_color.rgb, along);
    float occlusion = mix(1.0 - frame.root_color.w, 1.0, along);
    vec3 color = base * occlusion * (frame.shading.w + diffuse * frame.light.w)
               + vec3(specular * frame.light.w) * occlusion;
    out_color = vec4(color, 1.0);
}
