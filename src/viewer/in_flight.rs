//! The frames in flight: per frame a command buffer, a fence, an acquire semaphore and
//! what to do once the frame has finished, with the command pool the buffers come from.

use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;

use super::FRAMES_IN_FLIGHT;
use fur_gpu::error::Result;
use fur_gpu::gpu::{CommandPool, Device, Fence, Semaphore};

/// Per frame in flight: command buffer, fence, acquire semaphore and what to do once
/// the frame is done.
pub(super) struct FrameSync {
    /// Allocated from the pool of the `Frames` holding this slot, freed with it.
    pub cmd: vk::CommandBuffer,
    pub fence: Fence,
    pub image_available: Semaphore,
    pub submitted: bool,
    pub simulated: bool,
    pub screenshot: Option<PathBuf>,
    pub free_textures: Vec<egui::TextureId>,
}

/// The frames in flight and the command pool their command buffers come from. Every
/// object here frees itself (each holds the device); the owner waits for the device
/// before dropping this, so no buffer, fence or semaphore is still in use.
pub(super) struct Frames {
    pub slots: Vec<FrameSync>,
    /// Held for what it frees: the slots' command buffers. Declared after the slots so
    /// that it goes last and no slot ever holds a buffer of a destroyed pool.
    _pool: CommandPool,
}

impl Frames {
    /// `FRAMES_IN_FLIGHT` slots, each with a command buffer, a signalled fence (the
    /// first wait on it returns at once) and an acquire semaphore.
    pub fn new(device: &Arc<Device>) -> Result<Self> {
        let pool = CommandPool::new(device, "frames")?;
        let mut slots = Vec::new();
        for (i, cmd) in pool
            .allocate(FRAMES_IN_FLIGHT as u32)?
            .into_iter()
            .enumerate()
        {
            slots.push(FrameSync {
                cmd,
                fence: Fence::new(device, true, &format!("frame_done[{i}]"))?,
                image_available: Semaphore::new(device, &format!("image_available[{i}]"))?,
                submitted: false,
                simulated: false,
                screenshot: None,
                free_textures: Vec::new(),
            });
        }
        Ok(Self { slots, _pool: pool })
    }

    /// The slot frame number `index` uses.
    pub fn slot_of(index: u64) -> usize {
        (index % FRAMES_IN_FLIGHT as u64) as usize
    }
}
