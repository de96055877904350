//! The skinning pass on the device (`shaders/skin.comp`): every simulated frame it skins
//! the body's vertices for each substep, writing each strand's root pose (read by the
//! simulation) and, for the frame's last substep, the posed positions and normals the
//! mesh and fur passes draw.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, UVec4, Vec4};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::{
    bindings, Buffer, DescriptorPool, DescriptorSetLayout, Device, Pipeline, PipelineLayout,
    Specialization, TexelBuffer,
};
use fur_core::skinning::SkinnedBody;

use crate::frame::{record_memory_uses, uses, Resource};
/// Vertices per workgroup (`local_size_x` in `skin.comp`).
use crate::gpu::shader::GROUP_SIZE;
use crate::gpu::{Access, Tracker};
/// The most root-pose memory a body may take (substeps × strands × 48 bytes).
const MAX_ROOT_POSE_BYTES: u64 = 256 << 20;

/// The skinning pass's resources for one body.
pub struct GpuSkin {
    device: Arc<Device>,
    vertex_count: u32,
    joint_count: u32,
    /// Substeps one dispatch can pose (the root-pose buffer's capacity).
    pub max_substeps: u32,
    /// Per vertex: position and normal of the last posed substep.
    pub posed: Buffer,
    /// Per substep of a dispatch and strand: 3 × vec4 (R's columns, the root in w).
    pub root_poses: TexelBuffer,
    _statics: [TexelBuffer; 4],
    /// Per frame in flight: joint matrices of every substep of a submission.
    joints: Vec<TexelBuffer>,
    /// Per frame in flight: the bones' posed capsules of every substep of a submission
    /// (read by the simulation's collision step).
    pub capsules: Vec<TexelBuffer>,
    pub capsule_count: u32,
    /// Per frame in flight: every joint's motion from the rest pose (three rows, see
    /// [`fur_core::skinning::blend::bone_rows`]) for each substep of a submission (read by the
    /// simulation's collision step).
    pub bones: Vec<TexelBuffer>,
    /// Per strand, its root pose after the last simulated substep (the simulation's).
    pub last_poses: TexelBuffer,
    joint_capacity: usize,
    _set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    _pool: DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    pipeline: Pipeline,
}

