#version 450
// The skinning pass: linear blend skinning of the body's vertices, and one rigid root
// pose per master strand, for every substep of one simulated frame (crates/fur-core/src/skinning/cpu.rs
// is the CPU twin, with the same arithmetic in the same order).
//
// Per vertex v and substep k, with the joints' skinning matrices J of that substep:
//   M = w₀ J[j₀] + w₁ J[j₁] + w₂ J[j₂] + w₃ J[j₃]
//   p = M (p_bind, 1),  n = normalize(mat3(M) n_bind),  t = normalize(mat3(M) t_bind)
//   F = [t⊥, n × t⊥, n] with t⊥ = normalize(t − n (n·t)),  R = F F_restᵀ
// The strand grown from v maps rest point x to R (x − r) + p (r: its rest root), so
// its root lands on the skinned vertex exactly and its shape turns rigidly.
// The last substep's positions and normals are the posed body the mesh pass draws.

layout(local_size_x = GROUP_SIZE) in;   // crates/fur-gpu/src/gpu/shader.rs

// The binding numbers are defines from crates/fur-gpu/src/skinning/gpu.rs
// (`SkinBinding`), never typed here.
#ifndef KB_POSED
#error "the skinning kernel is compiled with its bindings' defines (crates/fur-gpu/src/skinning/gpu.rs)"
#endif

// Every table but the posed body is a texel buffer: a CPU driver reads and writes one
// at lane-varying indices in one gather or scatter, a storage buffer lane by lane.
layout(set = 0, binding = KB_BIND_VERTICES, rgba32f) uniform readonly imageBuffer bind_vertices;  // per vertex: position, normal, tangent
layout(set = 0, binding = KB_INFLUENCES, rgba32ui) uniform readonly uimageBuffer influences;
layout(set = 0, binding = KB_WEIGHTS, rgba32f) uniform readonly imageBuffer weights;
layout(set = 0, binding = KB_REST_FRAMES, rgba32f) uniform readonly imageBuffer rest_frames;    // per vertex: rest tangent, rest normal
// Per substep of the submission, every joint's matrix, column after column.
layout(set = 0, binding = KB_JOINTS, rgba32f) uniform readonly imageBuffer joints;
layout(set = 0, binding = KB_POSED, std430) writeonly buffer Posed {
    vec4 posed[];           // per vertex: position, normal (the last substep)
};
// Per substep of the dispatch and strand: R's columns, p in w.
layout(set = 0, binding = KB_ROOT_POSES, rgba32f) uniform writeonly imageBuffer root_poses;

layout(push_constant) uniform Push {
    uint first_step;    // the submission's substep of this dispatch's first substep
    uint count;         // substeps in this dispatch
    uint vertex_count;
    uint joint_count;
} push;

mat4 joint(uint i) {
    int c = 4 * int(i);
    return mat4(imageLoad(joints, c), imageLoad(joints, c + 1), imageLoad(joints, c + 2),
                imageLoad(joints, c + 3));
}

void main() {
    uint v = gl_GlobalInvocationID.x;
    if (v >= push.vertex_count) {
        return;
    }
    int b = 3 * int(v);
    vec3 bind_p = imageLoad(bind_vertices, b).xyz;
    vec3 bind_n = imageLoad(bind_vertices, b + 1).xyz;
    vec3 bind_t = imageLoad(bind_vertices, b + 2).xyz;
    uvec4 j = imageLoad(influences, int(v));
    vec4 w = imageLoad(weights, int(v));
    vec3 rt = imageLoad(rest_frames, 2 * int(v)).xyz;
    vec3 rn = imageLoad(rest_frames, 2 * int(v) + 1).xyz;
    mat3 rest = mat3(rt, cross(rn, rt), rn);
    for (uint k = 0u; k < push.count; ++k) {
        uint base = (push.first_step + k) * push.joint_count;
        mat4 m = joint(base + j.x) * w.x + joint(base + j.y) * w.y + joint(base + j.z) * w.z
               + joint(base + j.w) * w.w;
        vec3 p = (m * vec4(bind_p, 1.0)).xyz;
        vec3 n = normalize(mat3(m) * bind_n);
        vec3 t = normalize(mat3(m) * bind_t);
        vec3 tp = normalize(t - n * dot(n, t));
        mat3 r = mat3(tp, cross(n, tp), n) * transpose(rest);
        uint o = 3u * (k * push.vertex_count + v);
        imageStore(root_poses, int(o), vec4(r[0], p.x));
        imageStore(root_poses, int(o + 1u), vec4(r[1], p.y));
        imageStore(root_poses, int(o + 2u), vec4(r[2], p.z));
        if (k + 1u == push.count) {
            posed[2u * v] = vec4(p, 1.0);
            posed[2u * v + 1u] = vec4(n, 0.0);
        }
    }
}
