//! Samplers (how the render passes filter and address their textures), each named for
//! the validation layer and destroyed on drop.

use std::sync::Arc;

use ash::vk;

use super::Device;
use crate::error::{Result, VkContext};

/// A `VkSampler`.
pub struct Sampler {
    device: Arc<Device>,
    raw: vk::Sampler,
}

impl Sampler {
    pub fn new(device: &Arc<Device>, name: &str, info: &vk::SamplerCreateInfo) -> Result<Self> {
        // SAFETY: the device is alive; callers pass a complete create info (a builder
        // from `vk::SamplerCreateInfo::default()`); the sampler is destroyed in Drop.
        let raw = unsafe { device.raw.create_sampler(info, None) }.vk("vkCreateSampler")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    /// A sampler that filters nothing and clamps: for images read texel by texel
    /// (`texelFetch`, or a depth read at a pixel's centre).
    pub fn nearest(device: &Arc<Device>, name: &str) -> Result<Self> {
        Self::new(
            device,
            name,
            &vk::SamplerCreateInfo::default()
                .mag_filter(vk::Filter::NEAREST)
                .min_filter(vk::Filter::NEAREST)
                .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
                .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE),
        )
    }

    pub fn raw(&self) -> vk::Sampler {
        self.raw
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: the sampler is owned here and destroyed once; owners wait for the
        // device first, so no descriptor set in use by a submission still refers to it.
        unsafe { self.device.raw.destroy_sampler(self.raw, None) };
    }
}
