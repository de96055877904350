//! Strand textures: master-hair vertices in RGBA32F images shared by the simulation
//! (which ping-pongs them) and the fur pass (which reads the current one).
//!
//! Layout: strand `s` occupies `V` consecutive texels of one row (a 1×V tile); a row
//! holds `strands_per_row = ⌊max_width / V⌋` strands and rows stack downwards. The
//! seed's one-row-per-strand layout capped the mesh at the maximum image height
//! (16,384 on lavapipe); this one holds `⌊16384 / V⌋ × 16384` strands (over 15 million
//! at 17 vertices).

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::{
    image_barriers, whole_image_copy, Access, Buffer, Device, Image, ImageDesc, Sampler, State,
};
use fur_core::scene::Strands;

/// Where each strand vertex lives in the strand textures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StrandLayout {
    pub vertices_per_strand: u32,
    pub strand_count: u32,
    pub strands_per_row: u32,
    pub width: u32,
    pub height: u32,
}

impl StrandLayout {
    pub fn new(vertices_per_strand: u32, strand_count: u32, max_dimension: u32) -> Result<Self> {
        if vertices_per_strand < 2 || vertices_per_strand > max_dimension {
            return Err(Error::parameter(format!(
                "strands need 2..={max_dimension} vertices, got {vertices_per_strand}"
            )));
        }
        if strand_count == 0 {
            return Err(Error::parameter("there are no master hairs to store"));
        }
        let strands_per_row = (max_dimension / vertices_per_strand).min(strand_count);
        let height = strand_count.div_ceil(strands_per_row);
        if height > max_dimension {
            return Err(Error::parameter(format!(
                "{strand_count} master hairs of {vertices_per_strand} vertices exceed the device's \
                 {max_dimension}×{max_dimension} strand texture"
            )));
        }
        Ok(Self {
            vertices_per_strand,
            strand_count,
            strands_per_row,
            width: strands_per_row * vertices_per_strand,
            height,
        })
    }

    /// Texel (x, y) of vertex `vertex` of strand `strand`.
    pub fn texel(&self, strand: u32, vertex: u32) -> (u32, u32) {
        (
            (strand % self.strands_per_row) * self.vertices_per_strand + vertex,
            strand / self.strands_per_row,
        )
    }

    fn texel_count(&self) -> usize {
        (self.width * self.height) as usize
    }

    /// Lays out one value per strand vertex as image rows (unused texels are zero).
    fn texels_from(&self, values: impl Iterator<Item = Vec4>) -> Vec<Vec4> {
        let mut texels = vec![Vec4::ZERO; self.texel_count()];
        let v = self.vertices_per_strand;
        for (i, value) in values.enumerate() {
            let (x, y) = self.texel(i as u32 / v, i as u32 % v);
            texels[(y * self.width + x) as usize] = value;
        }
        texels
    }
}

/// The strand images on the GPU.
pub struct StrandTextures {
    device: Arc<Device>,
    pub layout: StrandLayout,
    /// Rest positions in model space; w = rest length of the segment ending here
    /// (filled in by the simulation's rest pass).
    pub rest: Image,
    /// Each segment's rest vector in its parent's frame (see [`fur_core::sim::RestPose`]);
    /// computed on the GPU by the simulation's rest pass.
    pub rest_local: Image,
    /// World-space positions, ping-ponged by the simulation, which writes them as storage
    /// images; the hair stages read them as textures (`texelFetch`) through `sampler`.
    pub positions: [Image; 2],
    /// How the hair stages read `positions`: nearest, clamped (`texelFetch` filters
    /// nothing, but a sampled image is bound with a sampler).
    pub sampler: Sampler,
    /// Which of `positions` holds the current state.
    pub current: usize,
    /// Per strand, the root frame's three columns (3 × vec4); from the rest pass.
    pub root_frames: Buffer,
    /// Length of the longest master hair (rest pose), scene units.
    pub hair_length: f32,
    /// The coat's mean height above the skin (rest pose; [`Strands::coat_height`]).
    pub coat_height: f32,
    /// The simulation view's arrows: per strand vertex (strand-major), the correction
    /// the chosen step made in the last substep simulated (xyz; `GpuSim::set_probe`).
    /// A placeholder until [`StrandTextures::ensure_probe`] sizes it.
    pub probe: Buffer,
}

pub const STRAND_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

