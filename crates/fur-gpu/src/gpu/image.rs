//! Images (2D, and 3D volumes) with one view each, allocated through `gpu-allocator`.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::access::{Access, Scope, State};
use super::Device;
use crate::error::{Error, Result, VkContext};

/// What to create.
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc {
    pub extent: vk::Extent2D,
    pub format: vk::Format,
    pub usage: vk::ImageUsageFlags,
    pub samples: vk::SampleCountFlags,
    pub aspect: vk::ImageAspectFlags,
}

/// A `VkImage`, its memory and a view of the whole image.
pub struct Image {
    device: Arc<Device>,
    pub raw: vk::Image,
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
    pub desc: ImageDesc,
}

impl Image {
    pub fn new(device: &Arc<Device>, name: &str, desc: ImageDesc) -> Result<Self> {
        Self::with_mips(device, name, desc, 1)
    }

    /// An image with `mip_levels` levels (its view and barriers cover them all).
    pub fn with_mips(
        device: &Arc<Device>,
        name: &str,
        desc: ImageDesc,
        mip_levels: u32,
    ) -> Result<Self> {
        Self::create(device, name, desc, mip_levels, None)
    }

    /// A 3D image `depth` slices deep of `desc.extent` each, one level, single-sampled
    /// (a volume such as a distance field, read as a storage image).
    pub fn volume(device: &Arc<Device>, name: &str, desc: ImageDesc, depth: u32) -> Result<Self> {
        Self::create(device, name, desc, 1, Some(depth))
    }

    /// A 2D image (`depth` None) or a 3D one.
    fn create(
        device: &Arc<Device>,
        name: &str,
        desc: ImageDesc,
        mip_levels: u32,
        depth: Option<u32>,
    ) -> Result<Self> {
        let (image_type, view_type) = match depth {
            Some(_) => (vk::ImageType::TYPE_3D, vk::ImageViewType::TYPE_3D),
            None => (vk::ImageType::TYPE_2D, vk::ImageViewType::TYPE_2D),
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(image_type)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.extent.width,
                height: desc.extent.height,
                depth: depth.unwrap_or(1),
            })
            .mip_levels(mip_levels)
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: a create info on a live device; the image is destroyed on the error
        // path below or by Drop.
        let raw = unsafe { device.raw.create_image(&info, None) }.vk("vkCreateImage")?;
        // SAFETY: `raw` was just created from this device.
        let requirements = unsafe { device.raw.get_image_memory_requirements(raw) };
        let allocation = device.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(source) => {
                // SAFETY: `raw` was just created, has no memory bound and was never
                // used.
                unsafe { device.raw.destroy_image(raw, None) };
                return Err(Error::Allocation {
                    name: name.into(),
                    bytes: requirements.size,
                    source: Box::new(source),
                });
            }
        };
        let mut image = Self {
            device: device.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: Some(allocation),
            desc,
        };
        let a = image.allocation.as_ref().expect("allocation was just set");
        // SAFETY: the allocation was made for `raw`'s own memory requirements (size,
        // alignment, memory types); the image has no memory bound yet.
        unsafe { device.raw.bind_image_memory(raw, a.memory(), a.offset()) }
            .vk("vkBindImageMemory")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(view_type)
            .format(desc.format)
            .subresource_range(subresource_range(desc.aspect));
        image.view =
            // SAFETY: `raw` has its memory bound, and the view matches it: its format,
            // a view type of its image type, and every level of its single layer.
            unsafe { device.raw.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        device.set_name(raw, name);
        device.set_name(image.view, name);
        Ok(image)
    }

    pub fn raw(&self) -> vk::Image {
        self.raw
    }

    pub fn view(&self) -> vk::ImageView {
        self.view
    }

    /// The barrier a use of the whole image by `next` needs after `before`, derived
    /// from the two ([`super::access::barrier`]: stages, access masks and layouts);
    /// None when none is needed. What an upload or a read-back outside a frame records
    /// around its copy.
    pub fn barrier_after(
        &self,
        before: &State,
        next: &[Access],
    ) -> Option<vk::ImageMemoryBarrier2<'static>> {
        super::access::barrier(before, next, true)
            .map(|b| self.barrier(b.src, b.dst, b.old_layout, b.new_layout))
    }

    /// A layout transition (and memory dependency) for the whole image.
    pub fn barrier(
        &self,
        src: Scope,
        dst: Scope,
        old_layout: vk::ImageLayout,
        new_layout: vk::ImageLayout,
    ) -> vk::ImageMemoryBarrier2<'static> {
        image_barrier(self.raw, self.desc.aspect, src, dst, old_layout, new_layout)
    }
}

