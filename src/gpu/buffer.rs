//! Buffers with their memory, allocated through `gpu-allocator`.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::Device;
use crate::error::{Error, Result, VkContext};

/// A `VkBuffer` and its memory.
pub struct Buffer {
    device: Arc<Device>,
    pub(crate) raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: vk::DeviceSize,
}

impl Buffer {
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let size = size.max(4);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let raw = unsafe { device.raw.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        let requirements = unsafe { device.raw.get_buffer_memory_requirements(raw) };
        let allocation = device.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(source) => {
                unsafe { device.raw.destroy_buffer(raw, None) };
                return Err(Error::Allocation {
                    name: name.into(),
                    bytes: size,
                    source,
                });
            }
        };
        // From here on Drop cleans up.
        let buffer = Self {
            device: device.clone(),
            raw,
            allocation: Some(allocation),
            size,
        };
        let a = buffer.allocation.as_ref().expect("allocation was just set");
        unsafe { device.raw.bind_buffer_memory(raw, a.memory(), a.offset()) }
            .vk("vkBindBufferMemory")?;
        device.set_name(raw, name);
        Ok(buffer)
    }

    /// A host-visible buffer filled with `data`.
    pub fn with_data<T: bytemuck::Pod>(
        device: &Arc<Device>,
        name: &str,
        usage: vk::BufferUsageFlags,
        data: &[T],
    ) -> Result<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut buffer = Self::new(
            device,
            name,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
        )?;
        buffer.write(0, bytes);
        Ok(buffer)
    }

    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }

    pub fn size(&self) -> vk::DeviceSize {
        self.size
    }

    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> &[u8] {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .expect("buffer is not host-visible")
    }

    /// Copies `bytes` into a host-visible buffer at `offset`.
    pub fn write(&mut self, offset: usize, bytes: &[u8]) {
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .expect("buffer is not host-visible");
        slice[offset..offset + bytes.len()].copy_from_slice(bytes);
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if let Some(allocation) = self.allocation.take() {
            // Freeing can only fail on a corrupt allocator; there is nothing to recover.
            let _ = self.device.allocator().free(allocation);
        }
        unsafe { self.device.raw.destroy_buffer(self.raw, None) };
    }
}
