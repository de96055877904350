//! The compute rasteriser's pools on the device: one target size's buffers, sized by
//! `fur_core::render::strand_raster::pools` and held to the device's limits.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::{Buffer, Device, Image, ImageDesc, TexelBuffer};
use fur_core::render::strand_raster::pools::{
    Demand, PoolBudget, PoolSizes, ENTRY_BYTES, SEGMENT_BYTES, SORTED_ENTRY_BYTES,
    VERTEX_TEXEL_BYTES,
};

/// The pools of one target size.
pub(super) struct Pools {
    pub(super) extent: vk::Extent2D,
    pub(super) capacity: Demand,
    pub(super) columns: u32,
    pub(super) rows: u32,
    /// The vertices, the segments and the entries are texel buffers
    /// (`shaders/strand_raster.glsl` says why); a vertex's texels are words, its
    /// position's floats or its colour's, or what lights it under the Marschner model.
    pub(super) vertices: TexelBuffer,
    pub(super) segments: TexelBuffer,
    pub(super) tiles: Buffer,
    pub(super) entries: TexelBuffer,
    /// The entries again, each tile's list sorted front to back by depth bin.
    pub(super) sorted: TexelBuffer,
    pub(super) layer: Buffer,
    /// The hair over the target, sRGB-encoded, copied onto the target.
    pub(super) composited: Image,
}

impl Pools {
    /// The pools for a target of `extent` under `budget`, holding at least `demand`;
    /// refused, with the size named, where they would not fit the device's limits.
    pub(super) fn new(
        device: &Arc<Device>,
        (budget, demand): (&PoolBudget, &Demand),
        extent: vk::Extent2D,
    ) -> Result<Self> {
        let sizes = PoolSizes::of(budget, extent.width, extent.height, demand);
        let pixels = u64::from(extent.width) * u64::from(extent.height);
        let capacity = PoolSizes::capacity(budget, pixels, demand);
        let limits = &device.info.limits;
        let (buffer_limit, texel_limit) = (
            u64::from(limits.max_storage_buffer_range),
            u64::from(limits.max_texel_buffer_elements),
        );
        let gib = |bytes: u64| bytes as f64 / f64::from(1u32 << 30);
        let refuse = |what: String| {
            Err(Error::parameter(format!(
                "the compute rasteriser cannot draw {}×{}: its pools would take {:.1} GiB, \
                 and {what}; draw it smaller or with --raster hardware",
                extent.width,
                extent.height,
                gib(sizes.total()),
            )))
        };
        if sizes.largest_storage() > buffer_limit {
            return refuse(format!(
                "its largest storage buffer {:.1} GiB where {} allows {:.1} GiB",
                gib(sizes.largest_storage()),
                device.info.name,
                gib(buffer_limit),
            ));
        }
        if sizes.most_texels() > texel_limit {
            return refuse(format!(
                "its largest texel buffer {} texels where {} allows {texel_limit}",
                sizes.most_texels(),
                device.info.name,
            ));
        }
        // Transfer sources: the tests read them back (`capture`).
        let storage = |name: &str, size: u64| {
            Buffer::new(
                device,
                name,
                size,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )
        };
        // Read in the passes' loops through texel views (`strand_raster.glsl`); the
        // vertices and segments are also written by the geometry stage as storage
        // buffers (`RasterBinding::VerticesWritten`; `largest_storage` counts them).
        let texels = |name: &str, size: u64, format: vk::Format, bytes: u64, usage| {
            TexelBuffer::with_usage(
                device,
                name,
                size / bytes,
                format,
                bytes,
                vk::BufferUsageFlags::TRANSFER_SRC | usage,
                MemoryLocation::GpuOnly,
            )
        };
        let (written, read) = (
            vk::BufferUsageFlags::STORAGE_BUFFER,
            vk::BufferUsageFlags::empty(),
        );
        Ok(Self {
            extent,
            capacity,
            columns: extent.width.div_ceil(budget.tile),
            rows: extent.height.div_ceil(budget.tile),
            vertices: texels(
                "raster.vertices",
                sizes.vertices,
                vk::Format::R32G32B32A32_UINT,
                VERTEX_TEXEL_BYTES,
                written,
            )?,
            segments: texels(
                "raster.segments",
                sizes.segments,
                vk::Format::R32G32_UINT,
                SEGMENT_BYTES,
                written,
            )?,
            tiles: storage("raster.tiles", sizes.tiles)?,
            entries: texels(
                "raster.entries",
                sizes.entries,
                vk::Format::R32_UINT,
                ENTRY_BYTES,
                read,
            )?,
            sorted: texels(
                "raster.sorted",
                sizes.sorted,
                vk::Format::R32G32_UINT,
                SORTED_ENTRY_BYTES,
                read,
            )?,
            layer: storage("raster.layer", sizes.layer)?,
            composited: Image::new(
                device,
                "raster.composited",
                ImageDesc {
                    extent,
                    format: vk::Format::R8G8B8A8_UNORM,
                    usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
                    samples: vk::SampleCountFlags::TYPE_1,
                    aspect: vk::ImageAspectFlags::COLOR,
                },
            )?,
        })
    }
}
