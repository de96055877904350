// Kajiya–Kay lighting with Scheuermann's two shifted highlights, self-shadowing and a
// root-to-tip colour ramp. The lighting terms are evaluated per strand vertex in the
// geometry stage (or, for strands drawn in compute under the Marschner model, in
// strand_shade.comp) or per fragment; the colour ramp always per fragment, so that it stays
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

// base^layers: the light `layers` hair layers of transmittance `base` (0..1) pass on;
// all of it through none, whatever the base (GLSL leaves pow(0, 0) undefined, and an
// opacity of 1 makes the base 0).
float through(float base, float layers) {
    return layers > 0.0 ? pow(base, layers) : 1.0;
}
vec3 through(vec3 base, float layers) {
    return layers > 0.0 ? pow(base, vec3(layers)) : vec3(1.0);
}
vec4 through(vec4 base, vec4 layers) {
    return mix(vec4(1.0), pow(base, layers), greaterThan(layers, vec4(0.0)));
}

#if TEXTURED
// The model's colour texture (sRGB, with mips), for the fur's roots and the skin.
layout(set = SET_BODY, binding = B_ALBEDO) uniform sampler2D albedo;
#endif

#if SHADOWS
// The fur's depth seen from the light (orthographic, 0 near .. 1 far).
layout(set = SET_FRAME, binding = B_SHADOW_MAP) uniform sampler2D shadow_map;

// The hair layers in front of world point p along the light, at the map's four
// nearest texels, and the bilinear weights `f` between them.
vec4 layers_in_front(vec3 p, out vec2 f) {
    vec4 c = frame.shadow.light_view_proj * vec4(p, 1.0);
    vec2 uv = c.xy * 0.5 + 0.5;
    vec4 front = textureGather(shadow_map, uv, 0);
    f = fract(uv * vec2(textureSize(shadow_map, 0)) - 0.5);
    return min(max(vec4(c.z) - front - frame.shadow.depth_bias, 0.0) * frame.shadow.layers_per_depth, vec4(MAX_LAYERS));
}

// The fraction of the light that reaches world point p through the hair in front of
// it: (1 − α)^(Δz / spacing), bilinearly filtered over the map's four nearest texels.
float light_through_fur(vec3 p) {
    vec2 f;
    vec4 layers = layers_in_front(p, f);
    vec4 light = through(vec4(1.0 - frame.shadow.opacity), layers);
    return mix(mix(light.w, light.z, f.x), mix(light.x, light.y, f.x), f.y);
}

#else
float light_through_fur(vec3 p) {
    return 1.0;
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
    vec3 e = normalize(world - frame.camera.eye);
    vec3 l = frame.lighting.direction;
    float tl = dot(t, l);
    float te = dot(t, e);
    float sin_tl = sqrt(max(1.0 - tl * tl, 0.0));
    float sin_te = sqrt(max(1.0 - te * te, 0.0));
    float diffuse = frame.lighting.kd * sin_tl;
#ifdef FUR_TEST_DIFFUSE
    // Test only: wrong diffuse terms that tests/render.rs must reject (1: Lambert with
    // the tangent as the normal, 2: sin² instead of sin).
    diffuse = frame.lighting.kd * (FUR_TEST_DIFFUSE == 1 ? max(tl, 0.0) : sin_tl * sin_tl);
#endif
    float specular = frame.lighting.ks * lobe(tl, sin_tl, te, sin_te, frame.lighting.primary_shift, frame.lighting.shininess);
    float tinted = 0.0;
    if ((frame.lighting.flags & FLAG_SECONDARY_HIGHLIGHT) != 0u) {
        tinted = frame.lighting.secondary_strength * lobe(tl, sin_tl, te, sin_te, frame.lighting.secondary_shift, frame.lighting.secondary_shininess);
    }
    float direct = frame.lighting.intensity * light;
    return vec3(frame.lighting.ambient + diffuse * direct, specular * direct, tinted * direct);
}

#ifndef MARSCHNER
#define MARSCHNER 0
#endif

