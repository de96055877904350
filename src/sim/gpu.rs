//! The simulation in compute shaders: one dispatch per frame of `simulate.comp`, in
//! which one invocation carries one master strand through every substep, running the
//! named steps of Han & Harada in order. The strand textures ping-pong once per frame.
//!
//! Steps a scene does not use are compiled out of the kernel (a specialization
//! constant): the global constraint at S_G = 0 (or an empty range), the local constraint
//! at S_L = 0 or 0 iterations, the length constraint at 0 iterations, wind when its
//! vector is zero.

use std::sync::Arc;

use ash::vk;
use glam::{DMat4, UVec4, Vec3, Vec4};
use gpu_allocator::MemoryLocation;

use super::kernel::{after_dispatch, bindings, write_sim_set, GpuStep, SimStatic};
use super::params::{SimParams, StepConstants};
use super::sdf::Sdf;
pub use super::steps::SimStep;
use crate::error::{Error, Result};
use crate::gpu::{
    memory_barrier, Buffer, DescriptorPool, DescriptorSetLayout, Device, Pipeline, PipelineLayout,
    QueryPool, Specialization, TexelBuffer,
};
use crate::skinning::{GpuSkin, Playback, SkinnedBody};
use crate::strand_textures::StrandTextures;

/// Strands per workgroup (one invocation each).
const GROUP_SIZE: u32 = 64;
/// Most vertices a strand may have (private arrays in the kernel).
pub const MAX_VERTICES: u32 = 64;
/// Substeps whose constants fit in the step buffer: one submission's worth.
const STEP_CAPACITY: usize = 1024;
/// The kernel's `STEPS` bit for a skinned body (`BODY_SKINNED` in `simulate.comp`).
const BODY_SKINNED: u32 = 64;
/// The kernel's `STEPS` bit for sleep (`SLEEP` in `simulate.comp`): only where hair can
/// come to rest ([`SimParams::hair_can_rest`]).
const SLEEP: u32 = 128;

/// A skinned body's part of the simulation: the skinning pass, the body, which clip
/// plays, and the joint matrices of the substeps not yet recorded.
pub struct Skinned {
    pub skin: GpuSkin,
    pub body: Arc<SkinnedBody>,
    pub playback: Playback,
    pending: Vec<glam::Mat4>,
    pending_capsules: Vec<[Vec4; 2]>,
}

/// GPU simulation state for one set of strand textures.
pub struct GpuSim {
    device: Arc<Device>,
    params: SimParams,
    vertices: u32,
    strand_count: u32,
    _set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    _pool: DescriptorPool,
    /// Parameters the kernel reads; written only while the device is idle.
    statics: Buffer,
    /// The kernel, specialized for the steps in use, with their `STEPS` mask.
    pipeline: Option<(u32, Pipeline)>,
    /// Steps to compile in even when the parameters do not need them (the benchmark
    /// measures steps alone this way); `None`: exactly the needed ones.
    forced_steps: Option<u32>,
    /// The body's distance field (a 3D image, per grid point its value and gradient; a
    /// placeholder without a body) and its grid.
    _body: crate::gpu::Image,
    grid: Option<BodyGrid>,
    /// The skinned body, if the strands grow on one.
    pub skinned: Option<Skinned>,
    /// Stand in for the root poses and capsules of a rigid body.
    _no_poses: TexelBuffer,
    _no_capsules: TexelBuffer,
    /// Per frame in flight: step constants, timestamps, descriptor sets.
    slots: Vec<SimSlot>,
    /// Simulated time in seconds.
    pub time: f64,
}

/// Where the body's distance field lies.
#[derive(Clone, Copy, Debug)]
struct BodyGrid {
    origin: Vec3,
    cell: f32,
    dims: [u32; 3],
}

/// The resources of one frame in flight.
struct SimSlot {
    /// Set `k` reads `positions[k]` as current and `positions[1 - k]` as previous.
    sets: [vk::DescriptorSet; 2],
    steps: Buffer,
    timestamps: Option<QueryPool>,
    /// Frames (dispatches) recorded by the last `record` into this slot.
    recorded: usize,
}

