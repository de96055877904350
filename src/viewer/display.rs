//! The viewer's display: the window, the Vulkan surface on it and the swapchain on the
//! surface, recreated when the window's size changes.

use std::sync::Arc;

use ash::vk;
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::ViewerOptions;
use fur_gpu::error::{Error, Result};
use fur_gpu::gpu::{Device, Surface, Swapchain};

/// The window and what presents to it.
pub(super) struct Display {
    // Field order is drop order, and here it matters: the swapchain is built on the
    // surface, and the surface refers to the window's native handle, so the swapchain
    // goes first, then the surface, and the window last.
    /// None only while being recreated.
    swapchain: Option<Swapchain>,
    surface: Surface,
    /// The swapchain no longer matches the window (a resize, or an out-of-date acquire
    /// or present): it is recreated before the next frame draws.
    pub needs_resize: bool,
    vsync: bool,
    pub window: Arc<Window>,
}

impl Display {
    /// Opens a window as `options` ask, the device (one that can present to it) with
    /// its surface, and a swapchain of the window's size.
    pub fn open(
        event_loop: &ActiveEventLoop,
        options: &ViewerOptions,
    ) -> Result<(Arc<Device>, Self)> {
        let attributes = Window::default_attributes()
            .with_title("fur")
            .with_inner_size(PhysicalSize::new(
                options.width.max(1),
                options.height.max(1),
            ));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Window(format!("cannot create a window: {e}")))?,
        );
        let (device, surface) =
            fur_gpu::gpu::windowed(options.validate, options.device.as_deref(), &*window)?;
        let size = window.inner_size();
        let extent = vk::Extent2D {
            width: size.width.max(1),
            height: size.height.max(1),
        };
        let swapchain = Swapchain::new(&device, &surface, extent, options.vsync, None)?;
        let display = Self {
            swapchain: Some(swapchain),
            surface,
            needs_resize: false,
            vsync: options.vsync,
            window,
        };
        Ok((device, display))
    }

    /// The swapchain; None only if recreating it failed.
    pub fn swapchain(&self) -> Option<&Swapchain> {
        self.swapchain.as_ref()
    }

    /// The window's drawable size; zero while minimised.
    pub fn drawable(&self) -> vk::Extent2D {
        let size = self.window.inner_size();
        if self.window.is_minimized() == Some(true) {
            return vk::Extent2D::default();
        }
        vk::Extent2D {
            width: size.width,
            height: size.height,
        }
    }

    /// Rebuilds the swapchain at the window's size, once the device is idle. Returns
    /// its extent, or None (nothing done) while the window has no drawable area.
    pub fn recreate_swapchain(&mut self, device: &Arc<Device>) -> Result<Option<vk::Extent2D>> {
        let extent = self.drawable();
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        device.wait_idle()?;
        let old = self.swapchain.take();
        let swapchain = Swapchain::new(device, &self.surface, extent, self.vsync, old.as_ref())?;
        drop(old);
        let extent = swapchain.extent;
        self.swapchain = Some(swapchain);
        self.needs_resize = false;
        Ok(Some(extent))
    }
}