// Whether the fragment stage reads the texture's colour at the hair's root from the
// geometry stage: not in the stage views, and not under the Marschner model lit per
// vertex (the geometry stage colours those itself). An output that no stage reads is
// one the validation layer reports.
#if TEXTURED && STAGE_VIEW == 0 && !(MARSCHNER && VERTEX_SHADING)
#define TEXEL_TO_FRAGMENT 1
#else
#define TEXEL_TO_FRAGMENT 0
#endif

#if MARSCHNER
// The Marschner-family fibre model (MARSCHNER = 1; crates/fur-core/src/render/marschner.rs is its CPU
// twin and says where each term comes from): R, TT and TRT lobes with Gaussian
// longitudinal terms on the fibre's roughness and cuticle tilt, Karis 2016's azimuthal
// terms and attenuations, absorption from the colour by Chiang et al.'s mapping;
// multiple scattering between fibres by dual scattering (Zinke et al. 2008) on the
// table of the fibre's averages (render::dual_scattering), through the hair layers in
// front: the shadow map's with SHADOWS, the coat's estimate otherwise (fur.geom's
// coat_layers); and the environment's light through the coat above. frame.fibre: the
// fibre's constants worked out per frame, its cuticle tilt α (radians) and its
// dual-scattering table.
const float PI = 3.14159265;

const float LN_MIN_COLOR = -9.2103404;   // ln 1e-4

// Reflectance at incidence cos θ: Schlick's approximation on F0 = frame.fibre.f0.
float fibre_fresnel(float cos_theta) {
    float f0 = frame.fibre.f0;
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
    vec3 l = clamp(ln_c, vec3(LN_MIN_COLOR), vec3(0.0)) * frame.fibre.colour_scale;
    return l * l;
}

vec3 sigma_a_from_color(vec3 c) {
    return sigma_a_from_log(log_color(c));
}

// One node of the dual-scattering table (render::dual_scattering::table), bilinear
// between the nodes around |sin θ| = u and colour coordinate w = ln c / ln 10⁻⁴ (0
// white, 1 black): [a_f, β_f², Ā_b, Δ_b] and [σ_b², a_b, α, β²].
void fibre_node(float u, float w, out vec4 first, out vec4 second) {
    float x = clamp(u, 0.0, 1.0) * float(DS_ANGLE_NODES - 1);
    float y = clamp(w, 0.0, 1.0) * float(DS_COLOUR_NODES - 1);
    int i = min(int(x), DS_ANGLE_NODES - 2);
    int j = min(int(y), DS_COLOUR_NODES - 2);
    float fx = x - float(i);
    float fy = y - float(j);
    const int N = DS_NODE_VEC4S;
    int a = N * (i * DS_COLOUR_NODES + j);
    int b = a + N * DS_COLOUR_NODES;
    first = mix(mix(frame.fibre.table[a], frame.fibre.table[a + N], fy),
                mix(frame.fibre.table[b], frame.fibre.table[b + N], fy), fx);
    second = mix(mix(frame.fibre.table[a + 1], frame.fibre.table[a + N + 1], fy),
                 mix(frame.fibre.table[b + 1], frame.fibre.table[b + N + 1], fy), fx);
}

// The fibre's averages for light at |sin θ| = u, colour by colour of the colour whose
// logarithm is `ln_c`.
struct FibreAverages {
    vec3 a_f;       // forward-scattered fraction
    vec3 beta_f2;   // its longitudinal variance
    vec3 a_back;    // Ā_b: what the neighbourhood scatters back
    vec3 shift_b;   // Δ_b: its longitudinal shift
    vec3 sigma_b2;  // σ_b²: its longitudinal variance
    vec3 a_b;       // backward-scattered fraction
    vec3 alpha;     // the mean longitudinal shift of all the scattered light
    vec3 beta2;     // its variance
};