impl StrandTextures {
    /// Uploads `strands` posed by `head` as both the current and previous state.
    pub fn new(device: &Arc<Device>, strands: &Strands, head: Mat4) -> Result<Self> {
        let max_dimension = device.info.limits.max_image_dimension2_d;
        let layout = StrandLayout::new(
            strands.vertices_per_strand,
            strands.count() as u32,
            max_dimension,
        )?;
        let desc = ImageDesc {
            extent: vk::Extent2D {
                width: layout.width,
                height: layout.height,
            },
            format: STRAND_FORMAT,
            usage: vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::TRANSFER_SRC,
            samples: vk::SampleCountFlags::TYPE_1,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let rest = Image::new(device, "strands.rest", desc)?;
        let rest_local = Image::new(device, "strands.rest_local", desc)?;
        let positions = [
            Image::new(device, "strands.positions[0]", desc)?,
            Image::new(device, "strands.positions[1]", desc)?,
        ];
        let root_frames = Buffer::new(
            device,
            "strands.root_frames",
            u64::from(layout.strand_count) * 3 * std::mem::size_of::<Vec4>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let sampler = Sampler::nearest(device, "strands.positions.sampler")?;
        let textures = Self {
            device: device.clone(),
            layout,
            rest,
            rest_local,
            positions,
            sampler,
            current: 0,
            root_frames,
            hair_length: strands.hair_length(),
            coat_height: strands.coat_height(),
            probe: Self::probe_buffer(device, 1)?,
        };
        let rest_texels = layout.texels_from(strands.positions.iter().map(|p| p.extend(0.0)));
        let posed = layout.texels_from(
            strands
                .positions
                .iter()
                .map(|p| head.transform_point3(*p).extend(1.0)),
        );
        // Both position images start from the same posed data: one staging copy serves
        // both. The rest-local image is filled on the GPU by the simulation's rest pass
        // and only needs its layout.
        textures.upload(
            &[&rest_texels, &posed],
            &[
                (&textures.rest, 0),
                (&textures.positions[0], 1),
                (&textures.positions[1], 1),
            ],
            &textures.rest_local,
        )?;
        Ok(textures)
    }

    fn probe_buffer(device: &Arc<Device>, vertices: u64) -> Result<Buffer> {
        Buffer::new(
            device,
            "strands.probe",
            vertices * std::mem::size_of::<Vec4>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )
    }

    /// Sizes [`StrandTextures::probe`] for every strand vertex, zeroed; true when it
    /// was the placeholder (descriptor sets holding it must be written again). No
    /// frame may be in flight.
    pub fn ensure_probe(&mut self) -> Result<bool> {
        let vertices = u64::from(self.layout.strand_count * self.layout.vertices_per_strand);
        if self.probe.size() >= vertices * std::mem::size_of::<Vec4>() as u64 {
            return Ok(false);
        }
        let probe = Self::probe_buffer(&self.device, vertices)?;
        self.device.submit_once(|cmd| {
            // SAFETY: `cmd` is recording (inside `submit_once`); the buffer is new and
            // has TRANSFER_DST usage; the submission waits.
            unsafe {
                self.device
                    .raw
                    .cmd_fill_buffer(cmd, probe.raw(), 0, vk::WHOLE_SIZE, 0)
            };
            Ok(())
        })?;
        self.probe = probe;
        Ok(true)
    }

    /// The probe's arrows read back, one per strand vertex (strand-major). For tests
    /// and tools; waits for the GPU.
    pub fn read_probe(&self) -> Result<Vec<Vec4>> {
        Ok(bytemuck::pod_collect_to_vec(&self.probe.read_back()?))
    }

    fn extent(&self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.layout.width,
            height: self.layout.height,
        }
    }

    /// The image holding the current positions.
    pub fn current_positions(&self) -> &Image {
        &self.positions[self.current]
    }

    /// Copies `data[k]` into every image that names `k`, and leaves those images and
    /// `layout_only` (contents undefined) in `GENERAL` layout for storage use.
    fn upload(
        &self,
        data: &[&Vec<Vec4>],
        images: &[(&Image, usize)],
        layout_only: &Image,
    ) -> Result<()> {
        let texel_bytes = std::mem::size_of::<Vec4>();
        let total: usize = data.iter().map(|t| t.len() * texel_bytes).sum();
        let mut staging = Buffer::new(
            &self.device,
            "strands.staging",
            total as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        let mut offsets = Vec::new();
        let mut offset = 0usize;
        for texels in data {
            let bytes: &[u8] = bytemuck::cast_slice(texels.as_slice());
            staging.write(offset, bytes);
            offsets.push(offset as u64);
            offset += bytes.len();
        }
        let d = &self.device;
        let extent = self.extent();
        let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        // Once filled, the images are read and written as storage by the kernels and
        // sampled by the hair stages.
        let storage = [Access::ComputeWrite, Access::HairStagesSampled];
        let fresh = State::discarded_after(&[]);
        d.submit_once(|cmd| {
            let mut to_dst: Vec<_> = images
                .iter()
                .filter_map(|(image, _)| image.barrier_after(&fresh, &[Access::TransferWrite]))
                .collect();
            to_dst.extend(layout_only.barrier_after(&fresh, &storage));
            image_barriers(d, cmd, &to_dst);
            for (image, k) in images {
                let region = whole_image_copy(extent, offsets[*k]);
                // SAFETY: `cmd` is recording (inside `submit_once`); the image is in
                // TRANSFER_DST_OPTIMAL (barrier above), and the region, `extent` texels
                // from `offsets[k]`, lies within the staging buffer, which holds every
                // data set back to back; both outlive the submission, which waits.
                unsafe {
                    d.raw
                        .cmd_copy_buffer_to_image(cmd, staging.raw(), image.raw(), dst, &[region])
                };
            }
            let written = State::after(&[Access::TransferWrite]);
            let to_general: Vec<_> = images
                .iter()
                .filter_map(|(image, _)| image.barrier_after(&written, &storage))
                .collect();
            image_barriers(d, cmd, &to_general);
            Ok(())
        })
    }

    /// Reads back the current (`which = current`) or other position image as one
    /// position per strand vertex. For tests and tools; waits for the GPU.
    pub fn read_positions(&self, which: usize) -> Result<Vec<Vec3>> {
        Ok(self
            .read_vertices(which)?
            .into_iter()
            .map(Vec4::truncate)
            .collect())
    }

    /// [`StrandTextures::read_positions`] with each texel's w: 1, or the simulation
    /// kernel's probe where it writes one (`GpuSim::set_probe`).
    pub fn read_vertices(&self, which: usize) -> Result<Vec<Vec4>> {
        let texel_data = self.read_texels(which)?;
        let l = self.layout;
        Ok((0..l.strand_count * l.vertices_per_strand)
            .map(|i| {
                let (x, y) = l.texel(i / l.vertices_per_strand, i % l.vertices_per_strand);
                texel_data[(y * l.width + x) as usize]
            })
            .collect())
    }

    /// Test hook: the position image's texels as stored, row by row, so a test can
    /// check the layout without going through [`StrandLayout::texel`] both ways.
    #[doc(hidden)]
    pub fn read_texels(&self, which: usize) -> Result<Vec<Vec4>> {
        let image = &self.positions[which];
        let texels = self.layout.texel_count();
        let size = (texels * std::mem::size_of::<Vec4>()) as u64;
        let buffer = Buffer::new(
            &self.device,
            "strands.readback",
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let d = &self.device;
        let extent = self.extent();
        d.submit_once(|cmd| {
            // Last read and written as storage (and sampled); copied from; storage again.
            let storage = [Access::ComputeWrite, Access::HairStagesSampled];
            let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            let to_copy = image.barrier_after(&State::after(&storage), &[Access::TransferRead]);
            image_barriers(d, cmd, &Vec::from_iter(to_copy));
            let region = whole_image_copy(extent, 0);
            // SAFETY: `cmd` is recording (inside `submit_once`); the image was moved to
            // TRANSFER_SRC_OPTIMAL by the barrier above, and the buffer holds exactly
            // its `extent` of 16-byte texels; both outlive the submission, which waits.
            unsafe {
                d.raw
                    .cmd_copy_image_to_buffer(cmd, image.raw(), src, buffer.raw(), &[region])
            };
            let back = image.barrier_after(&State::after(&[Access::TransferRead]), &storage);
            image_barriers(d, cmd, &Vec::from_iter(back));
            Ok(())
        })?;
        let texel_data: &[Vec4] = bytemuck::cast_slice(buffer.mapped());
        Ok(texel_data[..texels].to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_tiles_more_strands_than_the_maximum_dimension() {
        let l = StrandLayout::new(17, 50_000, 16_384).unwrap();
        assert_eq!(l.strands_per_row, 963);
        assert!(l.height <= 16_384 && l.width <= 16_384);
        // Every vertex maps to a distinct texel inside the image.
        let mut seen = std::collections::HashSet::new();
        for s in (0..50_000).step_by(7) {
            for v in 0..17 {
                let (x, y) = l.texel(s, v);
                assert!(x < l.width && y < l.height);
                assert!(seen.insert((x, y)));
            }
        }
    }

    #[test]
    fn layout_rejects_what_cannot_fit() {
        assert!(StrandLayout::new(17, 0, 16_384).is_err());
        assert!(StrandLayout::new(1, 10, 16_384).is_err());
        assert!(StrandLayout::new(64, 64 * 64 + 1, 64 * 64 / 64).is_err());
    }
}
