//! The simulation in compute shaders: one dispatch per frame of `simulate.comp`, in
//! which one invocation carries one master strand through every substep, running the
//! named steps of Han & Harada in order. The strand textures ping-pong once per frame.
//!
//! Steps a scene does not use are compiled out of the kernel (a specialization
//! constant): the global constraint at S_G = 0 (or an empty range), the local constraint
//! at S_L = 0 or 0 iterations, the length constraint at 0 iterations, wind when its
//! vector is zero.

mod record;

use std::sync::Arc;

use ash::vk;
use glam::{DMat4, UVec3, Vec3, Vec4};
use gpu_allocator::MemoryLocation;

pub use super::kernel::kernel_defines;
use super::kernel::{
    write_sim_set, BodyViews, GpuStep, SimBinding, SimStatic, BODY_BLEND, BODY_SKINNED, PROBE,
    SLEEP,
};
use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, DescriptorPool, DescriptorSetLayout, Device, Pipeline, PipelineLayout, QueryPool,
    Specialization, TexelBuffer,
};
use crate::skinning::{GpuSkin, SkinCapacity};
use crate::strand_textures::StrandTextures;
use fur_core::sim::params::{SimParams, StepConstants};
use fur_core::sim::sdf::Sdf;
pub use fur_core::sim::steps::SimStep;
use fur_core::skinning::{Playback, SkinnedBody};

/// Strands per workgroup (one invocation each).
use crate::gpu::shader::GROUP_SIZE;
/// Most vertices a strand may have (private arrays in the kernel).
pub const MAX_VERTICES: u32 = 64;
/// Substeps whose constants fit in the step buffer: one submission's worth.
const STEP_CAPACITY: usize = 1024;
/// A skinned body and the clip it plays: what a simulation on a skinned body follows
/// ([`GpuSim::build`]).
#[derive(Clone)]
pub struct SkinnedMotion {
    pub body: Arc<SkinnedBody>,
    pub playback: Playback,
}

