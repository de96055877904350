// Declarations shared by the simulation kernels. The bindings and the SimStatic and
// Step layouts are checked against crates/fur-gpu/src/sim/kernel.rs by its test (SPIR-V reflection);
// the constants shared with Rust are defined from it (crates/fur-gpu/src/sim/kernel.rs: kernel_defines).
//
// One invocation per master strand; GROUP_SIZE strands per workgroup.
#ifndef SIM_COMMON_GLSL
#define SIM_COMMON_GLSL

#include "strands.glsl"

// The set's binding numbers are defines from crates/fur-gpu/src/sim/kernel.rs
// (`SimBinding`), never typed here.
#ifndef SB_STATIC
#error "the simulation kernels are compiled with kernel_defines() (crates/fur-gpu/src/sim/kernel.rs)"
#endif

layout(constant_id = 1) const uint V = 17u;   // vertices per strand
layout(local_size_x = GROUP_SIZE) in;         // strands per workgroup (crates/fur-gpu/src/gpu/shader.rs)

layout(set = 0, binding = SB_STATIC, std140) uniform SimStatic {
    float global_stiffness;  // S_G
    float local_stiffness;   // S_L
    float collision_margin;  // a fraction of each strand's length
    float friction;
    uint strand_count;
    uint strands_per_row;
    uint global_cutoff;      // the last vertex the global shape constraint pulls
    uint local_iterations;
    uint length_iterations;
    uint capsule_count;      // the bones' capsules
    uint joint_count;
    uint probe_step;         // the step the probe records (its STEPS bit; 0 none)
    vec3 sdf_origin;         // model-space position of grid point (0, 0, 0)
    float cell;              // the grid's spacing
    uvec3 sdf_dims;          // grid points along x, y, z
    float inverse_cell;
} sim;

// Per-substep constants, written by the CPU before submission (StepConstants).
struct Step {
    mat4 head;          // H: model to world
    mat4 head_inverse;  // H⁻¹: world to model
    vec4 gravity_h2;    // xyz = g h², w = velocity retention
    vec4 wind_h2[4];    // W1..W4 scaled by magnitude and h²
};
layout(set = 0, binding = SB_STEPS, std430) readonly buffer Steps {
    Step steps[];
};

// Rest data: written once by simulate_rest.comp (which defines REST_ACCESS as empty),
// read-only for the simulation steps.
#ifndef REST_ACCESS
#define REST_ACCESS readonly
#endif
layout(set = 0, binding = SB_REST_POSITIONS, rgba32f) uniform REST_ACCESS image2D rest_positions;  // model space, w = rest length
layout(set = 0, binding = SB_REST_LOCAL, rgba32f) uniform REST_ACCESS image2D rest_local;      // segment i in frame i
layout(set = 0, binding = SB_ROOT_FRAMES, std430) REST_ACCESS buffer RootFrames {
    vec4 root_frames[];   // 3 columns per strand
};
layout(set = 0, binding = SB_PREVIOUS_POSITIONS, rgba32f) uniform image2D previous_positions;
layout(set = 0, binding = SB_CURRENT_POSITIONS, rgba32f) uniform image2D current_positions;
// The body's signed distance field (crates/fur-core/src/sim/sdf.rs, on the device crates/fur-gpu/src/sim/field.rs):
// per grid point, the distance and the field's gradient there. An image, not a buffer:
// a CPU driver reads an image at lane-varying points in one gather.
layout(set = 0, binding = SB_SDF, rgba32f) uniform readonly image3D sdf;

// A skinned body's root pose of every strand for each substep of this dispatch
// (shaders/skin.comp): R's columns, with the skinned root in their w.
layout(set = 0, binding = SB_ROOT_POSES, rgba32f) uniform readonly imageBuffer root_poses;

// A skinned body's bone capsules at the bind pose, then for each substep of the
// submission: (a, radius), (b, the child bone's capsule or −1) in model space,
// sim.capsule_count of them per pose (crates/fur-core/src/skinning/capsules.rs). A texel buffer, not a
// storage buffer: a CPU driver reads it in one gather (crates/fur-gpu/src/gpu/buffer.rs).
layout(set = 0, binding = SB_CAPSULES, rgba32f) uniform readonly imageBuffer capsules;

vec4 capsule(uint i) {
    return imageLoad(capsules, int(i));
}

// Per strand, its root pose after the last substep simulated (R's columns, the root in
// w), so the next substep can carry the strand along with the body.
layout(set = 0, binding = SB_LAST_POSES, rgba32f) uniform imageBuffer last_poses;

// A skinned body's blend of bones at each grid point of the field (crates/fur-core/src/skinning/blend.rs):
// two grid points along x per texel, each the heaviest and second heaviest joint's
// indices (16-bit halves of one word) and the heaviest's share of their weights (f32
// bits); all zero where no skin is near.
layout(set = 0, binding = SB_BLEND, rgba32ui) uniform readonly uimage3D blend;

// Per substep of the submission and joint, the joint's motion from the rest pose: the
// first three rows of K = J · J_rest⁻¹; sim.joint_count joints per substep.
layout(set = 0, binding = SB_BONES, rgba32f) uniform readonly imageBuffer bones;

// The simulation view's arrows (PROBE): per strand vertex, strand-major, the
// correction the step sim.probe_step made in the frame's last substep.
layout(set = 0, binding = SB_PROBE, std430) writeonly buffer Probe {
    vec4 arrows[];
};

layout(push_constant) uniform Push {
    uint step;          // index into steps[] of the first substep
    uint count;         // substeps in this dispatch
    uint place;         // 1: put every strand at its posed rest shape, at rest
} push;


// The rotation taking the x axis to unit u along the shortest arc (crates/fur-core/src/sim/cpu.rs).
mat3 rotation_from_x(vec3 u) {
    float c = u.x;
    if (c < -0.9999) {
        return mat3(vec3(-1.0, 0.0, 0.0), vec3(0.0, -1.0, 0.0), vec3(0.0, 0.0, 1.0));
    }
    float f = 1.0 / (1.0 + c);
    float y = u.y;
    float z = u.z;
    return mat3(vec3(c, y, z), vec3(-y, 1.0 - y * y * f, -y * z * f), vec3(-z, -y * z * f, 1.0 - z * z * f));
}

mat3 advance_frame(mat3 frame, vec3 v) {
    float len = length(v);
    return len > MIN_LENGTH ? frame * rotation_from_x(v * (1.0 / len)) : frame;
}

#endif
