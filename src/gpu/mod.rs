//! The Vulkan layer: one module per Vulkan concept, every handle owned by one value.

mod buffer;
mod device;
mod image;
mod instance;
mod pipeline;
mod query;
pub mod shader;

use std::sync::Arc;

pub use buffer::Buffer;
pub use device::{Device, DeviceInfo, PresentTarget};
pub use image::{image_barriers, memory_barrier, subresource_range, Image, ImageDesc};
pub use instance::{Instance, InstanceDesc, ValidationLog};
pub use pipeline::{DescriptorPool, DescriptorSetLayout, Pipeline, PipelineLayout, Specialization};
pub use query::{FurStatistics, QueryPool, FUR_STATISTICS};
pub use shader::ShaderModule;

use crate::error::Result;

/// A headless context: instance plus device, ready for offscreen work.
pub fn headless(validation: bool) -> Result<Arc<Device>> {
    let instance = Arc::new(Instance::new(&InstanceDesc {
        validation,
        extensions: Vec::new(),
    })?);
    Device::new(instance, None, &[])
}
