//! A window surface and its swapchain, with one render-finished semaphore per image.

use std::sync::Arc;

use ash::{khr, vk};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};

use super::access::Scope;
use super::{Device, Instance, Semaphore};

/// The blit's write into a swapchain image.
const BLIT_WRITE: Scope = Scope::new(
    vk::PipelineStageFlags2::BLIT,
    vk::AccessFlags2::TRANSFER_WRITE,
);
use crate::error::{Error, Result, VkContext};

/// A `VkSurfaceKHR` for a window.
pub struct Surface {
    _instance: Arc<Instance>,
    pub loader: khr::surface::Instance,
    pub raw: vk::SurfaceKHR,
}

impl Surface {
    pub fn new(
        instance: &Arc<Instance>,
        window: &(impl HasDisplayHandle + HasWindowHandle),
    ) -> Result<Self> {
        let display = window
            .display_handle()
            .map_err(|e| Error::Window(format!("no display handle: {e}")))?;
        let handle = window
            .window_handle()
            .map_err(|e| Error::Window(format!("no window handle: {e}")))?;
        // SAFETY: the display and window handles come from a live window that the
        // caller keeps alive longer than the surface (the viewer's display drops the
        // surface before the window), and the instance enabled the extensions
        // ash_window requires for this display (`gpu::windowed`).
        let raw = unsafe {
            ash_window::create_surface(
                &instance.entry,
                &instance.raw,
                display.as_raw(),
                handle.as_raw(),
                None,
            )
        }
        .vk("vkCreate*SurfaceKHR")?;
        Ok(Self {
            _instance: instance.clone(),
            loader: khr::surface::Instance::new(&instance.entry, &instance.raw),
            raw,
        })
    }

    pub fn loader(&self) -> &khr::surface::Instance {
        &self.loader
    }

