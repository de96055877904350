//! The simulation kernel's interface as the CPU sees it: the constants it shares with
//! Rust (its `STEPS` bits and thresholds, as defines), its descriptor bindings, the
//! layouts of its uniform block and per-substep constants (`shaders/sim_common.glsl`),
//! and the barrier between dependent dispatches.

use ash::vk;
use glam::{Mat4, UVec3, Vec3, Vec4};

use crate::gpu::{bindings, Buffer, Device, TexelBuffer};
use crate::strand_textures::StrandTextures;
use fur_core::sim::params::StepConstants;
use fur_core::sim::steps::SimStep;

/// The kernel's `STEPS` bit for a skinned body (`BODY_SKINNED` in `simulate.comp`).
pub(super) const BODY_SKINNED: u32 = 64;
/// The kernel's `STEPS` bit for sleep (`SLEEP` in `simulate.comp`): only where hair can
/// come to rest ([`super::SimParams::hair_can_rest`]).
pub(super) const SLEEP: u32 = 128;
/// The kernel's `STEPS` bit for carrying vertices back through the skin's blend of
/// bones (`BODY_BLEND` in `simulate.comp`, [`super::SimParams::skin_blend`]).
pub(super) const BODY_BLEND: u32 = 256;
/// The kernel's `STEPS` bit for the simulation view's probe (`PROBE` in
/// `simulate.comp`): each vertex's displacement from rest, and whether collision pushed
/// it, written into its position's w ([`super::GpuSim::set_probe`]).
pub(super) const PROBE: u32 = 512;

/// What the simulation kernels share with Rust, given to them as `#define`s so no
/// constant is typed twice: the `STEPS` bits, the projections per substep, the rest
/// thresholds and the bindings' numbers.
pub fn kernel_defines() -> Vec<(&'static str, String)> {
    let uint = |v: u32| format!("{v}u");
    // `{:?}` writes an f32 as its shortest round-trip decimal, always with a point.
    let float = |v: f32| format!("{v:?}");
    vec![
        ("STEP_INTEGRATE", uint(SimStep::Integrate.bit())),
        ("STEP_GLOBAL", uint(SimStep::Global.bit())),
        ("STEP_LOCAL", uint(SimStep::Local.bit())),
        ("STEP_LENGTH", uint(SimStep::Length.bit())),
        ("STEP_WIND", uint(SimStep::Wind.bit())),
        ("STEP_COLLISION", uint(SimStep::Collision.bit())),
        ("BODY_SKINNED", uint(BODY_SKINNED)),
        ("SLEEP", uint(SLEEP)),
        ("BODY_BLEND", uint(BODY_BLEND)),
        ("PROBE", uint(PROBE)),
        ("PROJECTIONS", uint(fur_core::sim::collide::PROJECTIONS)),
        (
            "PROJECTIONS_SKINNED",
            uint(fur_core::sim::collide::PROJECTIONS_SKINNED),
        ),
        ("SLEEP_ULPS", float(fur_core::sim::cpu::SLEEP_ULPS)),
        ("REST_MOTION", float(fur_core::sim::cpu::REST_MOTION)),
        ("REST_GRAVITY", float(fur_core::sim::cpu::REST_GRAVITY)),
        (
            "NEAR_CAPSULES",
            uint(fur_core::sim::collide::NEAR_CAPSULES as u32),
        ),
        ("CAPSULE_RAMP", float(fur_core::sim::collide::CAPSULE_RAMP)),
        (
            "MIN_DETERMINANT",
            float(fur_core::sim::collide::MIN_DETERMINANT),
        ),
        ("BLEND_REFINE", uint(fur_core::skinning::blend::REFINE)),
        ("MIN_LENGTH", float(fur_core::sim::math::MIN_LENGTH)),
    ]
    .into_iter()
    .chain(SimBinding::defines())
    .collect()
}

/// `SimStatic` in `shaders/sim_common.glsl` (std140).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SimStatic {
    /// The global and local shape constraints' stiffness S_G, S_L.
    pub(super) global_stiffness: f32,
    pub(super) local_stiffness: f32,
    /// How far from the body a vertex is held, a fraction of its strand's length.
    pub(super) collision_margin: f32,
    pub(super) friction: f32,
    pub(super) strand_count: u32,
    pub(super) strands_per_row: u32,
    /// The last vertex the global shape constraint pulls.
    pub(super) global_cutoff: u32,
    pub(super) local_iterations: u32,
    pub(super) length_iterations: u32,
    /// The bones' capsules, per pose.
    pub(super) capsule_count: u32,
    pub(super) joint_count: u32,
    /// The step whose corrections the probe records ([`SimStep::bit`]; 0: none).
    pub(super) probe_step: u32,
    /// The body's distance field: grid point (0, 0, 0) in model space, the spacing,
    /// the points along each axis, and one over the spacing.
    pub(super) sdf_origin: Vec3,
    pub(super) cell: f32,
    pub(super) sdf_dims: UVec3,
    pub(super) inverse_cell: f32,
}