FibreAverages fibre_averages(float u, vec3 ln_c) {
    vec3 w = ln_c * (1.0 / LN_MIN_COLOR);
    vec4 r0, r1, g0, g1, b0, b1;
    fibre_node(u, w.r, r0, r1);
    fibre_node(u, w.g, g0, g1);
    fibre_node(u, w.b, b0, b1);
    FibreAverages f;
    f.a_f = vec3(r0.x, g0.x, b0.x);
    f.beta_f2 = vec3(r0.y, g0.y, b0.y);
    f.a_back = vec3(r0.z, g0.z, b0.z);
    f.shift_b = vec3(r0.w, g0.w, b0.w);
    f.sigma_b2 = vec3(r1.x, g1.x, b1.x);
    f.a_b = vec3(r1.y, g1.y, b1.y);
    f.alpha = vec3(r1.z, g1.z, b1.z);
    f.beta2 = vec3(r1.w, g1.w, b1.w);
    return f;
}

// A unit-area Gaussian of variance v at x.
vec3 gaussian(vec3 x, vec3 v) {
    return exp(-0.5 * x * x / v) * inversesqrt(2.0 * PI * v);
}

// What `layers` hair layers in front pass on of the light (dual scattering, Zinke et
// al. 2008, on layers of opacity frame.shadow.opacity): `direct`, the fraction no fibre
// scattered (grey); the return, all that comes through, the forward-scattered part in
// the fibres' colour: each layer passes 1 − α unscattered and α a_f forward.
vec3 light_through_layers(float layers, vec3 a_f, out float direct) {
    float opacity = frame.shadow.opacity;
    direct = through(1.0 - opacity, layers);
    return through(vec3(1.0 - opacity) + opacity * a_f, layers);
}

// Radiance per unit irradiance of a fibre with tangent t at `world`, colour `base` of
// logarithm `ln_c`, behind `layers` hair layers towards the light: its single
// scattering (R, TT, TRT) of the light no fibre in front scattered, and dual
// scattering's multiple scattering — the forward-scattered light through the fibres in
// front (global) and what the fibres around scatter back (local). CPU twin:
// render::marschner::marschner. The per-frame constants come worked out
// (frame.fibre), and each lobe's Gaussian, azimuthal exponential and absorption
// share one exponential per channel.
vec3 marschner_terms(vec3 t, vec3 world, vec3 base, vec3 ln_c, float layers) {
    vec3 v = normalize(frame.camera.eye - world);
    vec3 l = frame.lighting.direction;
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
    float k = frame.fibre.r_exponent;          // −1 / (2 sd²) of the R lobe
    float norm = frame.fibre.r_norm;       // 1 / (√(2π) sd)
    float alpha = frame.fibre.cuticle_tilt;
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
    // The truth benchmark drops one term at a time (render::marschner::Lobes).
    uint flags = frame.lighting.flags;
    float keep_r = (flags & FLAG_NO_R) != 0u ? 0.0 : 1.0;
    float keep_tt = (flags & FLAG_NO_TT) != 0u ? 0.0 : 1.0;
    float keep_trt = (flags & FLAG_NO_TRT) != 0u ? 0.0 : 1.0;
    vec3 single = vec3(keep_r * r) + keep_tt * tt + keep_trt * trt;
    // Dual scattering.
    FibreAverages f = fibre_averages(abs(sin_i), ln_c);
    float direct;
    vec3 arriving = light_through_layers(layers, f.a_f, direct);
    vec3 radiance = direct * single;
    if ((flags & FLAG_NO_MULTIPLE) == 0u) {
        vec3 back = f.a_back * gaussian(vec3(sum) - f.shift_b, f.sigma_b2) * (1.0 / PI);
        vec3 scattered = max(arriving - vec3(direct), 0.0);
        vec3 spread = frame.shadow.opacity * layers * f.beta_f2;
        vec3 global = (f.a_f + f.a_b) * gaussian(vec3(sum) - f.alpha, f.beta2 + spread) * (0.5 / PI);
        vec3 back_spread = f.a_back * gaussian(vec3(sum) - f.shift_b, f.sigma_b2 + spread) * (1.0 / PI);
        radiance += direct * DS_DENSITY_BACKWARD * back
                  + scattered * DS_DENSITY_FORWARD * (global + DS_DENSITY_BACKWARD * back_spread);
    }
    return radiance;
}

