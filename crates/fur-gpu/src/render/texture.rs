//! Sampled images of the render passes: the model's colour texture (uploaded once,
//! with its mips) and the light-space depth map of the fur's shadows.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::target::DEPTH_FORMAT;
use crate::error::{Error, Result};
use crate::gpu::{image_barriers, Access, Buffer, Device, Image, ImageDesc, Sampler, State};
use fur_core::scene::Texture;

/// The model's colour texture on the device: sRGB with its mip chain, trilinear and
/// repeating, read by the fur's geometry stage and the skin's fragment stage.
pub struct GpuTexture {
    pub image: Image,
    pub sampler: Sampler,
    /// Texels in level 0.
    pub texels: f32,
}

impl GpuTexture {
    pub fn upload(device: &Arc<Device>, texture: &Texture) -> Result<Self> {
        let max = device.info.limits.max_image_dimension2_d;
        if texture.width > max || texture.height > max {
            return Err(Error::parameter(format!(
                "the texture is {}×{}; {} samples at most {max}×{max}",
                texture.width, texture.height, device.info.name
            )));
        }
        let levels = texture.levels.len() as u32;
        let image = Image::with_mips(
            device,
            "model.texture",
            ImageDesc {
                extent: vk::Extent2D {
                    width: texture.width,
                    height: texture.height,
                },
                format: vk::Format::R8G8B8A8_SRGB,
                usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
                samples: vk::SampleCountFlags::TYPE_1,
                aspect: vk::ImageAspectFlags::COLOR,
            },
            levels,
        )?;
        let bytes: Vec<u8> = texture.levels.concat();
        let mut staging = Buffer::new(
            device,
            "model.texture.staging",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(0, &bytes);
        let mut offset = 0u64;
        let copies: Vec<vk::BufferImageCopy> = (0..texture.levels.len())
            .map(|level| {
                let (width, height) = texture.level_size(level);
                let copy = vk::BufferImageCopy::default()
                    .buffer_offset(offset)
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: level as u32,
                        base_array_layer: 0,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D {
                        width,
                        height,
                        depth: 1,
                    });
                offset += texture.levels[level].len() as u64;
                copy
            })
            .collect();
        device.submit_once(|cmd| {
            let fresh = State::discarded_after(&[]);
            image_barriers(
                device,
                cmd,
                &Vec::from_iter(image.barrier_after(&fresh, &[Access::TransferWrite])),
            );
            // SAFETY: the one-time command buffer is recording; the image was just transitioned to
            // TRANSFER_DST_OPTIMAL and the staging buffer holds every level the regions name.
            unsafe {
                device.raw.cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw(),
                    image.raw(),
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &copies,
                )
            };
            // Sampled by the geometry and fragment stages from then on.
            let written = State::after(&[Access::TransferWrite]);
            image_barriers(
                device,
                cmd,
                &Vec::from_iter(image.barrier_after(&written, &[Access::ShadingSampled])),
            );
            Ok(())
        })?;
        let sampler = Sampler::new(
            device,
            "model.texture.sampler",
            &vk::SamplerCreateInfo::default()
                .mag_filter(vk::Filter::LINEAR)
                .min_filter(vk::Filter::LINEAR)
                .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
                .address_mode_u(vk::SamplerAddressMode::REPEAT)
                .address_mode_v(vk::SamplerAddressMode::REPEAT)
                .address_mode_w(vk::SamplerAddressMode::REPEAT)
                .max_lod(vk::LOD_CLAMP_NONE),
        )?;
        Ok(Self {
            image,
            sampler,
            texels: (texture.width as f32) * (texture.height as f32),
        })
    }
}

/// The light's view of the fur: the depth of the nearest hair per texel, and a sampler
/// that reads it unfiltered (the shader filters the attenuation, not the depth) with
/// everything outside the map lit.
pub struct ShadowMap {
    pub image: Image,
    pub sampler: Sampler,
    pub resolution: u32,
}

impl ShadowMap {
    pub fn new(device: &Arc<Device>, name: &str, resolution: u32) -> Result<Self> {
        let image = Image::new(
            device,
            name,
            ImageDesc {
                extent: vk::Extent2D {
                    width: resolution,
                    height: resolution,
                },
                format: DEPTH_FORMAT,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                samples: vk::SampleCountFlags::TYPE_1,
                aspect: vk::ImageAspectFlags::DEPTH,
            },
        )?;
        let sampler = Sampler::new(
            device,
            &format!("{name}.sampler"),
            &vk::SamplerCreateInfo::default()
                .mag_filter(vk::Filter::NEAREST)
                .min_filter(vk::Filter::NEAREST)
                .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
                .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_BORDER)
                .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_BORDER)
                .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_BORDER)
                .border_color(vk::BorderColor::FLOAT_OPAQUE_WHITE),
        )?;
        Ok(Self {
            image,
            sampler,
            resolution,
        })
    }
}
