// Kajiya–Kay lighting with Scheuermann's two shifted highlights, self-shadowing and a
// root-to-tip colour ramp. The lighting terms are evaluated per strand vertex in the
// geometry stage or per fragment; the colour ramp always per fragment, so that it stays
// exact however few vertices a hair is drawn with.
//   diffuse  = Kd · sin(t, l)
//   lobe(β)  = cos(θl + β − θe)^p = ((t·l) cos β − sin(t,l) sin β)(t·e)
//              + (sin(t,l) cos β + (t·l) sin β) sin(t,e), clamped at 0, to the p
//   specular = Ks · lobe(β1, p)            (white; β1 = 0 without the secondary lobe)
//   tinted   = Ks2 · lobe(β2, p2)          (times the hair colour; secondary on only)
// t: unit hair tangent, l: unit vector towards the light, e: unit vector from the eye
// towards the point (with e pointing this way a lobe peaks on the mirror cone; a
// positive shift moves it toward the tip). The CPU copy of this model is
// `render::kajiya_kay`.
#ifndef SHADING_GLSL
#define SHADING_GLSL

#include "common.glsl"

#if TEXTURED
// The model's colour texture (sRGB, with mips), for the fur's roots and the skin.
layout(set = SET_BODY, binding = B_ALBEDO) uniform sampler2D albedo;
#endif

// The fraction of the light, colour by colour, one hair layer lets through: of the
// light the layer intercepts (α, frame.shadow.x), the part its fibres of absorption
// sigma_a pass on forward — transmitted through two interfaces and absorbed along a path
// of two radii, (1 − F0)² e^(−2σa) — goes on (dual scattering's forward-scattering
// transmittance, Zinke et al. 2008), with FLAG_COLOURED_SHADOWS; otherwise 1 − α, grey.
vec3 through_one_layer(vec3 sigma_a) {
    float f0 = frame.fibre_terms.z;
    vec3 forward = (1.0 - f0) * (1.0 - f0) * exp(-2.0 * sigma_a);
    if ((frame.strands.w & FLAG_COLOURED_SHADOWS) == 0u) {
        forward = vec3(0.0);
    }
    return vec3(1.0 - frame.shadow.x) + frame.shadow.x * forward;
}

#if SHADOWS
// The fur's depth seen from the light (orthographic, 0 near .. 1 far).
layout(set = SET_FRAME, binding = B_SHADOW_MAP) uniform sampler2D shadow_map;

// The hair layers in front of world point p along the light, at the map's four
// nearest texels, and the bilinear weights `f` between them.
vec4 layers_in_front(vec3 p, out vec2 f) {
    vec4 c = frame.light_view_proj * vec4(p, 1.0);
    vec2 uv = c.xy * 0.5 + 0.5;
    vec4 front = textureGather(shadow_map, uv, 0);
    f = fract(uv * vec2(textureSize(shadow_map, 0)) - 0.5);
    return min(max(vec4(c.z) - front - frame.shadow.z, 0.0) * frame.shadow.y, vec4(MAX_LAYERS));
}

// The fraction of the light that reaches world point p through the hair in front of
// it: (1 − α)^(Δz / spacing), bilinearly filtered over the map's four nearest texels.
float light_through_fur(vec3 p) {
    vec2 f;
    vec4 layers = layers_in_front(p, f);
    vec4 light = pow(vec4(1.0 - frame.shadow.x), layers);
    return mix(mix(light.w, light.z, f.x), mix(light.x, light.y, f.x), f.y);
}

// The same through fibres of absorption sigma_a, colour by colour, one layer's
// transmittance (through_one_layer) to the power of the layers in front: light reddens
// and deepens through light fur with FLAG_COLOURED_SHADOWS (`[shadows] coloured`).
// CPU twin: render::marschner::light_through_fibres.
vec3 light_through_fibres(vec3 p, vec3 sigma_a) {
    vec2 f;
    vec4 layers = layers_in_front(p, f);
    vec3 through = through_one_layer(sigma_a);
    vec3 a = pow(through, vec3(layers.x));
    vec3 b = pow(through, vec3(layers.y));
    vec3 c = pow(through, vec3(layers.z));
    vec3 d = pow(through, vec3(layers.w));
    return mix(mix(d, c, f.x), mix(a, b, f.x), f.y);
}
#else
float light_through_fur(vec3 p) {
    return 1.0;
}

vec3 light_through_fibres(vec3 p, vec3 sigma_a) {
    return vec3(1.0);
}
#endif

float lobe(float tl, float sin_tl, float te, float sin_te, vec2 cos_sin, float p) {
    float c = tl * cos_sin.x - sin_tl * cos_sin.y;
    float s = sin_tl * cos_sin.x + tl * cos_sin.y;
    return pow(max(c * te + s * sin_te, 0.0), p);
}