impl GpuSim {
    /// A simulation with one set of per-frame resources and no body to collide with
    /// (see [`GpuSim::with_body`]).
    pub fn new(device: &Arc<Device>, textures: &StrandTextures, params: SimParams) -> Result<Self> {
        Self::with_body(device, textures, params, 1, None)
    }

    /// A simulation whose submissions can overlap `frames_in_flight` deep, colliding
    /// with the body whose distance field is `body` (when `params.collision` is on).
    pub fn with_body(
        device: &Arc<Device>,
        textures: &StrandTextures,
        params: SimParams,
        frames_in_flight: usize,
        body: Option<&Sdf>,
    ) -> Result<Self> {
        Self::build(device, textures, params, frames_in_flight, body, None)
    }

    /// A simulation as [`GpuSim::with_body`] whose strands grow on the skinned body
    /// `skinned` (one strand per body vertex) playing `Playback`: each strand's shape
    /// targets follow its own root pose. The strands are placed on the body's pose at
    /// time 0.
    pub fn build(
        device: &Arc<Device>,
        textures: &StrandTextures,
        params: SimParams,
        frames_in_flight: usize,
        body: Option<&Sdf>,
        skinned: Option<(Arc<SkinnedBody>, Playback)>,
    ) -> Result<Self> {
        let frames_in_flight = frames_in_flight.max(1);
        params.validate()?;
        let vertices = textures.layout.vertices_per_strand;
        if vertices > MAX_VERTICES {
            return Err(Error::Parameter(format!(
                "the simulation handles at most {MAX_VERTICES} vertices per strand, got {vertices}"
            )));
        }
        let bindings = bindings();
        let set_layout = DescriptorSetLayout::new(device, "sim.set_layout", &bindings)?;
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(12)];
        let layout = PipelineLayout::new(device, "sim.pipeline_layout", &[&set_layout], &push)?;
        let pool = DescriptorPool::new(
            device,
            "sim.descriptor_pool",
            2 * frames_in_flight as u32,
            &bindings,
        )?;
        let statics = Buffer::new(
            device,
            "sim.static",
            std::mem::size_of::<SimStatic>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let body_field = super::field::upload(device, body)?;
        let skinned = match skinned {
            Some((body, playback)) => {
                if body.vertex_count() != textures.layout.strand_count as usize {
                    return Err(Error::Parameter(format!(
                        "the skinned body has {} vertices but there are {} strands",
                        body.vertex_count(),
                        textures.layout.strand_count
                    )));
                }
                let skin = GpuSkin::new(
                    device,
                    &body,
                    params.substeps,
                    STEP_CAPACITY,
                    frames_in_flight,
                )?;
                Some(Skinned {
                    skin,
                    body,
                    playback,
                    pending: Vec::new(),
                    pending_capsules: Vec::new(),
                })
            }
            None => None,
        };
        let no_poses = TexelBuffer::with_data(
            device,
            "sim.no_root_poses",
            vk::Format::R32G32B32A32_SFLOAT,
            &[0.0f32; 12],
        )?;
        let root_poses = skinned.as_ref().map_or(&no_poses, |s| &s.skin.root_poses);
        let last = skinned
            .as_ref()
            .map_or(&no_poses, |s: &Skinned| &s.skin.last_poses);
        let no_capsules = TexelBuffer::new(
            device,
            "sim.no_capsules",
            2,
            (vk::Format::R32G32B32A32_SFLOAT, 16),
            MemoryLocation::CpuToGpu,
        )?;
        let capsules = |slot: usize| {
            skinned
                .as_ref()
                .map_or(&no_capsules, |s: &Skinned| &s.skin.capsules[slot])
        };
        let mut slots = Vec::new();
        for slot in 0..frames_in_flight {
            let steps = Buffer::new(
                device,
                &format!("sim.steps[{slot}]"),
                (STEP_CAPACITY * std::mem::size_of::<GpuStep>()) as u64,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::CpuToGpu,
            )?;
            let sets = pool.allocate(&set_layout, 2)?;
            for (k, set) in sets.iter().enumerate() {
                write_sim_set(
                    device,
                    *set,
                    k,
                    &statics,
                    &steps,
                    textures,
                    (&body_field, root_poses, capsules(slot), last),
                );
            }
            let timestamps = if device.info.timestamps {
                Some(QueryPool::timestamps(
                    device,
                    &format!("sim.timestamps[{slot}]"),
                    1 + STEP_CAPACITY as u32,
                )?)
            } else {
                None
            };
            slots.push(SimSlot {
                sets: [sets[0], sets[1]],
                steps,
                timestamps,
                recorded: 0,
            });
        }
        let mut sim = Self {
            device: device.clone(),
            params: params.clone(),
            vertices,
            strand_count: textures.layout.strand_count,
            _set_layout: set_layout,
            layout,
            _pool: pool,
            statics,
            pipeline: None,
            forced_steps: None,
            _body: body_field,
            grid: body.map(|sdf| BodyGrid {
                origin: sdf.origin,
                cell: sdf.cell,
                dims: sdf.dims,
            }),
            skinned,
            _no_poses: no_poses,
            _no_capsules: no_capsules,
            slots,
            time: 0.0,
        };
        sim.set_params(params, textures)?;
        sim.compute_rest_data()?;
        if sim.skinned.is_some() {
            sim.place(textures, DMat4::IDENTITY)?;
        }
        Ok(sim)
    }

