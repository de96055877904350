//! The simulation kernel's interface as the CPU sees it: the constants it shares with
//! Rust (its `STEPS` bits and thresholds, as defines), its descriptor bindings, the
//! layouts of its uniform block and per-substep constants (`shaders/sim_common.glsl`),
//! and the barrier between dependent dispatches.

use ash::vk;
use glam::{Mat4, UVec4, Vec4};

use super::params::StepConstants;
use super::steps::SimStep;
use crate::gpu::{memory_barrier, Buffer, Device, TexelBuffer};
use crate::strand_textures::StrandTextures;

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
/// constant is typed twice: the `STEPS` bits, the projections per substep and the rest
/// thresholds.
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
        ("PROJECTIONS", uint(super::collide::PROJECTIONS)),
        (
            "PROJECTIONS_SKINNED",
            uint(super::collide::PROJECTIONS_SKINNED),
        ),
        ("SLEEP_ULPS", float(super::cpu::SLEEP_ULPS)),
        ("REST_MOTION", float(super::cpu::REST_MOTION)),
        ("REST_GRAVITY", float(super::cpu::REST_GRAVITY)),
        ("NEAR_CAPSULES", uint(super::collide::NEAR_CAPSULES as u32)),
        ("CAPSULE_RAMP", float(super::collide::CAPSULE_RAMP)),
        ("MIN_DETERMINANT", float(super::collide::MIN_DETERMINANT)),
        ("BLEND_REFINE", uint(crate::skinning::blend::REFINE)),
        ("MIN_LENGTH", float(super::math::MIN_LENGTH)),
    ]
}

/// `SimStatic` in `shaders/sim_common.glsl` (std140).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SimStatic {
    pub(super) stiffness: Vec4,
    pub(super) counts: UVec4,
    pub(super) counts2: UVec4,
    pub(super) collision: Vec4,
    pub(super) sdf_origin: Vec4,
    pub(super) sdf_dims: UVec4,
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

pub(super) fn bindings() -> [(vk::DescriptorType, vk::ShaderStageFlags); 14] {
    let c = vk::ShaderStageFlags::COMPUTE;
    [
        (vk::DescriptorType::UNIFORM_BUFFER, c),
        (vk::DescriptorType::STORAGE_BUFFER, c),
        (vk::DescriptorType::STORAGE_IMAGE, c),
        (vk::DescriptorType::STORAGE_IMAGE, c),
        (vk::DescriptorType::STORAGE_BUFFER, c),
        (vk::DescriptorType::STORAGE_IMAGE, c),
        (vk::DescriptorType::STORAGE_IMAGE, c),
        (vk::DescriptorType::STORAGE_IMAGE, c), // the body's distance field
        (vk::DescriptorType::STORAGE_TEXEL_BUFFER, c), // root poses
        (vk::DescriptorType::STORAGE_TEXEL_BUFFER, c), // the bones' capsules
        (vk::DescriptorType::STORAGE_TEXEL_BUFFER, c), // last root poses
        (vk::DescriptorType::STORAGE_IMAGE, c), // the skin's blend of bones
        (vk::DescriptorType::STORAGE_TEXEL_BUFFER, c), // the bones' motions
        (vk::DescriptorType::STORAGE_BUFFER, c), // the probe's arrows
    ]
}

/// Makes a dispatch's storage writes visible to the next dispatch (a pipeline barrier
/// between dependent compute steps).
pub(super) fn after_dispatch(device: &Device, cmd: vk::CommandBuffer) {
    let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
    memory_barrier(
        device,
        cmd,
        (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
        (
            compute,
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
        ),
    );
}

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
    let bindings = bindings();
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
    let (b0, b1, b4, b13) = (
        buffer(statics),
        buffer(steps),
        buffer(&textures.root_frames),
        buffer(&textures.probe),
    );
    let (t8, t9, t10, t12) = (
        [body.root_poses.view()],
        [body.capsules.view()],
        [body.last.view()],
        [body.bones.view()],
    );
    let (i2, i3, i7, i11) = (
        image(&textures.rest),
        image(&textures.rest_local),
        image(body.field),
        image(body.blend),
    );
    let (i5, i6) = (
        image(&textures.positions[1 - k]),
        image(&textures.positions[k]),
    );
    let write = |binding: u32| {
        vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(binding)
            .descriptor_type(bindings[binding as usize].0)
    };
    let writes = [
        write(0).buffer_info(&b0),
        write(1).buffer_info(&b1),
        write(2).image_info(&i2),
        write(3).image_info(&i3),
        write(4).buffer_info(&b4),
        write(5).image_info(&i5),
        write(6).image_info(&i6),
        write(7).image_info(&i7),
        write(8).texel_buffer_view(&t8),
        write(9).texel_buffer_view(&t9),
        write(10).texel_buffer_view(&t10),
        write(11).image_info(&i11),
        write(12).texel_buffer_view(&t12),
        write(13).buffer_info(&b13),
    ];
    // SAFETY: `set` was allocated from this device with the simulation's layout, whose
    // bindings 0..=13 have the types written here; every view and buffer is alive (the
    // simulation owns them) and the info arrays outlive the call; the sets are written
    // once, at creation, before any submission uses them.
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points binding 13 of simulation set `set` at `probe` (resized by the simulation
/// view; the device is idle).
pub(super) fn write_probe(device: &Device, set: vk::DescriptorSet, probe: &Buffer) {
    let info = [vk::DescriptorBufferInfo::default()
        .buffer(probe.raw())
        .range(vk::WHOLE_SIZE)];
    let write = vk::WriteDescriptorSet::default()
        .dst_set(set)
        .dst_binding(13)
        .descriptor_type(bindings()[13].0)
        .buffer_info(&info);
    // SAFETY: the set has the simulation's layout (binding 13 a storage buffer); no
    // submission using it is pending (the caller waited for the device); the buffer
    // outlives the set's use (the strand textures own it and are rebound on change).
    unsafe { device.raw.update_descriptor_sets(&[write], &[]) };
}

#[cfg(test)]
mod tests {
    use std::mem::offset_of;

    use super::{bindings, GpuStep, SimStatic};
    use crate::gpu::reflect::{check_bindings, check_struct, reflect};
    use crate::gpu::shader::compile;

    /// Both kernels use the bindings of the Rust layout with their types and lay out
    /// `SimStatic` and `Step` as the Rust structs do; every binding is used.
    #[test]
    fn the_kernels_agree_with_the_rust_layouts() {
        let layout: Vec<_> = bindings().iter().map(|b| b.0).collect();
        let sim_static = [
            ("stiffness", offset_of!(SimStatic, stiffness)),
            ("counts", offset_of!(SimStatic, counts)),
            ("counts2", offset_of!(SimStatic, counts2)),
            ("collision", offset_of!(SimStatic, collision)),
            ("sdf_origin", offset_of!(SimStatic, sdf_origin)),
            ("sdf_dims", offset_of!(SimStatic, sdf_dims)),
        ];
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