// x: ambient + diffuse, y: white specular, z: tinted specular; the direct terms scaled
// by the light's intensity and `light`, the fraction of it that reaches the point.
vec3 kajiya_kay(vec3 t, vec3 world, float light) {
    vec3 e = normalize(world - frame.eye.xyz);
    vec3 l = frame.light.xyz;
    float tl = dot(t, l);
    float te = dot(t, e);
    float sin_tl = sqrt(max(1.0 - tl * tl, 0.0));
    float sin_te = sqrt(max(1.0 - te * te, 0.0));
    float diffuse = frame.shading.x * sin_tl;
#ifdef FUR_TEST_DIFFUSE
    // Test only: wrong diffuse terms that tests/render.rs must reject (1: Lambert with
    // the tangent as the normal, 2: sin² instead of sin).
    diffuse = frame.shading.x * (FUR_TEST_DIFFUSE == 1 ? max(tl, 0.0) : sin_tl * sin_tl);
#endif
    float specular = frame.shading.y * lobe(tl, sin_tl, te, sin_te, frame.highlight.xy, frame.shading.z);
    float tinted = 0.0;
    if ((frame.strands.w & FLAG_SECONDARY_HIGHLIGHT) != 0u) {
        tinted = frame.secondary.y * lobe(tl, sin_tl, te, sin_te, frame.highlight.zw, frame.secondary.x);
    }
    float direct = frame.light.w * light;
    return vec3(frame.shading.w + diffuse * direct, specular * direct, tinted * direct);
}

#ifndef MARSCHNER
#define MARSCHNER 0
#endif

#if MARSCHNER
// The Marschner-family fibre model (MARSCHNER = 1; crates/fur-core/src/render/marschner.rs is its CPU
// twin and says where each term comes from): R, TT and TRT lobes with Gaussian
// longitudinal terms on the fibre's roughness and cuticle tilt, Karis 2016's azimuthal
// terms and attenuations, absorption from the colour by Chiang et al.'s mapping, and
// Karis's approximation of multiple scattering, the light through the fur in front in
// the fibres' colour: the shadow map's layers with SHADOWS, the coat's estimate
// otherwise (fur.geom's coat_layers). frame.fibre: β_m, β_n, α (radians), η.
const float PI = 3.14159265;

const float LN_MIN_COLOR = -9.2103404;   // ln 1e-4

