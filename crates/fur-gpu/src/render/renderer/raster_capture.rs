//! What the compute rasteriser drew in the last frame, read back for the tests that
//! compare it with its CPU twin: the strands on the screen, the body's depth, and the
//! hair layer; and the hooks the tests and the bench change it by (the pools' budget,
//! the steps left out).

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::compute_raster::ComputeRaster;
use super::Renderer;
use crate::error::{Error, Result};
use crate::gpu::Buffer;
use crate::gpu::{Access, State};
use fur_core::render::strand_raster::order;
use fur_core::render::strand_raster::pools::{
    PoolBudget, LAYER_BYTES, SEGMENT_BYTES, TILE_BYTES, VERTEX_BYTES,
};
use fur_core::render::strand_raster::{Bins, Segment, StrandVertex};

/// The compute rasteriser's last frame.
#[derive(Clone, Debug)]
pub struct RasterCapture {
    pub width: u32,
    pub height: u32,
    /// The tile side it was binned with, pixels.
    pub tile: u32,
    /// The segments the geometry stage wrote, as the twin takes them.
    pub segments: Vec<Segment>,
    /// The mesh pass's depth per pixel, row by row (NDC z; 1 where no body is).
    pub depth: Vec<f32>,
    /// Per pixel: the hair premultiplied by its coverage, and the light let through.
    pub layer: Vec<[f32; 4]>,
    /// Each tile's list of segments (indices into `segments`' slots), sorted by depth
    /// bin in the order the GPU wrote it, and its stops, as the twin takes them: found
    /// from its entries' bins as the fine pass's pixels find them (`order::bin_ends`).
    pub bins: Bins,
}

impl Renderer {
    /// Sizes later frames' compute pools by `budget` (its tile side aside: the style's
    /// holds), remade at the next frame; for tests that overflow them.
    #[doc(hidden)]
    pub fn force_pool_budget(&mut self, budget: PoolBudget) {
        self.compute_raster.budget = PoolBudget {
            tile: self.compute_raster.budget.tile,
            ..budget
        };
        self.compute_raster.pools = None;
    }

    /// Leaves the compute steps from `STEP_NAMES[kept]` on out of later frames: each is
    /// recorded without its work (its barriers stay), and the image is then not the
    /// frame's. For `fur bench` on a driver whose timestamps between passes misattribute
    /// (lavapipe bins): a step's cost is the frame's with it less the frame's without.
    /// `None` keeps every step.
    #[doc(hidden)]
    pub fn leave_out_raster_steps(&mut self, kept: Option<usize>) {
        let kept = kept.unwrap_or(usize::MAX);
        if self.compute_raster.kept != kept {
            self.compute_raster.kept = kept;
            self.compute_raster.remake_steps();
        }
    }

    /// Reads back the compute rasteriser's last frame (one sample per pixel only: a
    /// multisampled depth cannot be copied out). Waits for the device; for tests.
    #[doc(hidden)]
    pub fn capture_raster(&self, slot: usize) -> Result<RasterCapture> {
        capture(&self.compute_raster, &self.target, slot)
    }
}