/// A layout transition (and memory dependency) for the whole of any image, including
/// ones this crate does not own (swapchain images).
pub fn image_barrier(
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    src: Scope,
    dst: Scope,
    old_layout: vk::ImageLayout,
    new_layout: vk::ImageLayout,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src.stages)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stages)
        .dst_access_mask(dst.access)
        .old_layout(old_layout)
        .new_layout(new_layout)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(subresource_range(aspect))
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the view was created from this image (or is null, skipped) and is
        // destroyed once; owners wait for the device before dropping an image, so no
        // command or descriptor in use refers to it.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.device.raw.destroy_image_view(self.view, None);
            }
        }
        if let Some(allocation) = self.allocation.take() {
            let _ = self.device.allocator().free(allocation);
        }
        // SAFETY: the image is owned here, its view is gone and its memory freed above;
        // no submission still uses it (owners wait for the device first).
        unsafe { self.device.raw.destroy_image(self.raw, None) };
    }
}

/// A buffer↔image copy of a whole single-layer colour image of `extent`, the buffer
/// tightly packed from `buffer_offset`.
pub fn whole_image_copy(
    extent: vk::Extent2D,
    buffer_offset: vk::DeviceSize,
) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .buffer_offset(buffer_offset)
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
}

/// Every mip level and the single layer of an image.
pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: vk::REMAINING_MIP_LEVELS,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// Every stage that reads or writes the strand images, the skinned body and the other
/// tables the passes share: the shader stages, vertex input and copies. Barriers name
/// these instead of `ALL_COMMANDS`, which also waits for stages that never touch them.
pub const SHARED_DATA_STAGES: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(
    vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT.as_raw()
        | vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
        | vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER.as_raw()
        | vk::PipelineStageFlags2::TESSELLATION_EVALUATION_SHADER.as_raw()
        | vk::PipelineStageFlags2::GEOMETRY_SHADER.as_raw()
        | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw()
        | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw()
        | vk::PipelineStageFlags2::COPY.as_raw(),
);

/// Records a pipeline barrier made of image barriers only.
pub fn image_barriers(
    device: &Device,
    cmd: vk::CommandBuffer,
    barriers: &[vk::ImageMemoryBarrier2],
) {
    let dependency = vk::DependencyInfo::default().image_memory_barriers(barriers);
    // SAFETY: callers pass a command buffer of `device` in the recording state, outside
    // a rendering, and barriers on images they keep alive until it has executed;
    // `dependency` borrows `barriers` through the call (synchronization2 is enabled).
    unsafe { device.raw.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// Records a global memory barrier (used between dependent compute dispatches).
pub fn memory_barrier(device: &Device, cmd: vk::CommandBuffer, src: Scope, dst: Scope) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.stages)
        .src_access_mask(src.access)
        .dst_stage_mask(dst.stages)
        .dst_access_mask(dst.access)];
    let dependency = vk::DependencyInfo::default().memory_barriers(&barrier);
    // SAFETY: callers pass a command buffer of `device` in the recording state, outside
    // a rendering; the barrier names no resource and `dependency` borrows it through
    // the call (synchronization2 is enabled).
    unsafe { device.raw.cmd_pipeline_barrier2(cmd, &dependency) };
}
