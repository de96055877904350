//! The viewer's panel as the window shows it: egui's context and window-system state,
//! the Vulkan renderer that draws it (with the command pool its texture uploads use),
//! and the panel's own state between frames.

use std::sync::Arc;

use ash::vk;
use winit::window::Window;

use super::{ui, FRAMES_IN_FLIGHT};
use fur_gpu::error::{Error, Result};
use fur_gpu::gpu::{CommandPool, Device};

type Renderer = egui_ash_renderer::Renderer<egui_ash_renderer::allocator::GpuAllocator>;

/// The panel and what draws it.
pub(super) struct Panel {
    renderer: Renderer,
    /// The command buffers of texture uploads (each upload waits for its own).
    upload_pool: CommandPool,
    pub state: egui_winit::State,
    pub ctx: egui::Context,
    pub ui: ui::PanelState,
    // Declared after the renderer, so dropped after it: the renderer destroys its
    // objects through the device's handle and frees its memory through the device's
    // allocator, so the device must outlive it.
    device: Arc<Device>,
}

impl Panel {
    /// A panel for `window`, drawn into images of `format` (a swapchain's).
    pub fn new(device: &Arc<Device>, window: &Window, format: vk::Format) -> Result<Self> {
        let upload_pool = CommandPool::new(device, "ui uploads")?;
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(device.info.limits.max_image_dimension2_d as usize),
        );
        let srgb = matches!(
            format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
        );
        let renderer = Renderer::with_gpu_allocator(
            device.shared_allocator(),
            device.raw.clone(),
            egui_ash_renderer::RenderMode::DynamicRendering(egui_ash_renderer::DynamicRendering {
                color_attachment_format: format,
                depth_attachment_format: None,
                stencil_attachment_format: None,
            }),
            egui_ash_renderer::Options {
                in_flight_frames: FRAMES_IN_FLIGHT,
                srgb_framebuffer: srgb,
                ..Default::default()
            },
        )
        .map_err(|e| Error::Window(format!("cannot create the UI renderer: {e}")))?;
        Ok(Self {
            renderer,
            upload_pool,
            state,
            ctx,
            ui: ui::PanelState::new(),
            device: device.clone(),
        })
    }

    /// Uploads the textures a frame's output sets; returns those it frees, to free
    /// once that frame has finished (`free`).
    pub fn set_textures(
        &mut self,
        mut textures: egui::TexturesDelta,
    ) -> Result<Vec<egui::TextureId>> {
        for (id, deltas) in textures.set.drain() {
            for delta in &deltas {
                self.renderer
                    .set_texture(self.device.queue, self.upload_pool.raw, id, delta)
                    .map_err(|e| Error::Window(format!("UI texture upload failed: {e}")))?;
            }
        }
        Ok(textures.free.drain().collect())
    }

    /// Frees textures no frame in flight uses any more.
    pub fn free(&mut self, textures: Vec<egui::TextureId>) -> Result<()> {
        for id in textures {
            self.renderer
                .free_texture(id)
                .map_err(|e| Error::Window(format!("UI texture free failed: {e}")))?;
        }
        Ok(())
    }

    /// Records drawing `primitives` into `cmd`, inside a rendering of `extent`.
    pub fn draw(
        &mut self,
        cmd: vk::CommandBuffer,
        extent: vk::Extent2D,
        pixels_per_point: f32,
        primitives: &[egui::ClippedPrimitive],
    ) -> Result<()> {
        self.renderer
            .cmd_draw(cmd, extent, pixels_per_point, primitives)
            .map_err(|e| Error::Window(format!("UI drawing failed: {e}")))
    }
}