/// `Step` in `shaders/sim_common.glsl` (std430).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct GpuStep {
    pub(super) head: Mat4,
    pub(super) head_inverse: Mat4,
    pub(super) gravity_h2: Vec4,
    pub(super) wind_h2: [Vec4; 4],
}

impl From<&StepConstants> for GpuStep {
    fn from(c: &StepConstants) -> Self {
        Self {
            head: c.head,
            head_inverse: c.head_inverse,
            gravity_h2: c.gravity_h2.extend(c.velocity_retention),
            wind_h2: c.wind_h2.map(|w| w.extend(0.0)),
        }
    }
}

const COMPUTE: vk::ShaderStageFlags = vk::ShaderStageFlags::COMPUTE;

bindings!(
    /// The simulation kernels' one set, one per position image (`shaders/sim_common.glsl`).
    SimBinding {
        /// The `SimStatic` uniform block.
        Static = ("SB_STATIC", UNIFORM_BUFFER, COMPUTE),
        /// Each substep's constants (`Step`).
        Steps = ("SB_STEPS", STORAGE_BUFFER, COMPUTE),
        /// The rest positions, model space.
        RestPositions = ("SB_REST_POSITIONS", STORAGE_IMAGE, COMPUTE),
        /// The rest segments, each in its parent's frame.
        RestLocal = ("SB_REST_LOCAL", STORAGE_IMAGE, COMPUTE),
        /// Each strand's root frame.
        RootFrames = ("SB_ROOT_FRAMES", STORAGE_BUFFER, COMPUTE),
        /// The positions a frame ago.
        PreviousPositions = ("SB_PREVIOUS_POSITIONS", STORAGE_IMAGE, COMPUTE),
        /// The positions now, written in place.
        CurrentPositions = ("SB_CURRENT_POSITIONS", STORAGE_IMAGE, COMPUTE),
        /// The body's distance field.
        Sdf = ("SB_SDF", STORAGE_IMAGE, COMPUTE),
        /// A skinned body's root poses.
        RootPoses = ("SB_ROOT_POSES", STORAGE_TEXEL_BUFFER, COMPUTE),
        /// The bones' capsules.
        Capsules = ("SB_CAPSULES", STORAGE_TEXEL_BUFFER, COMPUTE),
        /// The root poses of the frame before.
        LastPoses = ("SB_LAST_POSES", STORAGE_TEXEL_BUFFER, COMPUTE),
        /// The skin's blend of bones at the field's grid points.
        Blend = ("SB_BLEND", STORAGE_IMAGE, COMPUTE),
        /// The bones' motions.
        Bones = ("SB_BONES", STORAGE_TEXEL_BUFFER, COMPUTE),
        /// The probe's arrows (the simulation view).
        Probe = ("SB_PROBE", STORAGE_BUFFER, COMPUTE),
    }
);

/// A skinned body's resources as the kernel reads them (placeholders on a rigid body):
/// the field, the root poses, the capsules, the last root poses, the skin's blend of
/// bones at the field's grid points and the bones' motions.
pub(super) struct BodyViews<'a> {
    pub(super) field: &'a crate::gpu::Image,
    pub(super) root_poses: &'a TexelBuffer,
    pub(super) capsules: &'a TexelBuffer,
    pub(super) last: &'a TexelBuffer,
    pub(super) blend: &'a crate::gpu::Image,
    pub(super) bones: &'a TexelBuffer,
}

