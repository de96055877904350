//! Descriptor-set layouts, pools, pipeline layouts and pipelines, each destroyed on drop.

use std::sync::Arc;

use ash::vk;

use super::{Device, ShaderModule};
use crate::error::{Result, VkContext};

/// Declares a wrapper that owns one Vulkan handle and destroys it on drop.
macro_rules! owned_handle {
    ($(#[$doc:meta])* $name:ident, $handle:ty, $destroy:ident) => {
        $(#[$doc])*
        pub struct $name {
            device: Arc<Device>,
            pub raw: $handle,
        }

        impl $name {
            pub fn raw(&self) -> $handle {
                self.raw
            }
        }

        impl Drop for $name {
            fn drop(&mut self) {
                // SAFETY: the handle was created by this device, is owned by this value alone, and
                // its users finished before the owner dropped it (the device was waited on).
                unsafe { self.device.raw.$destroy(self.raw, None) };
            }
        }
    };
}

owned_handle!(
    /// A `VkDescriptorSetLayout`.
    DescriptorSetLayout,
    vk::DescriptorSetLayout,
    destroy_descriptor_set_layout
);
owned_handle!(
    /// A `VkDescriptorPool`; its sets are freed with it.
    DescriptorPool,
    vk::DescriptorPool,
    destroy_descriptor_pool
);
owned_handle!(
    /// A `VkPipelineLayout`.
    PipelineLayout,
    vk::PipelineLayout,
    destroy_pipeline_layout
);
owned_handle!(
    /// A graphics or compute `VkPipeline`.
    Pipeline,
    vk::Pipeline,
    destroy_pipeline
);

impl DescriptorSetLayout {
    /// One binding per `(type, stages)` entry, numbered from 0.
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        bindings: &[(vk::DescriptorType, vk::ShaderStageFlags)],
    ) -> Result<Self> {
        let bindings: Vec<_> = bindings
            .iter()
            .enumerate()
            .map(|(i, (ty, stages))| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(*ty)
                    .descriptor_count(1)
                    .stage_flags(*stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: `info` and the bindings it points at live until the call returns.
        let raw = unsafe { device.raw.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
}

impl DescriptorPool {
    /// A pool large enough for `sets` sets of `layout_bindings` each.
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        sets: u32,
        layout_bindings: &[(vk::DescriptorType, vk::ShaderStageFlags)],
    ) -> Result<Self> {
        let sizes: Vec<_> = layout_bindings
            .iter()
            .map(|(ty, _)| vk::DescriptorPoolSize {
                ty: *ty,
                descriptor_count: sets,
            })
            .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(sets)
            .pool_sizes(&sizes);
        // SAFETY: `info` and the pool sizes it points at live until the call returns.
        let raw = unsafe { device.raw.create_descriptor_pool(&info, None) }
            .vk("vkCreateDescriptorPool")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    pub fn allocate(
        &self,
        layout: &DescriptorSetLayout,
        count: usize,
    ) -> Result<Vec<vk::DescriptorSet>> {
        let layouts = vec![layout.raw; count];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.raw)
            .set_layouts(&layouts);
        // SAFETY: the pool and the layout are valid handles of this device; the pool was
        // sized for the sets its owner allocates.
        unsafe { self.device.raw.allocate_descriptor_sets(&info) }.vk("vkAllocateDescriptorSets")
    }
}

impl PipelineLayout {
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        set_layouts: &[&DescriptorSetLayout],
        push_constants: &[vk::PushConstantRange],
    ) -> Result<Self> {
        let layouts: Vec<_> = set_layouts.iter().map(|l| l.raw).collect();
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layouts)
            .push_constant_ranges(push_constants);
        // SAFETY: `info` and the set layouts it points at live until the call returns.
        let raw = unsafe { device.raw.create_pipeline_layout(&info, None) }
            .vk("vkCreatePipelineLayout")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
}

/// Specialization constants: `(constant_id, value)` pairs of 32-bit values.
pub struct Specialization {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u32>,
}

impl Specialization {
    pub fn new(values: &[(u32, u32)]) -> Self {
        let entries = values
            .iter()
            .enumerate()
            .map(|(i, (id, _))| vk::SpecializationMapEntry {
                constant_id: *id,
                offset: (i * 4) as u32,
                size: 4,
            })
            .collect();
        Self {
            entries,
            data: values.iter().map(|(_, v)| *v).collect(),
        }
    }

    pub fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default()
            .map_entries(&self.entries)
            .data(bytemuck::cast_slice(&self.data))
    }
}

impl Pipeline {
    /// A compute pipeline from an embedded shader compiled with `defines`.
    pub fn compute(
        device: &Arc<Device>,
        shader: &str,
        defines: &[(&str, String)],
        layout: &PipelineLayout,
        specialization: &Specialization,
    ) -> Result<Self> {
        let module = ShaderModule::new(device, shader, defines)?;
        let spec = specialization.info();
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw)
            .name(c"main")
            .specialization_info(&spec);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.raw);
        // SAFETY: `info`, its stage and specialisation data live until the call returns; the
        // module and the layout are valid handles of this device.
        let raw = unsafe {
            device
                .raw
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, result)| crate::error::vulkan("vkCreateComputePipelines", result))?[0];
        device.set_name(raw, shader);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }

    /// Wraps a pipeline created elsewhere (graphics pipelines are built by their pass).
    pub fn from_raw(device: &Arc<Device>, name: &str, raw: vk::Pipeline) -> Self {
        device.set_name(raw, name);
        Self {
            device: device.clone(),
            raw,
        }
    }
}
