//! The render passes' descriptor set: its bindings (`shaders/common.glsl`,
//! `shaders/fur.geom`) and how one set is pointed at its resources.

use ash::vk;

use crate::gpu::{Buffer, Device};

/// Points one render descriptor set at its uniforms, position image, ownership masks
/// and hair counters.
pub(super) fn write_render_set(
    device: &Device,
    set: vk::DescriptorSet,
    uniforms: &Buffer,
    positions: &crate::gpu::Image,
    ownership: &Buffer,
    counters: &Buffer,
) {
    let buffer = |b: &Buffer| {
        [vk::DescriptorBufferInfo::default()
            .buffer(b.raw())
            .range(vk::WHOLE_SIZE)]
    };
    let (ubo, owners, counts) = (buffer(uniforms), buffer(ownership), buffer(counters));
    let image = [vk::DescriptorImageInfo::default()
        .image_view(positions.view())
        .image_layout(vk::ImageLayout::GENERAL)];
    let types = bindings();
    let write = |binding: u32| {
        vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(binding)
            .descriptor_type(types[binding as usize].0)
    };
    let writes = [
        write(0).buffer_info(&ubo),
        write(1).image_info(&image),
        write(2).buffer_info(&owners),
        write(3).buffer_info(&counts),
    ];
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Bindings of descriptor set 0 (see `shaders/common.glsl` and `shaders/fur.geom`).
pub(super) fn bindings() -> [(vk::DescriptorType, vk::ShaderStageFlags); 4] {
    let hair_stages = vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
        | vk::ShaderStageFlags::GEOMETRY;
    [
        (
            vk::DescriptorType::UNIFORM_BUFFER,
            vk::ShaderStageFlags::ALL_GRAPHICS,
        ),
        (vk::DescriptorType::STORAGE_IMAGE, hair_stages),
        (vk::DescriptorType::STORAGE_BUFFER, hair_stages),
        (
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::GEOMETRY,
        ),
    ]
}
