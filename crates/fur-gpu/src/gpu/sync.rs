//! Fences, semaphores and command pools that destroy themselves: each holds its device,
//! so whatever owns one (a frame in flight, the viewer) frees it in `Drop` whatever the
//! order of its fields.

use std::sync::Arc;

use ash::vk;

use super::Device;
use crate::error::{Result, VkContext};

/// A fence, destroyed with its owner.
pub struct Fence {
    device: Arc<Device>,
    pub raw: vk::Fence,
}

impl Fence {
    /// A fence, created signalled when `signalled` (a first wait returns at once).
    pub fn new(device: &Arc<Device>, signalled: bool, name: &str) -> Result<Self> {
        let flags = if signalled {
            vk::FenceCreateFlags::SIGNALED
        } else {
            vk::FenceCreateFlags::empty()
        };
        // SAFETY: a plain create info; the device outlives the fence (held here).
        let raw = unsafe {
            device
                .raw
                .create_fence(&vk::FenceCreateInfo::default().flags(flags), None)
        }
        .vk("vkCreateFence")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
}

impl Drop for Fence {
    fn drop(&mut self) {
        // SAFETY: the owner has waited for the work that signals it (the viewer waits
        // for the device to be idle before it drops its frames).
        unsafe { self.device.raw.destroy_fence(self.raw, None) };
    }
}

/// A binary semaphore, destroyed with its owner.
pub struct Semaphore {
    device: Arc<Device>,
    pub raw: vk::Semaphore,
}

impl Semaphore {
    pub fn new(device: &Arc<Device>, name: &str) -> Result<Self> {
        // SAFETY: a plain create info; the device outlives the semaphore (held here).
        let raw = unsafe {
            device
                .raw
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
        }
        .vk("vkCreateSemaphore")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        // SAFETY: no pending operation waits on or signals it once the owner has waited
        // for the device.
        unsafe { self.device.raw.destroy_semaphore(self.raw, None) };
    }
}

/// A command pool of resettable command buffers on the device's queue family,
/// destroyed (with its buffers) with its owner.
pub struct CommandPool {
    device: Arc<Device>,
    pub raw: vk::CommandPool,
}

impl CommandPool {
    pub fn new(device: &Arc<Device>, name: &str) -> Result<Self> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a plain create info; the device outlives the pool (held here).
        let raw =
            unsafe { device.raw.create_command_pool(&info, None) }.vk("vkCreateCommandPool")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    /// `count` primary command buffers from this pool (freed with it).
    pub fn allocate(&self, count: u32) -> Result<Vec<vk::CommandBuffer>> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.raw)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count);
        // SAFETY: the pool is alive; the buffers are freed with it.
        unsafe { self.device.raw.allocate_command_buffers(&info) }.vk("vkAllocateCommandBuffers")
    }
}

impl Drop for CommandPool {
    fn drop(&mut self) {
        // SAFETY: none of its buffers is pending once the owner has waited for the
        // device.
        unsafe { self.device.raw.destroy_command_pool(self.raw, None) };
    }
}
