// Sampling the body's signed distance field (crates/fur-core/src/geometry/sdf.rs), included by
// simulate.comp after sim_common.glsl: the grid, its cell and its origin are in `sim`.
#ifndef SDF_SAMPLE_GLSL
#define SDF_SAMPLE_GLSL

// The distance at model-space point m to first order from its nearest grid point, and
// the gradient there; false outside the grid. The arithmetic, step by step, is
// `Sdf::sample` in crates/fur-core/src/geometry/sdf.rs.
bool sdf_sample(vec3 m, out float value, out vec3 gradient) {
    vec3 g = (m - sim.sdf_origin) * sim.inverse_cell;
    vec3 last = vec3(sim.sdf_dims - 1u);
    if (!(all(greaterThanEqual(g, vec3(0.0))) && all(lessThanEqual(g, last)))) {
        return false;
    }
    uvec3 c = uvec3(floor(g + 0.5));
    vec3 offset = (g - vec3(c)) * sim.cell;
    vec4 s = imageLoad(sdf, ivec3(c));
    gradient = s.yzw;
    value = s.x + (s.y * offset.x + s.z * offset.y + s.w * offset.z);
    return true;
}

// The distance and gradient at model-space point m: the trilinear blend of the eight
// grid points' first-order expansions at m, and of their gradients (continuous across
// cells, never above the distance where the field is convex); false outside the grid.
// `Sdf::sample_trilinear` in crates/fur-core/src/geometry/sdf.rs, step by step.
bool sdf_sample_trilinear(vec3 m, out float value, out vec3 gradient) {
    vec3 g = (m - sim.sdf_origin) * sim.inverse_cell;
    vec3 last = vec3(sim.sdf_dims - 1u);
    if (!(all(greaterThanEqual(g, vec3(0.0))) && all(lessThanEqual(g, last)))) {
        return false;
    }
    uvec3 base = min(uvec3(floor(g)), sim.sdf_dims - 2u);
    vec3 f = g - vec3(base);
    value = 0.0;
    gradient = vec3(0.0);
    for (uint corner = 0u; corner < 8u; ++corner) {
        uvec3 offset = uvec3(corner & 1u, (corner >> 1u) & 1u, (corner >> 2u) & 1u);
        vec3 w3 = mix(vec3(1.0) - f, f, bvec3(offset));
        float w = w3.x * w3.y * w3.z;
        uvec3 c = base + offset;
        vec4 s = imageLoad(sdf, ivec3(c));
        // This grid point's first-order expansion at m.
        vec3 o = (f - vec3(offset)) * sim.cell;
        value = value + w * (s.x + (s.y * o.x + s.z * o.y + s.w * o.z));
        gradient = gradient + s.yzw * w;
    }
    return true;
}

#endif