// Reflectance at incidence cos θ: Schlick's approximation on F0 = frame.fibre_terms.z.
float fibre_fresnel(float cos_theta) {
    float f0 = frame.fibre_terms.z;
    float m = 1.0 - clamp(cos_theta, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// ln c of a colour (of 1e-30 for black: the exponentials of it vanish).
vec3 log_color(vec3 c) {
    return log(max(c, vec3(1e-30)));
}

// Chiang et al.'s absorption for a colour of logarithm `ln_c` (log_color), the colour
// clamped to [1e-4, 1] (in the logarithm: the same clamp) as the mapping clamps it.
vec3 sigma_a_from_log(vec3 ln_c) {
    vec3 l = clamp(ln_c, vec3(LN_MIN_COLOR), vec3(0.0)) * frame.fibre_terms.w;
    return l * l;
}

vec3 sigma_a_from_color(vec3 c) {
    return sigma_a_from_log(log_color(c));
}

// Radiance per unit irradiance of a fibre with tangent t at `world`, colour `base` of
// absorption `sigma_a`, `light` the fraction of the light that reaches it, colour by
// colour. The per-frame constants come worked out (frame.fibre_terms), and each lobe's
// Gaussian, azimuthal exponential and absorption share one exponential per channel.
vec3 marschner_terms(vec3 t, vec3 world, vec3 base, vec3 ln_c, vec3 light) {
    vec3 v = normalize(frame.eye.xyz - world);
    vec3 l = frame.light.xyz;
    float sin_i = clamp(dot(t, l), -1.0, 1.0);
    float sin_o = clamp(dot(t, v), -1.0, 1.0);
    float theta_i = asin(sin_i);
    float theta_o = asin(sin_o);
    float cos_d = cos(0.5 * (theta_o - theta_i));
    float inv_cos_d = 1.0 / cos_d;
    vec3 lp = l - sin_i * t;
    vec3 vp = v - sin_o * t;
    float cos_phi = dot(lp, vp) * inversesqrt(dot(lp, lp) * dot(vp, vp) + 1e-4);
    float cos_half_phi = sqrt(clamp(0.5 + 0.5 * cos_phi, 0.0, 1.0));
    vec3 sigma_a = sigma_a_from_log(ln_c);
    float k = frame.fibre_terms.x;          // −1 / (2 sd²) of the R lobe
    float norm = frame.fibre_terms.y;       // 1 / (√(2π) sd)
    float alpha = frame.fibre.z;
    float sum = theta_i + theta_o;
    // R: a Gaussian of width sd.
    float x_r = sum - 2.0 * alpha;
    float r = norm * exp(k * x_r * x_r) * 0.25 * cos_half_phi
            * fibre_fresnel(sqrt(clamp(0.5 + 0.5 * dot(l, v), 0.0, 1.0)));
    // TT: a Gaussian of width sd / 2.
    float a = 1.0 / (1.19 * inv_cos_d + 0.36 * cos_d);
    float h = cos_half_phi * (1.0 + a * (0.6 - 0.8 * cos_phi));
    float f_tt = fibre_fresnel(cos_d * sqrt(clamp(1.0 - h * h, 0.0, 1.0)));
    float x_tt = sum + alpha;
    float path_tt = 2.0 * sqrt(clamp(1.0 - (h * a) * (h * a), 0.0, 1.0)) * inv_cos_d;
    vec3 tt = exp(-sigma_a * path_tt + (4.0 * k * x_tt * x_tt - 3.65 * cos_phi - 3.98))
            * (2.0 * norm * (1.0 - f_tt) * (1.0 - f_tt));
    // TRT: a Gaussian of width 2 sd.
    float f_trt = fibre_fresnel(0.5 * cos_d);
    float x_trt = sum + 4.0 * alpha;
    vec3 trt = exp(-sigma_a * (3.2 * inv_cos_d) + (0.25 * k * x_trt * x_trt + 17.0 * cos_phi - 16.78))
             * (0.5 * norm * (1.0 - f_trt) * (1.0 - f_trt) * f_trt);
    // Multiple scattering (Karis 2016)
    float kajiya = 1.0 - abs(dot(t, l));
    vec3 fake_normal = v - t * dot(v, t);
    float fn = length(fake_normal);
    fake_normal = fn > 0.0 ? fake_normal / fn : vec3(0.0);
    float wrap = clamp((dot(fake_normal, l) + 1.0) / 4.0, 0.0, 1.0);
    float diffuse = (wrap + (kajiya - wrap) * 0.33) / PI;
    // √c · (c / luma)^(1 − light) as one exponential of ln c.
    float ln_luma = log(max(dot(base, vec3(0.2126, 0.7152, 0.0722)), 1e-4));
    vec3 multiple = exp(0.5 * ln_c + (1.0 - light) * (ln_c - ln_luma)) * (diffuse * light);
    // The truth benchmark drops one term at a time (render::marschner::Lobes).
    uint flags = frame.strands.w;
    float keep_r = (flags & FLAG_NO_R) != 0u ? 0.0 : 1.0;
    float keep_tt = (flags & FLAG_NO_TT) != 0u ? 0.0 : 1.0;
    float keep_trt = (flags & FLAG_NO_TRT) != 0u ? 0.0 : 1.0;
    float keep_multiple = (flags & FLAG_NO_MULTIPLE) != 0u ? 0.0 : 1.0;
    return (vec3(keep_r * r) + keep_tt * tt + keep_trt * trt) * light + keep_multiple * multiple;
}

// The hair's radiance before root occlusion: the ambient term on the colour plus the
// fibre's response to the light's irradiance (π · intensity, as the export gives it),
// the light coming through the fibres in front in their colour.
// `coat`: without a shadow map, the hair layers between the point and the light as the
// geometry stage estimates them from the coat (fur.geom's coat_layers).
vec3 marschner(vec3 t, vec3 world, vec3 base, float coat) {
    vec3 ln_c = log_color(base);
    vec3 sigma_a = sigma_a_from_log(ln_c);
#if SHADOWS
    vec3 light = light_through_fibres(world, sigma_a);
#else
    bool lit = coat <= 0.0 || (frame.strands.w & FLAG_NO_COAT) != 0u;
    vec3 light = lit ? vec3(1.0) : pow(through_one_layer(sigma_a), vec3(coat));
#endif
    return frame.shading.w * base + (PI * frame.light.w) * marschner_terms(t, world, base, ln_c, light);
}
#endif

// The hair's base colour `along` (0 at the root, 1 at the tip) of the way. With a
// texture, `texel` (the texture at the root) is the tip's colour and the ramp darkens
// and tints it toward the root as it takes the tip colour to the root colour (by at
// most the ratio of the two, never brighter).
vec3 hair_base(float along, vec3 texel) {
    vec3 base = mix(frame.root_color.rgb, frame.tip_color.rgb, along);
#if TEXTURED
    base = texel * min(base / max(frame.tip_color.rgb, vec3(1e-4)), vec3(1.0));
#endif
    return base;
}

// The colour of a hair with lighting terms `lit`: base colour and root occlusion ramp
// from root to tip; the secondary highlight takes the base colour.
vec3 hair_color(vec3 lit, float along, vec3 texel) {
    vec3 base = hair_base(along, texel);
    float occlusion = mix(1.0 - frame.root_color.w, 1.0, along);
    return occlusion * (base * (lit.x + lit.z) + vec3(lit.y));
}

#endif
