#version 450
// Fur pass, tessellation control: how many interpolated hairs this triangle gets.
//
// Hairs per unit area at full density is `frame.drawing.density`; beyond the full-density
// distance D = frame.drawing.lod_distance the density falls with the square of the distance, so
// hairs per pixel stay roughly constant:  lod(d) = min(1, (D / d)²).
// An edge of length L gets outer level ceil(L · sqrt(density · lod)): the hair spacing
// along it. The inner level n is chosen so the ~3n²/4 points of a triangle with area A
// match A · density · lod:  n = ceil(sqrt(4/3 · A · density · lod)).
// Levels are clamped to [1, device max]. Back-facing triangles (by more than the cull
// margin) and triangles whose master hairs are all outside one clip plane get level 0
// and cost nothing further. Edge levels depend only on the edge, so both triangles
// sharing it generate the same points there (the owner draws them, see fur.tese).
// A skinned body's lengths and areas are its rest pose's (BODY_SKINNED), so a bending
// joint never adds or drops hairs. A triangle whose three master hairs are bald stubs
// (a groom's bald region: tip within frame.strands.stub_length of the root) draws nothing either.
// A degenerate patch (h, h, h) is a drawn groom's guide: level 1, one hair, the master.
#include "common.glsl"

layout(vertices = 3) out;

#if BODY_SKINNED
// Per triangle of the rest pose: edge lengths opposite corners 0, 1, 2 and the area. A
// skinned body's triangles stretch as its joints bend; its hair count must not follow.
layout(set = SET_BODY, binding = B_REST_TRIANGLES, std430) readonly buffer RestTriangles {
    vec4 rest_triangles[];
};
#endif

layout(location = 0) in uint v_hair[];
layout(location = 1) in uint v_triangle[];
layout(location = 0) out uint c_hair[];
layout(location = 1) patch out uint p_mask;
#if TEXTURED
layout(location = 2) patch out uint p_triangle;   // this patch's triangle (see fur.vert)
#endif

float edge_level(vec3 a, vec3 b, float len) {
    float spacing_inv = sqrt(frame.drawing.density * lod_factor((a + b) * 0.5));
    return clamp(ceil(len * spacing_inv), 1.0, frame.drawing.max_level);
}

// True when every master-hair vertex of the patch lies outside one clip plane.
bool outside_view(uint h0, uint h1, uint h2) {
    uint V = frame.strands.vertices_per_strand;
    uint all_out = 0x3fu;
    for (uint k = 0u; k < V; ++k) {
        uint hairs[3] = uint[3](h0, h1, h2);
        for (int j = 0; j < 3; ++j) {
            vec4 c = frame.camera.view_proj * vec4(strand_vertex(hairs[j], k), 1.0);
            float w = abs(c.w) * 1.05 + 1e-6;
            uint code = 0u;
            code |= c.x < -w ? 1u : 0u;
            code |= c.x > w ? 2u : 0u;
            code |= c.y < -w ? 4u : 0u;
            code |= c.y > w ? 8u : 0u;
            code |= c.z < 0.0 ? 16u : 0u;
            code |= c.z > c.w ? 32u : 0u;
            all_out &= code;
        }
        if (all_out == 0u) {
            return false;
        }
    }
    return true;
}

void main() {
    c_hair[gl_InvocationID] = v_hair[gl_InvocationID];
    if (gl_InvocationID != 0) {
        return;
    }
    uint h0 = v_hair[0], h1 = v_hair[1], h2 = v_hair[2];
    uint triangle = v_triangle[0];
#if TEXTURED
    p_triangle = triangle;
#endif
    p_mask = owner_mask[triangle];

    if (h0 == h1 && h1 == h2) {
        // A drawn groom's guide (fur_core::scene::DrawnGroom): a degenerate patch whose
        // one hair is its master, the point at its first corner (the only part it owns).
        // Level 1 makes just the corners, whatever the fixed level; culled only when
        // the master is out of view.
        bool unseen = (frame.drawing.flags & FLAG_CULL) != 0u && outside_view(h0, h0, h0);
        float l = unseen ? 0.0 : 1.0;
        gl_TessLevelOuter[0] = l;
        gl_TessLevelOuter[1] = l;
        gl_TessLevelOuter[2] = l;
        gl_TessLevelInner[0] = l;
        return;
    }

    uint fixed_level = frame.drawing.fixed_level;
    if (fixed_level > 0u) {
        float l = float(fixed_level);
        gl_TessLevelOuter[0] = l;
        gl_TessLevelOuter[1] = l;
        gl_TessLevelOuter[2] = l;
        gl_TessLevelInner[0] = l;
        return;
    }

    uint V = frame.strands.vertices_per_strand;
    vec3 r0 = strand_vertex(h0, 0u), r1 = strand_vertex(h1, 0u), r2 = strand_vertex(h2, 0u);
    vec3 t0 = strand_vertex(h0, V - 1u), t1 = strand_vertex(h1, V - 1u), t2 = strand_vertex(h2, V - 1u);
    float stub = frame.strands.stub_length;
    if (distance(t0, r0) < stub && distance(t1, r1) < stub && distance(t2, r2) < stub) {
        gl_TessLevelOuter[0] = 0.0;
        gl_TessLevelOuter[1] = 0.0;
        gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        return;
    }
    bool culled = false;
    if ((frame.drawing.flags & FLAG_CULL) != 0u) {
        vec3 growth = t0 + t1 + t2 - (r0 + r1 + r2);
        vec3 n = cross(r1 - r0, r2 - r0);
        n *= dot(n, growth) < 0.0 ? -1.0 : 1.0;   // orient along the fur, whatever the winding
        vec3 to_eye = frame.camera.eye - (r0 + r1 + r2) / 3.0;
        float facing = dot(normalize(n), normalize(to_eye));
        culled = facing < -frame.drawing.cull_margin || outside_view(h0, h1, h2);
    }
    if (culled) {
#if COUNT_HAIRS
        if ((frame.drawing.flags & FLAG_COUNT) != 0u) {
            atomicAdd(counters.triangles_culled, 1u);
        }
#endif
        gl_TessLevelOuter[0] = 0.0;
        gl_TessLevelOuter[1] = 0.0;
        gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        return;
    }
#if BODY_SKINNED
    vec4 rest = rest_triangles[triangle];
    vec3 lengths = rest.xyz;
    float area = rest.w;
#else
    vec3 lengths = vec3(distance(r1, r2), distance(r2, r0), distance(r0, r1));
    float area = 0.5 * length(cross(r1 - r0, r2 - r0));
#endif
    gl_TessLevelOuter[0] = edge_level(r1, r2, lengths.x);
    gl_TessLevelOuter[1] = edge_level(r2, r0, lengths.y);
    gl_TessLevelOuter[2] = edge_level(r0, r1, lengths.z);
    float hairs = area * frame.drawing.density * lod_factor((r0 + r1 + r2) / 3.0);
    gl_TessLevelInner[0] = clamp(ceil(sqrt(hairs * 4.0 / 3.0)), 1.0, frame.drawing.max_level);
}