    pub fn raw(&self) -> vk::SurfaceKHR {
        self.raw
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: the surface is owned here; owners drop the swapchain built on it
        // first, and `_instance` keeps the instance alive until after this.
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// The swapchain images, their views and per-image semaphores.
pub struct Swapchain {
    device: Arc<Device>,
    loader: khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub views: Vec<vk::ImageView>,
    /// Signalled when an image's frame is rendered; presentation waits on it. Per image,
    /// not per frame in flight, so a semaphore is never reused before its present.
    pub render_finished: Vec<Semaphore>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
}

impl Swapchain {
    /// Creates a swapchain for `surface`, `wanted` being the window's size in pixels.
    pub fn new(
        device: &Arc<Device>,
        surface: &Surface,
        wanted: vk::Extent2D,
        vsync: bool,
        old: Option<&Swapchain>,
    ) -> Result<Self> {
        let physical = device.physical;
        // SAFETY: `physical` is the device's, chosen to present to this surface, and
        // the surface is alive (borrowed).
        let caps = unsafe {
            surface
                .loader
                .get_physical_device_surface_capabilities(physical, surface.raw)
        }
        .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        // SAFETY: as above: the device's physical device and a live surface of the same
        // instance.
        let formats = unsafe {
            surface
                .loader
                .get_physical_device_surface_formats(physical, surface.raw)
        }
        .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        // SAFETY: as above: the device's physical device and a live surface of the same
        // instance.
        let modes = unsafe {
            surface
                .loader
                .get_physical_device_surface_present_modes(physical, surface.raw)
        }
        .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        let format = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB]
            .iter()
            .find_map(|f| formats.iter().find(|sf| sf.format == *f))
            .or(formats.first())
            .copied()
            .ok_or_else(|| Error::Window("the window surface offers no formats".into()))?;
        let mode = if vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: wanted
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: wanted
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(mode)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.raw));
        let loader = khr::swapchain::Device::new(&device.instance.raw, &device.raw);
        // SAFETY: `info` names the live surface with a format, extent, transform and
        // present mode the surface reported, and the image count within its limits;
        // `old`, if any, is the live swapchain of this surface, retired by this call.
        let raw = unsafe { loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        let mut swapchain = Self {
            device: device.clone(),
            loader,
            raw,
            images: Vec::new(),
            views: Vec::new(),
            render_finished: Vec::new(),
            format: format.format,
            extent,
        };
        swapchain.images =
            // SAFETY: `raw` was just created by this loader and is owned by
            // `swapchain`.
            unsafe { swapchain.loader.get_swapchain_images(raw) }.vk("vkGetSwapchainImagesKHR")?;
        for (i, &image) in swapchain.images.clone().iter().enumerate() {
            device.set_name(image, &format!("swapchain[{i}]"));
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format.format)
                .subresource_range(super::subresource_range(vk::ImageAspectFlags::COLOR));
            swapchain.views.push(
                // SAFETY: `image` is one of this swapchain's images, of
                // `format.format`, single-layer; the view is destroyed in Drop before
                // the swapchain.
                unsafe { device.raw.create_image_view(&view_info, None) }
                    .vk("vkCreateImageView")?,
            );
            swapchain
                .render_finished
                .push(Semaphore::new(device, &format!("render_finished[{i}]"))?);
        }
        log::info!(
            "swapchain {}×{} {:?} {:?}",
            extent.width,
            extent.height,
            format.format,
            mode
        );
        Ok(swapchain)
    }

    /// Records the barrier before image `index`'s first use in a frame, the blit into
    /// it: from whatever layout into `TRANSFER_DST_OPTIMAL`. The acquire semaphore is
    /// waited at the blit (the simulation and the passes before it need not wait for
    /// it), so the barrier's source is that stage, which chains it to the wait.
    pub fn before_blit(&self, cmd: vk::CommandBuffer, index: u32) {
        self.transition(
            cmd,
            index,
            Scope::new(vk::PipelineStageFlags2::BLIT, vk::AccessFlags2::NONE),
            BLIT_WRITE,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
    }

    /// Records the barrier between the blit into image `index` and the panel drawn over
    /// it as a colour attachment.
    pub fn before_panel(&self, cmd: vk::CommandBuffer, index: u32) {
        self.transition(
            cmd,
            index,
            BLIT_WRITE,
            Scope::new(
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ,
            ),
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
    }

    /// Records the barrier after the panel, into the layout the presentation engine
    /// reads (the present waits on the frame's semaphore, not on a stage).
    pub fn before_present(&self, cmd: vk::CommandBuffer, index: u32) {
        self.transition(
            cmd,
            index,
            Scope::new(
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
            Scope::NONE,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::PRESENT_SRC_KHR,
        );
    }

    fn transition(
        &self,
        cmd: vk::CommandBuffer,
        index: u32,
        src: Scope,
        dst: Scope,
        old: vk::ImageLayout,
        new: vk::ImageLayout,
    ) {
        let image = self.images[index as usize];
        let barrier = super::image_barrier(image, vk::ImageAspectFlags::COLOR, src, dst, old, new);
        super::image_barriers(&self.device, cmd, &[barrier]);
    }

    /// Acquires the next image; `None` when the swapchain must be recreated.
    pub fn acquire(&self, signal: vk::Semaphore) -> Result<Option<u32>> {
        // SAFETY: the swapchain is alive (borrowed); callers pass a semaphore with no
        // pending signal (the viewer waits for its frame slot's fence first, whose
        // submission consumed the last one) and no fence.
        match unsafe {
            self.loader
                .acquire_next_image(self.raw, u64::MAX, signal, vk::Fence::null())
        } {
            Ok((index, _suboptimal)) => Ok(Some(index)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(result) => Err(crate::error::vulkan("vkAcquireNextImageKHR", result)),
        }
    }

    /// Presents image `index` once its render-finished semaphore is signalled. Returns
    /// false when the swapchain is out of date or suboptimal and should be recreated.
    pub fn present(&self, index: u32) -> Result<bool> {
        let wait = [self.render_finished[index as usize].raw];
        let swapchains = [self.raw];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: `index` was acquired from this swapchain and the submission that
        // signals its render-finished semaphore was queued first on the same queue; the
        // arrays `info` points at outlive the call.
        match unsafe { self.loader.queue_present(self.device.queue, &info) } {
            Ok(suboptimal) => Ok(!suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(result) => Err(crate::error::vulkan("vkQueuePresentKHR", result)),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // SAFETY: owners wait for the device before dropping or recreating the
        // swapchain, so no command uses its views; the views were made here from its
        // images (which the swapchain frees itself), so they go first.
        unsafe {
            for &view in &self.views {
                self.device.raw.destroy_image_view(view, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}
