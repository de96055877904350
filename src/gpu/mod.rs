//! The Vulkan layer: one module per Vulkan concept, every handle owned by one value.

mod buffer;
mod device;
mod image;
mod instance;
mod pipeline;
mod query;
mod sampler;
pub mod shader;
mod swapchain;

use std::sync::Arc;

pub use buffer::{Buffer, TexelBuffer};
pub use device::{Device, DeviceInfo, PresentTarget};
pub use image::{
    image_barrier, image_barriers, memory_barrier, subresource_range, whole_image_copy, Image,
    ImageDesc,
};
pub use instance::{Instance, InstanceDesc, ValidationLog};
pub use pipeline::{DescriptorPool, DescriptorSetLayout, Pipeline, PipelineLayout, Specialization};
pub use query::{FurStatistics, QueryPool, FUR_STATISTICS};
pub use sampler::Sampler;
pub use shader::ShaderModule;
pub use swapchain::{Surface, Swapchain};

use crate::error::Result;

/// Destroys the device and reports what outlived the work: a Vulkan object never
/// released (it holds the device, which then cannot be destroyed), or anything the
/// validation layer said, teardown included (its object tracker names every object
/// still alive when the device goes).
pub fn shut_down(device: Arc<Device>) -> Result<()> {
    let instance = device.instance().clone();
    let device_alive = Arc::downgrade(&device);
    drop(device);
    if device_alive.upgrade().is_some() {
        return Err(crate::Error::Leak(
            "an object still holds the Vulkan device at exit: something was never released".into(),
        ));
    }
    instance.check_validation()
}

/// A headless context: instance plus device, ready for offscreen work.
pub fn headless(validation: bool) -> Result<Arc<Device>> {
    let instance = Arc::new(Instance::new(&InstanceDesc {
        validation,
        extensions: Vec::new(),
    })?);
    Device::new(instance, None, &[])
}

/// A context for a window: instance with the window system's surface extensions, the
/// surface, and a device whose queue can present to it.
pub fn windowed(
    validation: bool,
    window: &(impl raw_window_handle::HasDisplayHandle + raw_window_handle::HasWindowHandle),
) -> Result<(Arc<Device>, Surface)> {
    let display = window
        .display_handle()
        .map_err(|e| crate::Error::Window(format!("no display handle: {e}")))?;
    let required =
        ash_window::enumerate_required_extensions(display.as_raw()).map_err(|result| {
            crate::Error::Vulkan {
                call: "enumerate_required_extensions",
                result,
            }
        })?;
    // SAFETY: ash returns pointers to its static, NUL-terminated extension names.
    let extensions = required
        .iter()
        .map(|&p| unsafe { std::ffi::CStr::from_ptr(p) })
        .collect();
    let instance = Arc::new(Instance::new(&InstanceDesc {
        validation,
        extensions,
    })?);
    let surface = Surface::new(&instance, window)?;
    let device = Device::new(
        instance,
        Some(PresentTarget {
            surface_fn: surface.loader(),
            surface: surface.raw(),
        }),
        &[ash::khr::swapchain::NAME],
    )?;
    Ok((device, surface))
}