    fn specialization(&self, steps: u32) -> Specialization {
        Specialization::new(&[(0, GROUP_SIZE), (1, self.vertices), (2, steps)])
    }

    /// Runs `simulate_rest.comp` once: local rest vectors, rest lengths, root frames.
    fn compute_rest_data(&self) -> Result<()> {
        let spec = self.specialization(0);
        let pipeline = Pipeline::compute(&self.device, "simulate_rest.comp", &self.layout, &spec)?;
        let d = &*self.device;
        d.submit_once(|cmd| {
            d.begin_label(cmd, "rest pose");
            self.dispatch(cmd, &pipeline, self.slots[0].sets[0], [0, 0, 0]);
            d.end_label(cmd);
            after_dispatch(d, cmd);
            Ok(())
        })
    }

    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// The steps compiled into the kernel, in the order it runs them.
    pub fn active_steps(&self) -> Vec<SimStep> {
        let mask = self.pipeline.as_ref().map_or(0, |(m, _)| *m);
        SimStep::ALL
            .into_iter()
            .filter(|s| mask & s.bit() != 0)
            .collect()
    }

    /// Compiles exactly `steps` into the kernel (integration always runs), whatever the
    /// parameters need; `None` returns to the needed ones. For measuring steps alone.
    pub fn force_steps(
        &mut self,
        steps: Option<&[SimStep]>,
        textures: &StrandTextures,
    ) -> Result<()> {
        self.forced_steps =
            steps.map(|s| s.iter().fold(SimStep::Integrate.bit(), |m, s| m | s.bit()));
        self.set_params(self.params.clone(), textures)
    }

    /// Changes parameters; rebuilds the kernel when the set of needed steps changes.
    pub fn set_params(&mut self, params: SimParams, textures: &StrandTextures) -> Result<()> {
        params.validate()?;
        let statics = SimStatic {
            stiffness: Vec4::new(params.global_stiffness, params.local_stiffness, 0.0, 0.0),
            counts: UVec4::new(
                self.strand_count,
                textures.layout.strands_per_row,
                params.global_cutoff(self.vertices),
                params.local_iterations,
            ),
            counts2: UVec4::new(
                params.length_iterations,
                self.skinned.as_ref().map_or(0, |s| s.skin.capsule_count),
                0,
                0,
            ),
            collision: self.grid.map_or(Vec4::ZERO, |g| {
                Vec4::new(
                    params.collision_margin,
                    params.friction,
                    1.0 / g.cell,
                    g.cell,
                )
            }),
            sdf_origin: self.grid.map_or(Vec4::ZERO, |g| g.origin.extend(0.0)),
            sdf_dims: self.grid.map_or(UVec4::ZERO, |g| {
                UVec4::new(g.dims[0], g.dims[1], g.dims[2], 0)
            }),
        };
        // Only rewrite what the kernel reads when it changes: frames in flight may be
        // reading it (wind strength, for one, lives in the per-step constants instead).
        let bytes = bytemuck::bytes_of(&statics);
        if &self.statics.mapped()[..bytes.len()] != bytes {
            self.statics.write(0, bytes);
        }
        let needed = SimStep::ALL
            .into_iter()
            .filter(|s| s.needed(&params, self.vertices, self.grid.is_some()))
            .fold(0, |m, s| m | s.bit());
        let mut mask = self.forced_steps.unwrap_or(needed);
        if self.grid.is_none() {
            mask &= !SimStep::Collision.bit();
        }
        if params.hair_can_rest() {
            mask |= SLEEP;
        }
        if let Some(skinned) = &self.skinned {
            if params.substeps > skinned.skin.max_substeps {
                return Err(Error::Parameter(format!(
                    "this skinned body can take at most {} substeps per frame, got {}",
                    skinned.skin.max_substeps, params.substeps
                )));
            }
            mask |= BODY_SKINNED;
        }
        if self.pipeline.as_ref().map(|(m, _)| *m) != Some(mask) {
            let spec = self.specialization(mask);
            let pipeline = Pipeline::compute(&self.device, "simulate.comp", &self.layout, &spec)?;
            self.pipeline = Some((mask, pipeline));
        }
        self.params = params;
        Ok(())
    }

