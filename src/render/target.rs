//! The offscreen render target: 4× MSAA colour and depth, resolved into a single-sample
//! image that is copied to a host-visible buffer for PNG output.

use std::path::Path;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::{image_barriers, whole_image_copy, Buffer, Device, Image, ImageDesc};

pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
pub const SAMPLES: vk::SampleCountFlags = vk::SampleCountFlags::TYPE_4;

/// Colour, depth, resolve and readback for one image size.
pub struct RenderTarget {
    pub extent: vk::Extent2D,
    pub color: Image,
    pub depth: Image,
    pub resolve: Image,
    readback: Buffer,
}

impl RenderTarget {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D) -> Result<Self> {
        let limit = device
            .info
            .limits
            .max_framebuffer_width
            .min(device.info.limits.max_framebuffer_height);
        if extent.width == 0 || extent.height == 0 || extent.width > limit || extent.height > limit
        {
            return Err(Error::Parameter(format!(
                "image size {}×{} must be between 1×1 and {limit}×{limit}",
                extent.width, extent.height
            )));
        }
        let color = Image::new(
            device,
            "target.color",
            ImageDesc {
                extent,
                format: COLOR_FORMAT,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                samples: SAMPLES,
                aspect: vk::ImageAspectFlags::COLOR,
            },
        )?;
        let depth = Image::new(
            device,
            "target.depth",
            ImageDesc {
                extent,
                format: DEPTH_FORMAT,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                samples: SAMPLES,
                aspect: vk::ImageAspectFlags::DEPTH,
            },
        )?;
        let resolve = Image::new(
            device,
            "target.resolve",
            ImageDesc {
                extent,
                format: COLOR_FORMAT,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
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
            color,
            depth,
            resolve,
            readback,
        })
    }

    /// Transitions the attachments for rendering (contents discarded). The source
    /// scopes cover the previous frame's use of the same images, which may still be in
    /// flight: its attachment writes and the copy or blit that read the resolve image.
    pub fn begin(&self, device: &Device, cmd: vk::CommandBuffer) {
        let color_out = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ,
        );
        let depth_out = (
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
        );
        let earlier_color = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let earlier_depth = (
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
        );
        let earlier_resolve = (
            vk::PipelineStageFlags2::COPY
                | vk::PipelineStageFlags2::BLIT
                | vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::TRANSFER_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let undefined = vk::ImageLayout::UNDEFINED;
        image_barriers(
            device,
            cmd,
            &[
                self.color.barrier(
                    earlier_color,
                    color_out,
                    undefined,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
                self.depth.barrier(
                    earlier_depth,
                    depth_out,
                    undefined,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                ),
                self.resolve.barrier(
                    earlier_resolve,
                    color_out,
                    undefined,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
            ],
        );
    }

    /// Copies the resolved image into the readback buffer.
    pub fn copy_out(&self, device: &Device, cmd: vk::CommandBuffer) {
        self.finish(device, cmd);
        self.copy_to_readback(device, cmd);
    }

    /// Makes the resolved image a transfer source (for copies and blits).
    pub fn finish(&self, device: &Device, cmd: vk::CommandBuffer) {
        image_barriers(
            device,
            cmd,
            &[self.resolve.barrier(
                (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
                (
                    vk::PipelineStageFlags2::COPY | vk::PipelineStageFlags2::BLIT,
                    vk::AccessFlags2::TRANSFER_READ,
                ),
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            )],
        );
    }

    /// Copies the finished resolved image into the readback buffer.
    pub fn copy_to_readback(&self, device: &Device, cmd: vk::CommandBuffer) {
        let region = whole_image_copy(self.extent, 0);
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

/// An 8-bit RGBA image in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

impl RgbaImage {
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ]
    }

    /// Rec. 709 luma of the (sRGB-encoded) pixel, 0..1.
    pub fn luma(&self, x: u32, y: u32) -> f32 {
        let [r, g, b, _] = self.pixel(x, y);
        (0.2126 * f32::from(r) + 0.7152 * f32::from(g) + 0.0722 * f32::from(b)) / 255.0
    }

    pub fn write_png(&self, path: &Path) -> Result<()> {
        let error = |message: String| Error::ImageWrite {
            path: path.to_path_buf(),
            message,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| error(e.to_string()))?;
        }
        let file = std::fs::File::create(path).map_err(|e| error(e.to_string()))?;
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header().map_err(|e| error(e.to_string()))?;
        writer
            .write_image_data(&self.data)
            .map_err(|e| error(e.to_string()))?;
        writer.finish().map_err(|e| error(e.to_string()))
    }
}