// The light of the uniform environment (radiance ambient / Kd, as the export gives the
// path tracer) that a fibre of colour `base` (of logarithm `ln_c`), seen at
// |sin θo| = u_o, sends to the eye from under `above` hair layers. The sky it sees
// through them, (1 − α)^above, lights it as a lone fibre: its whole albedo a_f + a_b of
// the sky above and of the coat's glow below (the coat's colour c), (1 + c) / 2 of the
// light on average. The rest of its light comes from the coat around it, which sends
// back c of it (what Chiang et al.'s colour means: the colour dense fibres of that
// absorption take under uniform light). CPU twin: render::marschner::environment.
vec3 environment(float u_o, vec3 base, vec3 ln_c, float above) {
    FibreAverages f = fibre_averages(u_o, ln_c);
    float sky = through(1.0 - frame.shadow.opacity, above);
    vec3 c = clamp(base, 0.0, 1.0);
    return (frame.lighting.ambient / max(frame.lighting.kd, 1e-6))
         * (sky * 0.5 * (f.a_f + f.a_b) * (1.0 + c) + (1.0 - sky) * c);
}

// The hair layers between world point p and the light, from the shadow map (SHADOWS)
// or the coat's estimate `coat.x` (fur.geom's coat_layers; none with FLAG_NO_COAT).
float layers_towards_light(vec3 p, vec2 coat) {
#if SHADOWS
    vec2 f;
    vec4 layers = layers_in_front(p, f);
    return mix(mix(layers.w, layers.z, f.x), mix(layers.x, layers.y, f.x), f.y);
#else
    return (frame.lighting.flags & FLAG_NO_COAT) != 0u ? 0.0 : max(coat.x, 0.0);
#endif
}

// The hair's radiance: the environment's light plus the fibre's response to the
// light's irradiance (π · intensity, as the export gives it). `coat`: the hair layers
// towards the light and above the point, as the geometry stage estimates them from the
// coat (fur.geom's coat_layers).
vec3 marschner(vec3 t, vec3 world, vec3 base, vec2 coat) {
    vec3 ln_c = log_color(base);
    float layers = layers_towards_light(world, coat);
    float above = (frame.lighting.flags & FLAG_NO_COAT) != 0u ? 0.0 : max(coat.y, 0.0);
    float u_o = abs(dot(t, normalize(frame.camera.eye - world)));
    return environment(u_o, base, ln_c, above)
         + (PI * frame.lighting.intensity) * marschner_terms(t, world, base, ln_c, layers);
}

// The light that comes through the fibres in front of world point p, colour by
// colour (the shadow stage view under the Marschner model).
vec3 light_through_fibres(vec3 t, vec3 p, vec3 base, vec2 coat) {
    FibreAverages f = fibre_averages(abs(dot(t, frame.lighting.direction)), log_color(base));
    float direct;
    return light_through_layers(layers_towards_light(p, coat), f.a_f, direct);
}
#endif

// The hair's base colour `along` (0 at the root, 1 at the tip) of the way. With a
// texture, `texel` (the texture at the root) is the tip's colour and the ramp darkens
// and tints it toward the root as it takes the tip colour to the root colour (by at
// most the ratio of the two, never brighter).
vec3 hair_base(float along, vec3 texel) {
    vec3 base = mix(frame.lighting.root_color, frame.lighting.tip_color, along);
#if TEXTURED
    base = texel * min(base / max(frame.lighting.tip_color, vec3(1e-4)), vec3(1.0));
#endif
    return base;
}

// The colour of a hair with lighting terms `lit`: base colour and root occlusion ramp
// from root to tip; the secondary highlight takes the base colour.
vec3 hair_color(vec3 lit, float along, vec3 texel) {
    vec3 base = hair_base(along, texel);
    float occlusion = mix(1.0 - frame.lighting.root_occlusion, 1.0, along);
    return occlusion * (base * (lit.x + lit.z) + vec3(lit.y));
}

#endif
