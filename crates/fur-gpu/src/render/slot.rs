//! The resources of one frame in flight: uniforms, descriptor sets, queries, hair
//! counters, the light's uniforms and the shadow map.

use std::sync::Arc;

use ash::vk;

use super::bindings::write_frame_set;
use super::renderer::Variant;
use super::texture::ShadowMap;
use crate::error::Result;
use crate::gpu::{Buffer, DescriptorPool, DescriptorSetLayout, Device, QueryPool};
use crate::strand_textures::StrandTextures;
use fur_core::render::FrameUniforms;

/// Timestamp slots: the frame's start (before its simulation), the passes' start, after
/// the mesh pass, after the fur pass; when the strands are drawn in compute, after the
/// geometry stage wrote them (`TS_STRANDS`) and after each compute step that follows
/// (`renderer::STEP_NAMES`, in order).
pub(super) const TS_FRAME: u32 = 0;
pub(super) const TS_START: u32 = 1;
pub(super) const TS_MESH: u32 = 2;
pub(super) const TS_FUR: u32 = 3;
pub(super) const TS_STRANDS: u32 = 4;
/// The queries a frame drawn by the fixed-function rasteriser writes.
pub(super) const TS_HARDWARE: u32 = TS_FUR + 1;
pub(super) const TIMESTAMPS: u32 = TS_STRANDS + 1 + super::renderer::STEP_NAMES.len() as u32;

/// The counters' header: hairs drawn, segments drawn, triangles culled, one unused word
/// (the capture that follows it in `shaders/common.glsl` is 16-byte aligned).
pub(super) const COUNTERS_BYTES: u64 = 16;

/// The resources of one frame in flight.
pub(super) struct RenderSlot {
    pub(super) uniforms: Buffer,
    /// One set per possible current position image.
    pub(super) sets: [vk::DescriptorSet; 2],
    pub(super) timestamps: Option<QueryPool>,
    pub(super) statistics: Option<QueryPool>,
    /// Hairs and segments drawn and triangles culled (three u32, then one unused), reset at the start of
    /// every frame; `fur export-frame` swaps in a larger one that captures the hairs.
    pub(super) counters: Buffer,
    /// The fur pipelines this slot's frame draws, chosen by `update`.
    pub(super) variants: Vec<Variant>,
    /// The light's view of the fur: its uniforms and sets (one per position image).
    pub(super) light_uniforms: Buffer,
    pub(super) light_sets: [vk::DescriptorSet; 2],
    /// The shadow map: a 16 × 16 placeholder until a frame draws shadows.
    pub(super) shadow: ShadowMap,
    /// Whether a frame of this slot has drawn shadows.
    pub(super) shadow_drawn: bool,
    /// Whether this slot's frame draws shadows.
    pub(super) shadows: bool,
    /// Whether this slot's frame draws its strands in compute (which timestamps it
    /// writes, whether it has compute counts to report).
    pub(super) compute: bool,
}

impl RenderSlot {
    /// Slot number `slot`'s resources, its frame sets (two for the camera, two for the
    /// light, one per position image) allocated from `pool` with `set_layout`.
    pub(super) fn new(
        device: &Arc<Device>,
        slot: usize,
        pool: &DescriptorPool,
        set_layout: &DescriptorSetLayout,
        strands: &StrandTextures,
    ) -> Result<Self> {
        let uniforms = Buffer::new(
            device,
            &format!("render.uniforms[{slot}]"),
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            gpu_allocator::MemoryLocation::CpuToGpu,
        )?;
        let counters = Buffer::new(
            device,
            &format!("render.counters[{slot}]"),
            COUNTERS_BYTES,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let light_uniforms = Buffer::new(
            device,
            &format!("render.light_uniforms[{slot}]"),
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            gpu_allocator::MemoryLocation::CpuToGpu,
        )?;
        // A placeholder until a frame draws shadows at its own resolution.
        let shadow = ShadowMap::new(device, &format!("shadow_map[{slot}]"), 16)?;
        let sets = pool.allocate(set_layout, 4)?;
        for (i, set) in sets.iter().enumerate() {
            let ubo = if i < 2 { &uniforms } else { &light_uniforms };
            write_frame_set(
                device,
                *set,
                ubo,
                (&strands.positions[i % 2], &strands.sampler),
                &strands.probe,
                &counters,
                &shadow,
            );
        }
        let timestamps = if device.info.timestamps {
            Some(QueryPool::timestamps(
                device,
                &format!("render.timestamps[{slot}]"),
                TIMESTAMPS,
            )?)
        } else {
            None
        };
        let statistics = if device.info.pipeline_statistics {
            Some(QueryPool::fur_statistics(
                device,
                &format!("render.fur_statistics[{slot}]"),
            )?)
        } else {
            None
        };
        Ok(Self {
            uniforms,
            sets: [sets[0], sets[1]],
            timestamps,
            statistics,
            counters,
            variants: Vec::new(),
            light_uniforms,
            light_sets: [sets[2], sets[3]],
            shadow,
            shadow_drawn: false,
            shadows: false,
            compute: false,
        })
    }
}
