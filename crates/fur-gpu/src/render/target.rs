//! The offscreen render target: colour and depth at the chosen sample count; with
//! MSAA the colour is resolved into a single-sample image, without it that image is
//! drawn into directly. The single-sample image is copied to a host-visible buffer for
//! PNG output, or blitted to a window.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::{
    barrier, image_barriers, whole_image_copy, Access, Buffer, Device, Image, ImageDesc, State,
};
use fur_core::render::RgbaImage;

/// What a renderer draws into: the target's size, the frames in flight (each with its
/// own uniforms and sets) and the samples per pixel.
#[derive(Clone, Copy, Debug)]
pub struct TargetSpec {
    pub extent: vk::Extent2D,
    pub frames_in_flight: usize,
    pub samples: u32,
}

pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The sample-count flag for `samples` per pixel.
pub fn sample_flag(samples: u32) -> vk::SampleCountFlags {
    vk::SampleCountFlags::from_raw(samples)
}

/// The sample counts per pixel the device renders colour and depth at.
pub fn supported_samples(device: &Device) -> Vec<u32> {
    let limits = &device.info.limits;
    let supported = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
    (0..7)
        .map(|b| 1u32 << b)
        .filter(|n| supported.contains(sample_flag(*n)))
        .collect()
}

/// Checks that the device renders colour and depth at `samples` per pixel.
pub fn check_samples(device: &Device, samples: u32) -> Result<()> {
    let supported = supported_samples(device);
    if supported.contains(&samples) {
        return Ok(());
    }
    let counts: Vec<String> = supported.iter().map(u32::to_string).collect();
    Err(Error::parameter(format!(
        "{} cannot render {samples} samples per pixel; it supports {}",
        device.info.name,
        counts.join(", ")
    )))
}

/// Colour, depth, resolve and readback for one image size and sample count.
pub struct RenderTarget {
    pub extent: vk::Extent2D,
    pub samples: u32,
    /// The multisampled colour image (None at one sample per pixel).
    pub color: Option<Image>,
    pub depth: Image,
    /// The single-sample image: resolved into, or drawn into without MSAA.
    pub resolve: Image,
    readback: Buffer,
}

impl RenderTarget {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D, samples: u32) -> Result<Self> {
        check_samples(device, samples)?;
        let limit = device
            .info
            .limits
            .max_framebuffer_width
            .min(device.info.limits.max_framebuffer_height);
        if extent.width == 0 || extent.height == 0 || extent.width > limit || extent.height > limit
        {
            return Err(Error::parameter(format!(
                "image size {}×{} must be between 1×1 and {limit}×{limit}",
                extent.width, extent.height
            )));
        }
        let color = if samples > 1 {
            Some(Image::new(
                device,
                "target.color",
                ImageDesc {
                    extent,
                    format: COLOR_FORMAT,
                    usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                    samples: sample_flag(samples),
                    aspect: vk::ImageAspectFlags::COLOR,
                },
            )?)
        } else {
            None
        };
        let depth = Image::new(
            device,
            "target.depth",
            ImageDesc {
                extent,
                format: DEPTH_FORMAT,
                // Sampled: the compute strand passes hide hair behind the body by it.
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_SRC,
                samples: sample_flag(samples),
                aspect: vk::ImageAspectFlags::DEPTH,
            },
        )?;
        let resolve = Image::new(
            device,
            "target.resolve",
            ImageDesc {
                extent,
                format: COLOR_FORMAT,
                // Sampled and copied into: the compute strand passes composite over it.
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_DST,
                samples: vk::SampleCountFlags::TYPE_1,
                aspect: vk::ImageAspectFlags::COLOR,
            },
        )?;
        let readback = Buffer::new(
            device,
            "target.readback",
            u64::from(extent.width) * u64::from(extent.height) * 4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            extent,
            samples,
            color,
            depth,
            resolve,
            readback,
        })
    }

    /// The colour attachment of a rendering scope: the multisampled image resolved
    /// into the single-sample one, or the single-sample image itself.
    pub fn color_attachment(&self, clear: vk::ClearValue) -> vk::RenderingAttachmentInfo<'static> {
        let attachment = vk::RenderingAttachmentInfo::default()
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .clear_value(clear);
        match &self.color {
            Some(color) => attachment
                .image_view(color.view())
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(self.resolve.view())
                .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .store_op(vk::AttachmentStoreOp::DONT_CARE),
            None => attachment
                .image_view(self.resolve.view())
                .store_op(vk::AttachmentStoreOp::STORE),
        }
    }

    /// Copies the resolved image into the readback buffer.
    pub fn copy_out(&self, device: &Device, cmd: vk::CommandBuffer) {
        self.finish(device, cmd);
        self.copy_to_readback(device, cmd);
    }

    /// Makes the resolved image a transfer source (for copies and blits), after the
    /// frame's passes drew into it.
    pub fn finish(&self, device: &Device, cmd: vk::CommandBuffer) {
        let drawn = State::after(&[Access::ColorAttachment]);
        let b = barrier(&drawn, &[Access::TransferRead], true).expect("a layout change");
        image_barriers(
            device,
            cmd,
            &[self
                .resolve
                .barrier(b.src, b.dst, b.old_layout, b.new_layout)],
        );
    }

    /// Copies the finished resolved image into the readback buffer.
    pub fn copy_to_readback(&self, device: &Device, cmd: vk::CommandBuffer) {
        let region = whole_image_copy(self.extent, 0);
        // SAFETY: recording; `finish` left the resolved image in TRANSFER_SRC_OPTIMAL, and the
        // readback buffer holds width × height × 4 bytes, the whole copy.
        unsafe {
            device.raw.cmd_copy_image_to_buffer(
                cmd,
                self.resolve.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                self.readback.raw(),
                &[region],
            )
        };
    }

    /// Blits the finished resolved image onto `dst` (in `TRANSFER_DST_OPTIMAL`, same size).
    pub fn blit_to(&self, device: &Device, cmd: vk::CommandBuffer, dst: vk::Image) {
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let corner = vk::Offset3D {
            x: self.extent.width as i32,
            y: self.extent.height as i32,
            z: 1,
        };
        let region = vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner]);
        // SAFETY: recording; the resolved image is a transfer source (`finish`) and `dst` is in
        // TRANSFER_DST_OPTIMAL and as large, as the caller guarantees.
        unsafe {
            device.raw.cmd_blit_image(
                cmd,
                self.resolve.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
                vk::Filter::NEAREST,
            )
        };
    }

    /// The last copied image as tightly packed RGBA8 (sRGB) rows, top row first.
    pub fn pixels(&self) -> RgbaImage {
        RgbaImage {
            width: self.extent.width,
            height: self.extent.height,
            data: self.readback.mapped().to_vec(),
        }
    }
}