/// A skinned body's part of the simulation: the skinning pass, the body, which clip
/// plays, and the joint matrices of the substeps not yet recorded.
pub struct Skinned {
    pub skin: GpuSkin,
    pub body: Arc<SkinnedBody>,
    pub playback: Playback,
    pending: Vec<glam::Mat4>,
    pending_capsules: Vec<[Vec4; 2]>,
    pending_bones: Vec<[Vec4; 3]>,
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
    /// The simulation view's probe ([`GpuSim::set_probe`]).
    probe: Option<Option<SimStep>>,
    /// The body's distance field (a 3D image, per grid point its value and gradient; a
    /// placeholder without a body) and its grid.
    _body: crate::gpu::Image,
    /// A skinned body's blend of bones at each of the field's grid points (see
    /// [`fur_core::skinning::blend`]; a placeholder otherwise).
    _blend: crate::gpu::Image,
    /// Whether `_blend` holds a body's blend (built when the simulation is).
    has_blend: bool,
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
        skinned: Option<SkinnedMotion>,
    ) -> Result<Self> {
        let frames_in_flight = frames_in_flight.max(1);
        params.validate()?;
        let vertices = textures.layout.vertices_per_strand;
        if vertices > MAX_VERTICES {
            return Err(Error::parameter(format!(
                "the simulation handles at most {MAX_VERTICES} vertices per strand, got {vertices}"
            )));
        }
        let bindings = SimBinding::set_layout();
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
        let blend_wanted = params.blends() && body.is_some();
        let skinned = match skinned {
            Some(SkinnedMotion { body, playback }) => {
                if body.vertex_count() != textures.layout.strand_count as usize {
                    return Err(Error::parameter(format!(
                        "the skinned body has {} vertices but there are {} strands",
                        body.vertex_count(),
                        textures.layout.strand_count
                    )));
                }
                let skin = GpuSkin::new(
                    device,
                    &body,
                    SkinCapacity {
                        substeps: params.substeps,
                        step_capacity: STEP_CAPACITY,
                        frames_in_flight,
                        bones: blend_wanted,
                    },
                )?;
                Some(Skinned {
                    skin,
                    body,
                    playback,
                    pending: Vec::new(),
                    pending_capsules: Vec::new(),
                    pending_bones: Vec::new(),
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
            vk::Format::R32G32B32A32_SFLOAT,
            16,
            MemoryLocation::CpuToGpu,
        )?;
        let capsules = |slot: usize| {
            skinned
                .as_ref()
                .map_or(&no_capsules, |s: &Skinned| &s.skin.capsules[slot])
        };
        let blend =
            match (&skinned, body) {
                (Some(s), Some(sdf)) if params.blends() => Some(
                    fur_core::skinning::blend::for_body(&s.body, sdf, textures.hair_length)?,
                ),
                _ => None,
            };
        let blend_field = super::field::upload_blend(device, body.zip(blend.as_deref()))?;
        let bones = |slot: usize| {
            skinned
                .as_ref()
                .map_or(&no_capsules, |s: &Skinned| &s.skin.bones[slot])
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
                let views = BodyViews {
                    field: &body_field,
                    root_poses,
                    capsules: capsules(slot),
                    last,
                    blend: &blend_field,
                    bones: bones(slot),
                };
                write_sim_set(device, *set, k, &statics, &steps, textures, &views);
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
            probe: None,
            _body: body_field,
            _blend: blend_field,
            has_blend: blend.is_some(),
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
        Specialization::new(&[(1, self.vertices), (2, steps)])
    }

    /// Runs `simulate_rest.comp` once: local rest vectors, rest lengths, root frames.
    fn compute_rest_data(&self) -> Result<()> {
        let spec = self.specialization(0);
        let pipeline = Pipeline::compute(
            &self.device,
            "simulate_rest.comp",
            &kernel_defines(),
            &self.layout,
            &spec,
        )?;
        let d = &*self.device;
        d.submit_once(|cmd| {
            d.begin_label(cmd, "rest pose");
            self.declare_uses(cmd, &mut crate::frame::tracker());
            self.dispatch(cmd, &pipeline, self.slots[0].sets[0], [0, 0, 0]);
            d.end_label(cmd);
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

    /// The simulation view's probe: None when off, else the step drawn as arrows.
    pub fn probe(&self) -> Option<Option<SimStep>> {
        self.probe
    }

    /// `Some(arrows)`: has the kernel write, into the w of each vertex's new position,
    /// 1 + its distance from its rest shape carried by the body as a fraction of its
    /// strand's rest length, negated when collision pushed it during the frame (the
    /// simulation view reads it; w is 1 otherwise), and, with `arrows`, the correction
    /// that step made in the frame's last substep into [`StrandTextures::probe`]
    /// (sized here). `None`: off. Rebuilds the kernel: no frame may be in flight.
    pub fn set_probe(
        &mut self,
        probe: Option<Option<SimStep>>,
        textures: &mut StrandTextures,
    ) -> Result<()> {
        if matches!(probe, Some(Some(_))) && textures.ensure_probe()? {
            for slot in &self.slots {
                for set in slot.sets {
                    super::kernel::write_probe(&self.device, set, &textures.probe);
                }
            }
        }
        self.probe = probe;
        self.set_params(self.params.clone(), textures)
    }

    /// Changes parameters; rebuilds the kernel when the set of needed steps changes.
    pub fn set_params(&mut self, params: SimParams, textures: &StrandTextures) -> Result<()> {
        params.validate()?;
        let collides = self.grid.is_some();
        let statics = SimStatic {
            global_stiffness: params.global_stiffness,
            local_stiffness: params.local_stiffness,
            collision_margin: if collides {
                params.collision_margin
            } else {
                0.0
            },
            friction: if collides { params.friction } else { 0.0 },
            strand_count: self.strand_count,
            strands_per_row: textures.layout.strands_per_row,
            global_cutoff: params.global_cutoff(self.vertices),
            local_iterations: params.local_iterations,
            length_iterations: params.length_iterations,
            capsule_count: self.skinned.as_ref().map_or(0, |s| s.skin.capsule_count),
            joint_count: self.skinned.as_ref().map_or(0, |s| s.skin.joint_count()),
            probe_step: self.probe.flatten().map_or(0, SimStep::bit),
            sdf_origin: self.grid.map_or(Vec3::ZERO, |g| g.origin),
            cell: self.grid.map_or(0.0, |g| g.cell),
            sdf_dims: self.grid.map_or(UVec3::ZERO, |g| UVec3::from_array(g.dims)),
            inverse_cell: self.grid.map_or(0.0, |g| 1.0 / g.cell),
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
        if self.probe.is_some() {
            mask |= PROBE;
        }
        if let Some(skinned) = &self.skinned {
            if params.substeps > skinned.skin.max_substeps {
                return Err(Error::parameter(format!(
                    "this skinned body can take at most {} substeps per frame, got {}",
                    skinned.skin.max_substeps, params.substeps
                )));
            }
            mask |= BODY_SKINNED;
            if params.blends() && self.grid.is_some() {
                if !self.has_blend {
                    return Err(Error::parameter(
                        "the skin's blend for collision is chosen when the simulation is built, \
                         not changed while it runs",
                    ));
                }
                mask |= BODY_BLEND;
            }
        }
        if self.pipeline.as_ref().map(|(m, _)| *m) != Some(mask) {
            let spec = self.specialization(mask);
            let pipeline = Pipeline::compute(
                &self.device,
                "simulate.comp",
                &kernel_defines(),
                &self.layout,
                &spec,
            )?;
            self.pipeline = Some((mask, pipeline));
        }
        self.params = params;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
