//! Recording the simulation: the per-substep constants, the dispatches of a
//! submission with their barriers and timestamps, placing strands on a pose, and the
//! blocking helper that runs whole frames.

use ash::vk;
use glam::DMat4;

use super::*;
use crate::frame::{record_memory_uses, uses, Resource};
use crate::gpu::{Access, Tracker};

impl GpuSim {
    fn group_count(&self) -> u32 {
        self.strand_count.div_ceil(GROUP_SIZE)
    }

    /// Declares the uses of the kernel's next dispatch to `tracker`, which records the
    /// barriers they need: it writes the strand positions (and the probe's arrows) and
    /// reads a skinned body's root poses.
    pub(super) fn declare_uses(&self, cmd: vk::CommandBuffer, tracker: &mut Tracker<Resource>) {
        let mut list = vec![uses(Resource::Positions, Access::ComputeWrite)];
        if self.skinned.is_some() {
            list.push(uses(Resource::Posed, Access::ComputeRead));
        }
        if self.probe().is_some() {
            list.push(uses(Resource::Probe, Access::ComputeWrite));
        }
        record_memory_uses(&self.device, cmd, tracker, &list);
    }

    /// Records one dispatch of `pipeline` over every strand with descriptor set `set`
    /// and push constants `push` (first substep, substeps, placement).
    pub(super) fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        set: vk::DescriptorSet,
        push: [u32; 3],
    ) {
        let raw = &self.device.raw;
        // SAFETY: callers pass a command buffer of this device in the recording state,
        // outside a rendering; `pipeline` was built with `self.layout`, the push
        // constants fit its 12-byte COMPUTE range, and `set` is one of this
        // simulation's sets, written at creation, whose resources `self` keeps alive.
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
        tracker: &mut Tracker<Resource>,
        slot: usize,
        textures: &mut StrandTextures,
        constants: &[StepConstants],
    ) -> Result<()> {
        if constants.len() > STEP_CAPACITY {
            return Err(Error::parameter(format!(
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
            let bones = std::mem::take(&mut skinned.pending_bones);
            if !bones.is_empty() {
                skinned.skin.write_bones(slot, &bones);
            }
        }
        let frame = &self.slots[slot];
        let d = &*self.device;
        let raw = &d.raw;
        d.begin_label(cmd, "simulation");
        let per_frame = self.params.substeps as usize;
        let frames = constants.len().div_ceil(per_frame);
        // One timestamp before the first dispatch and one after every dispatch.
        if let Some(q) = &frame.timestamps {
            q.reset_first(1 + frames as u32);
            // SAFETY: `cmd` is recording; the slot's timestamp pool has room for `1 +
            // frames` queries (at most STEP_CAPACITY frames, checked above) and query 0
            // was just reset.
            unsafe {
                raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::COMPUTE_SHADER, q.raw(), 0)
            };
        }
        for (index, chunk) in constants.chunks(per_frame).enumerate() {
            let first = (index * per_frame) as u32;
            if let Some(skinned) = &self.skinned {
                skinned
                    .skin
                    .record(cmd, tracker, slot, first, chunk.len() as u32);
            }
            self.declare_uses(cmd, tracker);
            let push = [first, chunk.len() as u32, 0];
            d.begin_label(cmd, "simulate frame");
            self.dispatch(cmd, pipeline, frame.sets[textures.current], push);
            d.end_label(cmd);
            textures.current = 1 - textures.current;
            if let Some(q) = &frame.timestamps {
                let stage = vk::PipelineStageFlags2::COMPUTE_SHADER;
                // SAFETY: `cmd` is recording and query `1 + index` lies within the
                // range reset above (`index < frames`).
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
                let capsules = fur_core::skinning::capsules::pose(&s.body.capsules, &matrices);
                if self.params.blends() {
                    let rows =
                        fur_core::skinning::blend::bone_rows(&matrices, &s.body.rest_inverse);
                    s.pending_bones.extend(rows);
                }
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
            s.pending_bones.clear();
            s.skin.write_joints(0, &matrices)?;
        }
        let d = self.device.clone();
        d.submit_once(|cmd| {
            let mut tracker = crate::frame::tracker();
            if let Some(skinned) = &self.skinned {
                skinned.skin.record(cmd, &mut tracker, 0, 0, 1);
            }
            self.declare_uses(cmd, &mut tracker);
            self.dispatch(
                cmd,
                pipeline,
                self.slots[0].sets[textures.current],
                [0, 1, 1],
            );
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
            device.submit_once(|cmd| {
                self.record(cmd, &mut crate::frame::tracker(), 0, textures, &constants)
            })?;
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
