//! The Vulkan layer: one module per Vulkan concept, every handle owned by one value.

mod access;
mod buffer;
mod choice;
mod descriptors;
mod device;
mod image;
mod instance;
mod physical;
mod pipeline;
mod query;
#[cfg(test)]
pub mod reflect;
mod sampler;
pub mod shader;
mod swapchain;
mod sync;

use std::sync::Arc;

pub use access::{barrier, Access, Barrier, Scope, State, Tracker};
pub use buffer::{Buffer, TexelBuffer};
pub use choice::{choose, Candidate, DeviceEntry, DeviceKind, DeviceList};
pub(crate) use descriptors::bindings;
pub use device::{Device, DeviceInfo, PresentTarget};
pub use image::{
    image_barrier, image_barriers, memory_barrier, subresource_range, whole_image_copy, Image,
    ImageDesc, SHARED_DATA_STAGES,
};
pub use instance::{Instance, InstanceDesc, ValidationLog};
pub use physical::list_devices;
pub use pipeline::{DescriptorPool, DescriptorSetLayout, Pipeline, PipelineLayout, Specialization};
pub use query::{FurStatistics, QueryPool, FUR_STATISTICS};
pub use sampler::Sampler;
pub use shader::ShaderModule;
pub use swapchain::{Surface, Swapchain};
pub use sync::{CommandPool, Fence, Semaphore};

use crate::error::Result;

/// Held around every call that makes the Vulkan loader change its process-wide lists of
/// drivers and devices (instance creation and destruction, vkEnumeratePhysicalDevices,
/// which unloads the drivers that find no device, vkCreateDevice, vkDestroyDevice) and
/// around the debug-utils calls it resolves by walking those lists (object names,
/// command-buffer labels). Debian 13's loader (1.4.309) walks them under a lock its
/// writers do not take (KhronosGroup/Vulkan-Loader#2018), so two threads with their own
/// instances (the tests) could crash it: a thread naming a buffer while another's
/// enumeration unloaded a driver. The product has one device; the lock costs nothing
/// there.
static LOADER: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Takes the loader's lock; a panic elsewhere while it was held leaves nothing to repair.
pub fn loader_lock() -> std::sync::MutexGuard<'static, ()> {
    LOADER.lock().unwrap_or_else(|e| e.into_inner())
}

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

/// A headless context: instance plus device, ready for offscreen work, on the default
/// device (see [`headless_on`]).
pub fn headless(validation: bool) -> Result<Arc<Device>> {
    headless_on(validation, None)
}

/// A headless context on the device `choice` names: an index into [`list_devices`] or
/// a case-insensitive part of one usable device's name (`--device`); `None` takes the
/// best usable device (discrete, integrated, virtual, then CPU drivers).
pub fn headless_on(validation: bool, choice: Option<&str>) -> Result<Arc<Device>> {
    let instance = Arc::new(Instance::new(&InstanceDesc {
        validation,
        extensions: Vec::new(),
    })?);
    Device::new(instance, None, &[], choice)
}

/// A context for a window: instance with the window system's surface extensions, the
/// surface, and a device whose queue can present to it (the one `choice` names, as for
/// [`headless_on`]).
pub fn windowed(
    validation: bool,
    choice: Option<&str>,
    window: &(impl raw_window_handle::HasDisplayHandle + raw_window_handle::HasWindowHandle),
) -> Result<(Arc<Device>, Surface)> {
    let display = window
        .display_handle()
        .map_err(|e| crate::Error::Window(format!("no display handle: {e}")))?;
    let required = ash_window::enumerate_required_extensions(display.as_raw())
        .map_err(|result| crate::error::vulkan("enumerate_required_extensions", result))?;
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
        choice,
    )?;
    Ok((device, surface))
}