/// Points simulation descriptor set `k` (current = `positions[k]`) at its resources:
/// the static tables, the step constants, the strand images and the body.
pub(super) fn write_sim_set(
    device: &Device,
    set: vk::DescriptorSet,
    k: usize,
    statics: &Buffer,
    steps: &Buffer,
    textures: &StrandTextures,
    body: &BodyViews,
) {
    let buffer = |b: &Buffer| {
        [vk::DescriptorBufferInfo::default()
            .buffer(b.raw())
            .range(vk::WHOLE_SIZE)]
    };
    let image = |i: &crate::gpu::Image| {
        [vk::DescriptorImageInfo::default()
            .image_view(i.view())
            .image_layout(vk::ImageLayout::GENERAL)]
    };
    let (statics, steps, root_frames, probe) = (
        buffer(statics),
        buffer(steps),
        buffer(&textures.root_frames),
        buffer(&textures.probe),
    );
    let (root_poses, capsules, last, bones) = (
        [body.root_poses.view()],
        [body.capsules.view()],
        [body.last.view()],
        [body.bones.view()],
    );
    let (rest, rest_local, field, blend) = (
        image(&textures.rest),
        image(&textures.rest_local),
        image(body.field),
        image(body.blend),
    );
    let (previous, current) = (
        image(&textures.positions[1 - k]),
        image(&textures.positions[k]),
    );
    use SimBinding as B;
    let writes = [
        B::Static.write(set).buffer_info(&statics),
        B::Steps.write(set).buffer_info(&steps),
        B::RestPositions.write(set).image_info(&rest),
        B::RestLocal.write(set).image_info(&rest_local),
        B::RootFrames.write(set).buffer_info(&root_frames),
        B::PreviousPositions.write(set).image_info(&previous),
        B::CurrentPositions.write(set).image_info(&current),
        B::Sdf.write(set).image_info(&field),
        B::RootPoses.write(set).texel_buffer_view(&root_poses),
        B::Capsules.write(set).texel_buffer_view(&capsules),
        B::LastPoses.write(set).texel_buffer_view(&last),
        B::Blend.write(set).image_info(&blend),
        B::Bones.write(set).texel_buffer_view(&bones),
        B::Probe.write(set).buffer_info(&probe),
    ];
    // SAFETY: `set` was allocated from this device with the simulation's layout
    // (`SimBinding::set_layout`), whose bindings have the types written here; every view and buffer is alive (the
    // simulation owns them) and the info arrays outlive the call; the sets are written
    // once, at creation, before any submission uses them.
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points simulation set `set`'s probe at `probe` (resized by the simulation view; the
/// device is idle).
pub(super) fn write_probe(device: &Device, set: vk::DescriptorSet, probe: &Buffer) {
    let info = [vk::DescriptorBufferInfo::default()
        .buffer(probe.raw())
        .range(vk::WHOLE_SIZE)];
    let write = SimBinding::Probe.write(set).buffer_info(&info);
    // SAFETY: the set has the simulation's layout (the probe a storage buffer); no
    // submission using it is pending (the caller waited for the device); the buffer
    // outlives the set's use (the strand textures own it and are rebound on change).
    unsafe { device.raw.update_descriptor_sets(&[write], &[]) };
}

#[cfg(test)]
mod tests {
    use std::mem::offset_of;

    use super::{GpuStep, SimBinding, SimStatic};
    use crate::gpu::reflect::{check_bindings, check_struct, reflect};
    use crate::gpu::shader::compile;

    /// Both kernels use the bindings of the Rust layout with their types and lay out
    /// `SimStatic` and `Step` as the Rust structs do; every binding is used.
    #[test]
    fn the_kernels_agree_with_the_rust_layouts() {
        let layout: Vec<_> = SimBinding::set_layout().iter().map(|b| b.0).collect();
        macro_rules! fields {
            ($($f:ident),+) => { [$((stringify!($f), offset_of!(SimStatic, $f))),+] };
        }
        let sim_static = fields!(
            global_stiffness,
            local_stiffness,
            collision_margin,
            friction,
            strand_count,
            strands_per_row,
            global_cutoff,
            local_iterations,
            length_iterations,
            capsule_count,
            joint_count,
            probe_step,
            sdf_origin,
            cell,
            sdf_dims,
            inverse_cell
        );
        let step = [
            ("head", offset_of!(GpuStep, head)),
            ("head_inverse", offset_of!(GpuStep, head_inverse)),
            ("gravity_h2", offset_of!(GpuStep, gravity_h2)),
            ("wind_h2", offset_of!(GpuStep, wind_h2)),
        ];
        let mut used = std::collections::BTreeSet::new();
        for kernel in ["simulate.comp", "simulate_rest.comp"] {
            let words = compile(kernel, &super::kernel_defines())
                .unwrap_or_else(|e| panic!("{kernel}: {e}"));
            let found = reflect(&words);
            check_bindings(kernel, &found, &[&layout]).unwrap();
            check_struct(kernel, &found, "SimStatic", &sim_static).unwrap();
            if kernel == "simulate.comp" || found.structs.contains_key("Step") {
                check_struct(kernel, &found, "Step", &step).unwrap();
            }
            used.extend(found.bindings.keys().map(|&(_, b)| b));
        }
        assert_eq!(used.len(), layout.len(), "bindings used: {used:?}");
    }
}
