//! The body's distance field on the device: a 3D storage image (`rgba32f`, per grid
//! point the distance and the gradient there), which the kernel reads with `imageLoad`.
//!
//! An image, not a storage buffer: on a CPU driver a buffer read at an index that
//! differs from lane to lane is a loop over the lanes, while an image read is one
//! gather; the skinned body's sampler reads eight grid points per vertex, and as a
//! buffer they were most of its collision's cost (docs/benchmark.md). The values are
//! the same bits either way, so the kernel's arithmetic is unchanged.

use std::sync::Arc;

use ash::vk;
use glam::Vec4;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::{image_barriers, Access, Buffer, Device, Image, ImageDesc, State};
use fur_core::sim::sdf::Sdf;

/// The image holding `sdf` (a single grid point, zero, without a body), left in
/// `GENERAL` layout for the kernel to read.
pub(super) fn upload(device: &Arc<Device>, sdf: Option<&Sdf>) -> Result<Image> {
    let (dims, texels) = match sdf {
        Some(sdf) => (sdf.dims, sdf.texels()),
        None => ([1, 1, 1], vec![[0.0; 4]]),
    };
    let limit = device.info.limits.max_image_dimension3_d;
    if dims.iter().any(|&n| n > limit) {
        return Err(Error::parameter(format!(
            "the distance field's grid ({}×{}×{} points) exceeds this device's largest 3D \
             image ({limit} per side); lower --sdf-resolution",
            dims[0], dims[1], dims[2]
        )));
    }
    let texels: Vec<Vec4> = texels.iter().map(|t| Vec4::from_array(*t)).collect();
    let name = if sdf.is_some() {
        "sim.body_sdf"
    } else {
        "sim.no_body"
    };
    volume(
        device,
        name,
        dims,
        vk::Format::R32G32B32A32_SFLOAT,
        bytemuck::cast_slice(&texels),
    )
}

/// The image holding a skinned body's blend of bones at each grid point of `sdf` (see
/// [`fur_core::skinning::blend`]; `rgba32ui`, two grid points along x per texel, the same
/// grid as the field's), or a single texel of zeros (no blend: the root pose carries
/// every vertex), left in `GENERAL` layout for the kernel to read. Two points to a
/// texel keep to the formats every device can store (`rg32ui` needs a feature).
pub(super) fn upload_blend(
    device: &Arc<Device>,
    blend: Option<(&Sdf, &[fur_core::skinning::blend::Packed])>,
) -> Result<Image> {
    match blend {
        Some((sdf, packed))
            if packed.len()
                == fur_core::skinning::blend::dims(sdf).iter().product::<u32>() as usize =>
        {
            let [nx, ny, nz] = fur_core::skinning::blend::dims(sdf);
            let dims = [nx.div_ceil(2), ny, nz];
            let limit = device.info.limits.max_image_dimension3_d;
            if let Some(why) = fur_core::skinning::blend::misfit(sdf, limit) {
                return Err(Error::parameter(format!(
                    "{why}; lower --sdf-resolution or turn --skin-blend off"
                )));
            }
            let mut texels = vec![[0u32; 4]; (dims[0] * ny * nz) as usize];
            for (row, points) in texels
                .chunks_exact_mut(dims[0] as usize)
                .zip(packed.chunks_exact(nx as usize))
            {
                for (x, point) in points.iter().enumerate() {
                    let half = 2 * (x % 2);
                    row[x / 2][half..half + 2].copy_from_slice(point);
                }
            }
            volume(
                device,
                "sim.body_blend",
                dims,
                vk::Format::R32G32B32A32_UINT,
                bytemuck::cast_slice(&texels),
            )
        }
        _ => volume(
            device,
            "sim.no_blend",
            [1, 1, 1],
            vk::Format::R32G32B32A32_UINT,
            &[0u8; 16],
        ),
    }
}

/// A 3D storage image of `dims` 16-byte texels of `format` holding `bytes`, in
/// `GENERAL` layout.
fn volume(
    device: &Arc<Device>,
    name: &str,
    dims: [u32; 3],
    format: vk::Format,
    bytes: &[u8],
) -> Result<Image> {
    let image = Image::volume(
        device,
        name,
        ImageDesc {
            extent: vk::Extent2D {
                width: dims[0],
                height: dims[1],
            },
            format,
            usage: vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_DST,
            samples: vk::SampleCountFlags::TYPE_1,
            aspect: vk::ImageAspectFlags::COLOR,
        },
        dims[2],
    )?;
    let mut staging = Buffer::new(
        device,
        &format!("{name}.staging"),
        bytes.len() as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    staging.write(0, bytes);
    let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
    let region = vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D {
            width: dims[0],
            height: dims[1],
            depth: dims[2],
        });
    device.submit_once(|cmd| {
        let fresh = State::discarded_after(&[]);
        image_barriers(
            device,
            cmd,
            &Vec::from_iter(image.barrier_after(&fresh, &[Access::TransferWrite])),
        );
        // SAFETY: `cmd` is recording (inside `submit_once`); the staging buffer holds
        // all of `bytes`, which is the whole volume of `region`, and the image, of
        // those dimensions, was just moved to TRANSFER_DST_OPTIMAL by the barrier
        // above; both outlive the submission, which waits.
        unsafe {
            device
                .raw
                .cmd_copy_buffer_to_image(cmd, staging.raw(), image.raw(), dst, &[region])
        };
        // Read as storage by the simulation's kernel from then on.
        let written = State::after(&[Access::TransferWrite]);
        image_barriers(
            device,
            cmd,
            &Vec::from_iter(image.barrier_after(&written, &[Access::ComputeRead])),
        );
        Ok(())
    })?;
    Ok(image)
}