fn capture(
    raster: &ComputeRaster,
    target: &super::super::target::RenderTarget,
    slot: usize,
) -> Result<RasterCapture> {
    let pools = raster
        .pools
        .as_ref()
        .ok_or_else(|| Error::parameter("no frame was drawn in compute"))?;
    if target.samples != 1 {
        return Err(Error::parameter("the capture reads one sample per pixel"));
    }
    let counts = raster.counts(slot);
    let words =
        |b: &Buffer| -> Result<Vec<f32>> { Ok(bytemuck::cast_slice(&b.read_back()?).to_vec()) };
    let vertex_floats = words(&pools.vertices.buffer)?;
    let segment_bytes = pools.segments.buffer.read_back()?;
    let segment_words: &[u32] = bytemuck::cast_slice(&segment_bytes);
    let vertex = |i: usize| {
        let v = &vertex_floats[i * (VERTEX_BYTES / 4) as usize..][..8];
        StrandVertex {
            position: [v[0], v[1]],
            depth: v[2],
            width: v[3],
            alpha: v[7],
            color: [v[4], v[5], v[6]],
        }
    };
    let stored = (segment_words.len() / (SEGMENT_BYTES / 4) as usize).min(counts.segments as usize);
    // Slot for slot, so that the lists' indices hold (an empty slot, NO_SEGMENT, is
    // never listed).
    let segments: Vec<Segment> = (0..stored)
        .map(|i| (segment_words[2 * i], segment_words[2 * i + 1]))
        .map(|(first, strand)| match first {
            u32::MAX => Segment {
                a: vertex(0),
                b: vertex(0),
                strand,
            },
            first => Segment {
                a: vertex(first as usize),
                b: vertex(first as usize + 1),
                strand,
            },
        })
        .collect();
    // A tile: body depth, count, offset, kept, cursor, key range, the scatter's halves
    // and a place of the list of tiles that list something (`TileBin`).
    let tile_bytes = pools.tiles.read_back()?;
    let tile_words: &[u32] = bytemuck::cast_slice(&tile_bytes);
    // The layer as the composite takes it: the fine pass leaves a tile that lists
    // nothing unwritten, and the composite takes it clear (strand_composite.comp).
    let layer_floats = words(&pools.layer)?;
    let (width, side) = (target.extent.width, raster.tile());
    let listed = |i: usize| {
        let (x, y) = (i as u32 % width, i as u32 / width);
        let tile = (y / side * pools.columns + x / side) as usize;
        tile_words[tile * (TILE_BYTES / 4) as usize + 3] > 0
    };
    let pixels = (width * target.extent.height) as usize;
    let layer = (0..pixels)
        .map(|i| match listed(i) {
            true => {
                let p = &layer_floats[i * (LAYER_BYTES / 4) as usize..][..4];
                [p[0], p[1], p[2], p[3]]
            }
            false => [0.0, 0.0, 0.0, 1.0],
        })
        .collect();
    let entry_bytes = pools.sorted.buffer.read_back()?;
    let entries: &[u32] = bytemuck::cast_slice(&entry_bytes);
    let tiles = tile_words.chunks_exact((TILE_BYTES / 4) as usize);
    let lists: Vec<Vec<u32>> = tiles
        .clone()
        // A sorted entry: its segment, then a word of the block masks.
        .map(|t| {
            entries[2 * t[2] as usize..][..2 * t[3] as usize]
                .iter()
                .step_by(2)
                .copied()
                .collect()
        })
        .collect();
    let stops = tiles
        .zip(&lists)
        .map(|(t, list)| {
            let lo = f32::from_bits(t[5]);
            let scale = order::bin_scale(lo, f32::from_bits(t[6]));
            // (A slot past the segments read back, which no list should hold, takes a
            // bin of its own.)
            let bin = |&s: &u32| match segments.get(s as usize) {
                Some(g) => order::depth_bin(order::depth_key(g.a.depth, g.b.depth), lo, scale),
                None => u32::MAX,
            };
            order::bin_ends(&list.iter().map(bin).collect::<Vec<_>>())
        })
        .collect();
    let bins = Bins {
        columns: pools.columns,
        rows: pools.rows,
        lists,
        stops,
    };
    Ok(RasterCapture {
        bins,
        width: target.extent.width,
        height: target.extent.height,
        tile: raster.tile(),
        segments,
        depth: read_depth(raster, target)?,
        layer,
    })
}

/// The target's depth, copied out after the frame (which left it sampled by compute).
fn read_depth(
    raster: &ComputeRaster,
    target: &super::super::target::RenderTarget,
) -> Result<Vec<f32>> {
    let device = raster.device();
    let extent = target.extent;
    let staging = Buffer::new(
        device,
        "raster.capture.depth",
        u64::from(extent.width) * u64::from(extent.height) * 4,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    device.submit_once(|cmd| {
        let aspect = vk::ImageAspectFlags::DEPTH;
        // The frame drew the depth and left it sampled by the compute strand passes.
        let drawn = State::after(&[Access::ComputeSampled, Access::DepthAttachment]);
        let to_copy = Vec::from_iter(target.depth.barrier_after(&drawn, &[Access::TransferRead]));
        let copied = State::after(&[Access::TransferRead]);
        let back = Vec::from_iter(
            target
                .depth
                .barrier_after(&copied, &[Access::ComputeSampled]),
        );
        let mut region = crate::gpu::whole_image_copy(extent, 0);
        region.image_subresource.aspect_mask = aspect;
        crate::gpu::image_barriers(device, cmd, &to_copy);
        // SAFETY: recording; the frame has finished (its fence was waited on) and left
        // the depth sampled by compute, moved to TRANSFER_SRC_OPTIMAL by the barrier
        // above; the staging buffer holds the whole copy.
        unsafe {
            device.raw.cmd_copy_image_to_buffer(
                cmd,
                target.depth.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                staging.raw(),
                &[region],
            );
        }
        crate::gpu::image_barriers(device, cmd, &back);
        Ok(())
    })?;
    Ok(
        bytemuck::cast_slice(&staging.mapped()[..(extent.width * extent.height * 4) as usize])
            .to_vec(),
    )
}