    fn group_count(&self) -> u32 {
        self.strand_count.div_ceil(GROUP_SIZE)
    }

    /// Records one dispatch of `pipeline` over every strand with descriptor set `set`
    /// and push constants `push` (first substep, substeps, placement).
    fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        set: vk::DescriptorSet,
        push: [u32; 3],
    ) {
        let raw = &self.device.raw;
        unsafe {
            raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw());
            raw.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.raw(),
                0,
                &[set],
                &[],
            );
            raw.cmd_push_constants(
                cmd,
                self.layout.raw(),
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::cast_slice(&push),
            );
            raw.cmd_dispatch(cmd, self.group_count(), 1, 1);
        }
    }

    /// Records the simulation of `constants.len() / substeps` frames: one dispatch per
    /// frame, each running that frame's substeps. The step constants are written into
    /// the step buffer now, so the submission must complete before the next call.
    pub fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        textures: &mut StrandTextures,
        constants: &[StepConstants],
    ) -> Result<()> {
        if constants.len() > STEP_CAPACITY {
            return Err(Error::Parameter(format!(
                "at most {STEP_CAPACITY} substeps per submission, got {}",
                constants.len()
            )));
        }
        let Some((_, pipeline)) = &self.pipeline else {
            return Ok(());
        };
        let data: Vec<GpuStep> = constants.iter().map(GpuStep::from).collect();
        self.slots[slot].steps.write(0, bytemuck::cast_slice(&data));
        if let Some(skinned) = &mut self.skinned {
            let joints = std::mem::take(&mut skinned.pending);
            skinned.skin.write_joints(slot, &joints)?;
            let capsules = std::mem::take(&mut skinned.pending_capsules);
            skinned.skin.write_capsules(slot, &capsules);
        }
        let frame = &self.slots[slot];
        let d = &*self.device;
        let raw = &d.raw;
        d.begin_label(cmd, "simulation");
        // Earlier reads of the strand images (drawing, copies) finish before we write.
        memory_barrier(
            d,
            cmd,
            (
                vk::PipelineStageFlags2::ALL_COMMANDS,
                vk::AccessFlags2::SHADER_STORAGE_READ
                    | vk::AccessFlags2::SHADER_STORAGE_WRITE
                    | vk::AccessFlags2::TRANSFER_READ,
            ),
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
        );
        let per_frame = self.params.substeps as usize;
        let frames = constants.len().div_ceil(per_frame);
        // One timestamp before the first dispatch and one after every dispatch.
        if let Some(q) = &frame.timestamps {
            q.reset_first(1 + frames as u32);
            unsafe {
                raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::COMPUTE_SHADER, q.raw(), 0)
            };
        }
        for (index, chunk) in constants.chunks(per_frame).enumerate() {
            let first = (index * per_frame) as u32;
            if let Some(skinned) = &self.skinned {
                skinned.skin.record(cmd, slot, first, chunk.len() as u32);
            }
            let push = [first, chunk.len() as u32, 0];
            d.begin_label(cmd, "simulate frame");
            self.dispatch(cmd, pipeline, frame.sets[textures.current], push);
            d.end_label(cmd);
            textures.current = 1 - textures.current;
            // The next frame reads what this one wrote. The last needs no barrier here:
            // whoever reads the result next (the fur pass, a copy, the next submission)
            // brings its own.
            if index + 1 < frames {
                after_dispatch(d, cmd);
            }
            if let Some(q) = &frame.timestamps {
                let stage = vk::PipelineStageFlags2::COMPUTE_SHADER;
                unsafe { raw.cmd_write_timestamp2(cmd, stage, q.raw(), 1 + index as u32) };
            }
        }
        d.end_label(cmd);
        self.slots[slot].recorded = frames;
        Ok(())
    }

    /// The per-substep constants for the next `frames` frames under `head_at`, advancing
    /// the simulated time.
    pub fn next_constants(
        &mut self,
        frames: usize,
        head_at: impl Fn(f64) -> DMat4,
    ) -> Vec<StepConstants> {
        let h = self.params.substep_dt();
        let mut out = Vec::with_capacity(frames * self.params.substeps as usize);
        for _ in 0..frames * self.params.substeps as usize {
            self.time += h;
            out.push(StepConstants::new(
                &self.params,
                self.time,
                head_at(self.time),
            ));
            if let Some(s) = &mut self.skinned {
                let matrices = s.playback.joint_matrices(&s.body.rig, self.time);
                let capsules = crate::skinning::capsules::pose(&s.body.capsules, &matrices);
                s.pending.extend(matrices);
                s.pending_capsules.extend(capsules);
            }
        }
        out
    }

    /// Puts every strand at its rest shape carried by the body's pose at the current
    /// time and by `head`, not moving (a skinned body's first pose, or a jump in time);
    /// waits for the device.
    pub fn place(&mut self, textures: &StrandTextures, head: DMat4) -> Result<()> {
        let Some((_, pipeline)) = &self.pipeline else {
            return Ok(());
        };
        let constants = [StepConstants::new(&self.params, self.time, head)];
        let data: Vec<GpuStep> = constants.iter().map(GpuStep::from).collect();
        self.slots[0].steps.write(0, bytemuck::cast_slice(&data));
        if let Some(s) = &mut self.skinned {
            let matrices = s.playback.joint_matrices(&s.body.rig, self.time);
            s.pending.clear();
            s.pending_capsules.clear();
            s.skin.write_joints(0, &matrices)?;
        }
        let d = self.device.clone();
        d.submit_once(|cmd| {
            if let Some(skinned) = &self.skinned {
                skinned.skin.record(cmd, 0, 0, 1);
            }
            self.dispatch(
                cmd,
                pipeline,
                self.slots[0].sets[textures.current],
                [0, 1, 1],
            );
            after_dispatch(&d, cmd);
            Ok(())
        })
    }

    /// Simulates `frames` frames in slot 0 and waits for the GPU; returns the GPU
    /// milliseconds per frame of the last submission (NaN without timestamps).
    pub fn run_frames(
        &mut self,
        textures: &mut StrandTextures,
        frames: usize,
        head_at: impl Fn(f64) -> DMat4,
    ) -> Result<f64> {
        let per_submit = (STEP_CAPACITY / self.params.substeps as usize).max(1);
        let mut remaining = frames;
        let mut ms = f64::NAN;
        while remaining > 0 {
            let n = remaining.min(per_submit);
            let constants = self.next_constants(n, &head_at);
            let device = self.device.clone();
            device.submit_once(|cmd| self.record(cmd, 0, textures, &constants))?;
            ms = self.last_gpu_ms(0)? / n as f64;
            remaining -= n;
        }
        Ok(ms)
    }

    /// GPU milliseconds from before the first dispatch of slot `slot`'s last submission
    /// to after its last (NaN without timestamps).
    pub fn last_gpu_ms(&self, slot: usize) -> Result<f64> {
        let frame = &self.slots[slot];
        match &frame.timestamps {
            Some(q) if frame.recorded > 0 => {
                let t = q.timestamps_ms(1 + frame.recorded as u32)?;
                Ok(t.last().copied().unwrap_or(f64::NAN))
            }
            _ => Ok(f64::NAN),
        }
    }
}