bindings!(
    /// The skinning kernel's one set, one per frame in flight (`shaders/skin.comp`).
    /// Every table but the posed body is a storage texel buffer: a CPU driver reads and
    /// writes those at lane-varying indices in one gather or scatter, a storage buffer
    /// one lane at a time (`crates/fur-gpu/src/gpu/buffer.rs`).
    SkinBinding {
        /// Per vertex: position, normal, tangent at the bind pose.
        BindVertices = ("KB_BIND_VERTICES", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// Per vertex, its four joints.
        Influences = ("KB_INFLUENCES", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// Per vertex, their weights.
        Weights = ("KB_WEIGHTS", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// Per vertex: rest tangent, rest normal.
        RestFrames = ("KB_REST_FRAMES", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// The joint matrices of each substep (one buffer per frame in flight).
        Joints = ("KB_JOINTS", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// The posed body: a storage buffer, since the mesh pass reads it too.
        Posed = ("KB_POSED", STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// Each strand's root pose per substep.
        RootPoses = ("KB_ROOT_POSES", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
    }
);

/// The skinning kernel's defines: its bindings' numbers.
pub(crate) fn skin_defines() -> Vec<(&'static str, String)> {
    SkinBinding::defines().collect()
}

/// How much room a [`GpuSkin`] allocates.
#[derive(Clone, Copy, Debug)]
pub struct SkinCapacity {
    /// Substeps per dispatch (a frame's substeps).
    pub substeps: u32,
    /// Substeps (of joint matrices, capsules and bone motions) per submission.
    pub step_capacity: usize,
    /// Submissions in flight, each with its own per-substep buffers.
    pub frames_in_flight: usize,
    /// Room for every joint's motion of each substep, which the skin's blend of bones
    /// reads (a placeholder otherwise).
    pub bones: bool,
}

impl GpuSkin {
    /// Uploads `body` and allocates the room `capacity` asks for.
    pub fn new(device: &Arc<Device>, body: &SkinnedBody, capacity: SkinCapacity) -> Result<Self> {
        let SkinCapacity {
            substeps,
            step_capacity,
            frames_in_flight,
            bones: with_bones,
        } = capacity;
        let rig = &body.rig;
        let n = body.vertex_count();
        let vertex_count = u32::try_from(n).map_err(|_| {
            Error::parameter(format!("a skinned body of {n} vertices is too large"))
        })?;
        let joint_count = rig.joints.len().max(1) as u32;
        let per_substep = 48 * u64::from(vertex_count);
        let fits = (MAX_ROOT_POSE_BYTES / per_substep.max(1)).max(1) as u32;
        let max_substeps = fits.min(64);
        if substeps > max_substeps {
            return Err(Error::parameter(format!(
                "a skinned body of {vertex_count} vertices can take at most {max_substeps} \
                 substeps per frame, got {substeps}"
            )));
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let bind: Vec<Vec4> = (0..n)
            .flat_map(|v| {
                [
                    rig.bind_positions[v].extend(1.0),
                    rig.bind_normals[v].extend(0.0),
                    body.bind_tangents[v].extend(0.0),
                ]
            })
            .collect();
        let influences: Vec<UVec4> = rig
            .influences
            .iter()
            .map(|j| UVec4::from_array(j.map(u32::from)))
            .collect();
        let weights: Vec<Vec4> = rig.weights.iter().map(|w| Vec4::from_array(*w)).collect();
        let frames: Vec<Vec4> = body
            .rest_frames
            .iter()
            .flat_map(|(t, n)| [t.extend(0.0), n.extend(0.0)])
            .collect();
        let float = vk::Format::R32G32B32A32_SFLOAT;
        let statics = [
            TexelBuffer::with_data(device, "skin.bind_vertices", float, &bind)?,
            TexelBuffer::with_data(
                device,
                "skin.influences",
                vk::Format::R32G32B32A32_UINT,
                &influences,
            )?,
            TexelBuffer::with_data(device, "skin.weights", float, &weights)?,
            TexelBuffer::with_data(device, "skin.rest_frames", float, &frames)?,
        ];
        let posed = Buffer::new(
            device,
            "skin.posed",
            32 * u64::from(vertex_count),
            storage | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let root_poses = TexelBuffer::new(
            device,
            "skin.root_poses",
            per_substep / 16 * u64::from(max_substeps),
            float,
            16,
            MemoryLocation::GpuOnly,
        )?;
        let frames_in_flight = frames_in_flight.max(1);
        let joints = (0..frames_in_flight)
            .map(|slot| {
                // Four texels (columns) per matrix.
                TexelBuffer::new(
                    device,
                    &format!("skin.joints[{slot}]"),
                    (step_capacity * joint_count as usize * 4) as u64,
                    vk::Format::R32G32B32A32_SFLOAT,
                    16,
                    MemoryLocation::CpuToGpu,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        let capsule_count = body.capsules.len() as u32;
        let last_poses = TexelBuffer::new(
            device,
            "skin.last_poses",
            3 * u64::from(vertex_count),
            float,
            16,
            MemoryLocation::GpuOnly,
        )?;
        // The bind pose's capsules lead each slot's buffer (the simulation scales each
        // capsule by how far it moved from there relative to a strand's root).
        let rest_capsules = fur_core::skinning::capsules::pose(&body.capsules, &[]);
        let capsules = (0..frames_in_flight)
            .map(|slot| {
                let mut capsules = TexelBuffer::new(
                    device,
                    &format!("skin.capsules[{slot}]"),
                    ((step_capacity + 1) * capsule_count.max(1) as usize * 2) as u64,
                    vk::Format::R32G32B32A32_SFLOAT,
                    16,
                    MemoryLocation::CpuToGpu,
                )?;
                capsules
                    .buffer
                    .write(0, bytemuck::cast_slice(&rest_capsules));
                Ok(capsules)
            })
            .collect::<Result<Vec<_>>>()?;
        let bones = (0..frames_in_flight)
            .map(|slot| {
                TexelBuffer::new(
                    device,
                    &format!("skin.bones[{slot}]"),
                    if with_bones {
                        (step_capacity * joint_count as usize * 3) as u64
                    } else {
                        1
                    },
                    vk::Format::R32G32B32A32_SFLOAT,
                    16,
                    MemoryLocation::CpuToGpu,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        let bindings = SkinBinding::set_layout();
        let set_layout = DescriptorSetLayout::new(device, "skin.set_layout", &bindings)?;
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(16)];
        let layout = PipelineLayout::new(device, "skin.pipeline_layout", &[&set_layout], &push)?;
        let pool = DescriptorPool::new(
            device,
            "skin.descriptor_pool",
            frames_in_flight as u32,
            &bindings,
        )?;
        let sets = pool.allocate(&set_layout, frames_in_flight)?;
        for (set, joint_buffer) in sets.iter().zip(&joints) {
            let posed_info = [vk::DescriptorBufferInfo::default()
                .buffer(posed.raw())
                .range(vk::WHOLE_SIZE)];
            use SkinBinding as B;
            let views: Vec<(SkinBinding, [vk::BufferView; 1])> = [
                (B::BindVertices, &statics[0]),
                (B::Influences, &statics[1]),
                (B::Weights, &statics[2]),
                (B::RestFrames, &statics[3]),
                (B::Joints, joint_buffer),
                (B::RootPoses, &root_poses),
            ]
            .iter()
            .map(|(binding, texels)| (*binding, [texels.view()]))
            .collect();
            let mut writes: Vec<vk::WriteDescriptorSet> = views
                .iter()
                .map(|(binding, view)| binding.write(*set).texel_buffer_view(view))
                .collect();
            writes.push(B::Posed.write(*set).buffer_info(&posed_info));
            // SAFETY: `set` was just allocated from `pool` with `set_layout`, whose
            // bindings have the types written here, and no submission uses it yet; the
            // texel views and the posed buffer are alive (moved into `Self` below) and
            // `views` and `posed_info` outlive the call.
            unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
        }
        let pipeline = Pipeline::compute(
            device,
            "skin.comp",
            &skin_defines(),
            &layout,
            &Specialization::new(&[]),
        )?;
        Ok(Self {
            device: device.clone(),
            vertex_count,
            joint_count,
            max_substeps,
            posed,
            root_poses,
            _statics: statics,
            joints,
            capsules,
            capsule_count,
            bones,
            last_poses,
            joint_capacity: step_capacity,
            _set_layout: set_layout,
            layout,
            _pool: pool,
            sets,
            pipeline,
        })
    }

    /// Writes slot `slot`'s joint matrices: `matrices` holds every joint of each
    /// substep of the coming submission, substep after substep. The slot's previous
    /// submission must have finished.
    pub fn write_joints(&mut self, slot: usize, matrices: &[Mat4]) -> Result<()> {
        let substeps = matrices.len() / self.joint_count as usize;
        if substeps > self.joint_capacity {
            return Err(Error::parameter(format!(
                "at most {} skinned substeps per submission, got {substeps}",
                self.joint_capacity
            )));
        }
        self.joints[slot]
            .buffer
            .write(0, bytemuck::cast_slice(matrices));
        Ok(())
    }

    /// Writes slot `slot`'s posed capsules, every capsule of each substep of the coming
    /// submission, substep after substep (see [`fur_core::skinning::capsules::pose`]), after the
    /// bind pose's, which lead the buffer.
    pub fn write_capsules(&mut self, slot: usize, capsules: &[[Vec4; 2]]) {
        let lead = self.capsule_count as usize;
        let buffer = &mut self.capsules[slot].buffer;
        let capacity = (buffer.size() as usize / 32).saturating_sub(lead);
        let n = capsules.len().min(capacity);
        buffer.write(lead * 32, bytemuck::cast_slice(&capsules[..n]));
    }

    /// Writes slot `slot`'s bone motions, every joint's three rows of each substep of
    /// the coming submission, substep after substep (see [`fur_core::skinning::blend::bone_rows`]).
    pub fn write_bones(&mut self, slot: usize, rows: &[[Vec4; 3]]) {
        let buffer = &mut self.bones[slot].buffer;
        let n = rows.len().min(buffer.size() as usize / 48);
        buffer.write(0, bytemuck::cast_slice(&rows[..n]));
    }

    /// Joints per pose.
    pub fn joint_count(&self) -> u32 {
        self.joint_count
    }

    /// Records the skinning of substeps `first .. first + count` of the submission (the
    /// root poses of each, the posed body of the last), declaring to `tracker` that it
    /// writes them: the barrier after their earlier readers comes from there, and the
    /// simulation and the draws declare their reads.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        tracker: &mut Tracker<Resource>,
        slot: usize,
        first: u32,
        count: u32,
    ) {
        let d = &*self.device;
        d.begin_label(cmd, "skinning");
        record_memory_uses(
            d,
            cmd,
            tracker,
            &[uses(Resource::Posed, Access::ComputeWrite)],
        );
        let push = [first, count, self.vertex_count, self.joint_count];
        // SAFETY: callers pass a command buffer of this device in the recording state,
        // outside a rendering; the pipeline was built with `self.layout`, the push
        // constants fill its 16-byte COMPUTE range, and `self.sets[slot]` was written
        // at creation with resources `self` keeps alive.
        unsafe {
            d.raw
                .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.raw());
            d.raw.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.raw(),
                0,
                &[self.sets[slot]],
                &[],
            );
            d.raw.cmd_push_constants(
                cmd,
                self.layout.raw(),
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::cast_slice(&push),
            );
            d.raw
                .cmd_dispatch(cmd, self.vertex_count.div_ceil(GROUP_SIZE), 1, 1);
        }
        d.end_label(cmd);
    }

    /// Device memory the pass takes, in bytes.
    pub fn memory_bytes(&self) -> u64 {
        self._statics.iter().map(|t| t.buffer.size()).sum::<u64>()
            + self.posed.size()
            + self.root_poses.buffer.size()
            + self.joints.iter().map(|j| j.buffer.size()).sum::<u64>()
            + self.capsules.iter().map(|c| c.buffer.size()).sum::<u64>()
            + self.bones.iter().map(|b| b.buffer.size()).sum::<u64>()
            + self.last_poses.buffer.size()
    }
}

#[cfg(test)]
mod tests {
    use crate::gpu::reflect::{check_bindings, reflect};

    /// The skinning kernel uses the bindings of the Rust layout, each with its type,
    /// and every one of them.
    #[test]
    fn the_skinning_kernel_agrees_with_the_rust_layout() {
        let layout: Vec<_> = super::SkinBinding::set_layout()
            .iter()
            .map(|b| b.0)
            .collect();
        let words = crate::gpu::shader::compile("skin.comp", &super::skin_defines()).unwrap();
        let found = reflect(&words);
        check_bindings("skin.comp", &found, &[&layout]).unwrap();
        assert_eq!(found.bindings.len(), layout.len(), "{:?}", found.bindings);
    }
}
