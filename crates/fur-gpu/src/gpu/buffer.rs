//! Buffers with their memory, allocated through `gpu-allocator`.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::access::Scope;
use super::Device;
use crate::error::{Error, Result, VkContext};

/// A `VkBuffer` and its memory.
pub struct Buffer {
    device: Arc<Device>,
    pub raw: vk::Buffer,
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
        // SAFETY: a plain create info on a live device; the buffer is destroyed on the
        // error path below or by Drop.
        let raw = unsafe { device.raw.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `raw` was just created from this device.
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
                // SAFETY: `raw` was just created, has no memory bound and was never
                // used.
                unsafe { device.raw.destroy_buffer(raw, None) };
                return Err(Error::Allocation {
                    name: name.into(),
                    bytes: size,
                    source: Box::new(source),
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
        // SAFETY: the allocation was made for `raw`'s own memory requirements, so it is
        // large and aligned enough; the buffer has no memory bound yet.
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

    /// The buffer's contents, read back through a host-visible copy unless it is
    /// host-visible itself (it then needs `TRANSFER_SRC` usage). Waits for the device:
    /// for tools and exports, not per frame.
    pub fn read_back(&self) -> Result<Vec<u8>> {
        if let Some(bytes) = self.allocation.as_ref().and_then(|a| a.mapped_slice()) {
            return Ok(bytes[..self.size as usize].to_vec());
        }
        let staging = Buffer::new(
            &self.device,
            "readback",
            self.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let d = &self.device;
        d.submit_once(|cmd| {
            super::memory_barrier(
                d,
                cmd,
                Scope::new(
                    vk::PipelineStageFlags2::ALL_COMMANDS,
                    vk::AccessFlags2::MEMORY_WRITE,
                ),
                Scope::new(
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_READ,
                ),
            );
            let region = [vk::BufferCopy::default().size(self.size)];
            // SAFETY: both buffers are alive for the submission, which waits, and the
            // region lies within both (the staging buffer has this buffer's size).
            unsafe { d.raw.cmd_copy_buffer(cmd, self.raw, staging.raw, &region) };
            Ok(())
        })?;
        Ok(staging.mapped()[..self.size as usize].to_vec())
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
        // SAFETY: the buffer is owned here and freed once; its owners wait for the
        // device before dropping it, so no submission still uses it.
        unsafe { self.device.raw.destroy_buffer(self.raw, None) };
    }
}

/// A buffer that shaders read (and write) through a texel view (`imageBuffer`, a
/// storage texel buffer). On a CPU driver a texel read at lane-varying or
/// loop-varying indices is one gather, where a storage-buffer read loops over the lanes.
pub struct TexelBuffer {
    view: vk::BufferView,
    pub buffer: Buffer,
}

impl TexelBuffer {
    /// A buffer of `texels` texels of `format` (`texel_bytes` each) in `location`,
    /// usable as a storage texel buffer; refused, naming the limit, past the device's
    /// largest.
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        texels: u64,
        format: vk::Format,
        texel_bytes: u64,
        location: MemoryLocation,
    ) -> Result<Self> {
        let usage = vk::BufferUsageFlags::empty();
        Self::with_usage(device, name, texels, format, texel_bytes, usage, location)
    }

    /// [`TexelBuffer::new`] with `usage` besides (a transfer source, to be read back).
    pub fn with_usage(
        device: &Arc<Device>,
        name: &str,
        texels: u64,
        format: vk::Format,
        texel_bytes: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let limit = u64::from(device.info.limits.max_texel_buffer_elements);
        if texels > limit {
            return Err(Error::parameter(format!(
                "{name} needs {texels} texels, more than this device's largest texel buffer \
                 ({limit})"
            )));
        }
        let buffer = Buffer::new(
            device,
            name,
            texels.max(1) * texel_bytes,
            vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER | usage,
            location,
        )?;
        let info = vk::BufferViewCreateInfo::default()
            .buffer(buffer.raw)
            .format(format)
            .offset(0)
            .range(vk::WHOLE_SIZE);
        let view =
            // SAFETY: `buffer` has STORAGE_TEXEL_BUFFER usage and bound memory, and its
            // size is a whole number of texels, within the device's limit (checked
            // above).
            unsafe { device.raw.create_buffer_view(&info, None) }.vk("vkCreateBufferView")?;
        device.set_name(view, name);
        Ok(Self { view, buffer })
    }

    /// A host-visible texel buffer of 16-byte texels of `format` holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        device: &Arc<Device>,
        name: &str,
        format: vk::Format,
        data: &[T],
    ) -> Result<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut texels = Self::new(
            device,
            name,
            bytes.len().div_ceil(16) as u64,
            format,
            16,
            MemoryLocation::CpuToGpu,
        )?;
        texels.buffer.write(0, bytes);
        Ok(texels)
    }

    pub fn view(&self) -> vk::BufferView {
        self.view
    }
}

impl Drop for TexelBuffer {
    fn drop(&mut self) {
        // The view goes first; the buffer is dropped after this.
        // SAFETY: the view is owned here and destroyed once, before its buffer; owners
        // wait for the device before dropping it, so no descriptor in use still refers
        // to it.
        unsafe { self.buffer.device.raw.destroy_buffer_view(self.view, None) };
    }
}
