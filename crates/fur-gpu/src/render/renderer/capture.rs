//! Capturing the hairs a frame draws, exactly as its geometry stage emits them, for
//! `fur export-frame` and the comparison with the path tracer.
//!
//! The counting form of the fur pass (`COUNT_HAIRS` in `shaders/fur.geom`) writes
//! every hair it counts into the counters' buffer when that buffer has room after its
//! header: a frame is drawn once to count its hairs, then again, unchanged, into a
//! buffer of that size. The capture is the device's own arithmetic (interpolation,
//! jitter, curl, the simulation's state, the density LOD and its thickness
//! compensation), taken before the vertex LOD, which only leaves vertices out.

use ash::vk;
use glam::{Vec3, Vec4};
use gpu_allocator::MemoryLocation;

use super::super::bindings::write_counters;
use super::super::slot::COUNTERS_BYTES;
use super::{FrameSettings, Renderer, RgbaImage};
use crate::error::{size_text, Error, Result};
use crate::gpu::Buffer;
use crate::strand_textures::StrandTextures;

/// The largest capture buffer, in bytes (a frame of about 13 million hairs of 16
/// vertices): beyond it the export is refused before anything is drawn.
pub const MAX_CAPTURE_BYTES: u64 = 7 << 30;

/// The hairs of one frame as drawn, in a fixed order (by each hair's seed, which names
/// it on any device), each `vertices_per_strand` vertices long.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CapturedHairs {
    pub vertices_per_strand: usize,
    /// Per hair and vertex: the world position.
    pub points: Vec<Vec3>,
    /// Per hair and vertex: the hair's true width in world units (the taper, after the
    /// density LOD's thickness compensation; a sub-pixel hair covers its pixels by it).
    pub widths: Vec<f32>,
    /// Per hair and vertex: the width the rasteriser draws, never under the minimum
    /// pixel width.
    pub drawn_widths: Vec<f32>,
    /// Per hair and vertex: the base colour (linear RGB; the ramp and the texture,
    /// before lighting and root occlusion).
    pub colors: Vec<Vec3>,
    /// Per hair: drawn as a ribbon (true) or a line strip.
    pub ribbons: Vec<bool>,
}

impl CapturedHairs {
    /// How many hairs.
    pub fn count(&self) -> usize {
        self.ribbons.len()
    }

    /// Bytes the geometry stage writes per hair of `vertices_per_strand` vertices.
    pub fn bytes_per_hair(vertices_per_strand: u32) -> u64 {
        (2 * u64::from(vertices_per_strand) + 1) * std::mem::size_of::<Vec4>() as u64
    }

    /// Parses `count` hairs written by the geometry stage in `words`.
    fn parse(words: &[Vec4], count: usize, v: usize) -> Self {
        let stride = 2 * v + 1;
        let mut order: Vec<usize> = (0..count).collect();
        // The atomic hands out places in the order the device runs: sort by the seed,
        // then the root's position (two hairs may share a seed by a hash collision).
        let key = |i: usize| {
            let hair = &words[i * stride..];
            let root = hair[0];
            (
                hair[2 * v].x.to_bits(),
                [root.x, root.y, root.z].map(f32::to_bits),
            )
        };
        order.sort_by_key(|&i| key(i));
        let mut hairs = Self {
            vertices_per_strand: v,
            ..Self::default()
        };
        for i in order {
            let hair = &words[i * stride..(i + 1) * stride];
            for k in 0..v {
                hairs.points.push(hair[k].truncate());
                hairs.widths.push(hair[k].w);
                hairs.colors.push(hair[v + k].truncate());
                hairs.drawn_widths.push(hair[v + k].w);
            }
            hairs.ribbons.push(hair[2 * v].y > 0.5);
        }
        hairs
    }
}

impl Renderer {
    /// Draws one frame of the strands' current state twice (the second time unchanged,
    /// capturing every hair) and returns its image with the hairs as drawn. Needs a
    /// device that can store from the geometry stage (`vertexPipelineStoresAndAtomics`).
    pub fn capture(
        &mut self,
        strands: &StrandTextures,
        settings: &FrameSettings,
    ) -> Result<(RgbaImage, CapturedHairs)> {
        if !self.device.info.vertex_pipeline_stores {
            return Err(Error::parameter(
                "this device cannot store from the geometry stage \
                 (vertexPipelineStoresAndAtomics), so the hairs it draws cannot be captured",
            ));
        }
        let mut settings = settings.clone();
        settings.count_hairs = true;
        let (_, report) = self.render(strands, &settings)?;
        let counted = report.counts.map_or(0, |c| c.hairs);
        let v = self.shape.vertices_per_strand;
        let bytes = COUNTERS_BYTES + counted * CapturedHairs::bytes_per_hair(v);
        if bytes > MAX_CAPTURE_BYTES {
            return Err(Error::parameter(format!(
                "the frame draws {counted} hairs of {v} vertices: capturing them takes {}, \
                 over the limit of {}; draw fewer (--density-scale, a smaller image) or \
                 shorter strands",
                size_text(bytes),
                size_text(MAX_CAPTURE_BYTES)
            )));
        }
        let buffer = Buffer::new(
            &self.device,
            "render.capture",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let counters = std::mem::replace(&mut self.slots[0].counters, buffer);
        self.point_counters_at_slot_buffer();
        let drawn = self.render(strands, &settings);
        let buffer = std::mem::replace(&mut self.slots[0].counters, counters);
        self.point_counters_at_slot_buffer();
        let (image, report) = drawn?;
        let again = report.counts.map_or(0, |c| c.hairs);
        if again != counted {
            return Err(Error::parameter(format!(
                "the frame drew {counted} hairs, then {again} when drawn again unchanged: \
                 the device does not draw deterministically, so no capture is exact"
            )));
        }
        let start = COUNTERS_BYTES as usize;
        let end = start + (counted * CapturedHairs::bytes_per_hair(v)) as usize;
        // Copied out (the mapping need not be 16-byte aligned for `Vec4`).
        let words: Vec<Vec4> = bytemuck::pod_collect_to_vec(&buffer.mapped()[start..end]);
        let hairs = CapturedHairs::parse(&words, counted as usize, v as usize);
        Ok((image, hairs))
    }

    /// Points binding 3 of slot 0's frame sets at the slot's counters buffer.
    fn point_counters_at_slot_buffer(&self) {
        let slot = &self.slots[0];
        for set in slot.sets {
            write_counters(&self.device, set, &slot.counters);
        }
    }
}
