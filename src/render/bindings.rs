//! The render passes' descriptor set: its bindings (`shaders/common.glsl`,
//! `shaders/shading.glsl`, `shaders/fur.geom`, `shaders/fur.tese`) and how one set is
//! pointed at its resources.

use ash::vk;

use super::texture::{GpuTexture, ShadowMap};
use crate::gpu::{Buffer, Device};

/// The model's texture and its UVs per triangle corner.
pub(super) struct TextureBinding<'a> {
    pub texture: &'a GpuTexture,
    pub corner_uvs: &'a Buffer,
}

/// The body as the passes read it: the posed vertices of a skinned body (written by the
/// skinning pass; a placeholder for a rigid one), each triangle's rest-pose edge lengths
/// and area (the density's source), and the triangle list.
pub(super) struct BodyBinding<'a> {
    pub posed: vk::Buffer,
    pub rest_triangles: &'a Buffer,
    pub indices: &'a Buffer,
}

/// Points one render descriptor set at its uniforms, position image, ownership masks,
/// hair counters, the model's texture and the body.
pub(super) fn write_render_set(
    device: &Device,
    set: vk::DescriptorSet,
    uniforms: &Buffer,
    positions: &crate::gpu::Image,
    (ownership, counters): (&Buffer, &Buffer),
    texture: &TextureBinding<'_>,
    body: &BodyBinding<'_>,
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
    let albedo = [vk::DescriptorImageInfo::default()
        .sampler(texture.texture.sampler.raw())
        .image_view(texture.texture.image.view())
        .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)];
    let uvs = buffer(texture.corner_uvs);
    let posed = [vk::DescriptorBufferInfo::default()
        .buffer(body.posed)
        .range(vk::WHOLE_SIZE)];
    let (rest_triangles, indices) = (buffer(body.rest_triangles), buffer(body.indices));
    let write = |binding: u32| write(set, binding);
    let writes = [
        write(0).buffer_info(&ubo),
        write(1).image_info(&image),
        write(2).buffer_info(&owners),
        write(3).buffer_info(&counts),
        write(4).image_info(&albedo),
        write(6).buffer_info(&uvs),
        write(7).buffer_info(&posed),
        write(8).buffer_info(&rest_triangles),
        write(9).buffer_info(&indices),
    ];
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points binding 3 of `set` (the hair counters, and the capture after them) at
/// `counters`.
pub(super) fn write_counters(device: &Device, set: vk::DescriptorSet, counters: &Buffer) {
    let info = [vk::DescriptorBufferInfo::default()
        .buffer(counters.raw())
        .range(vk::WHOLE_SIZE)];
    let writes = [write(set, 3).buffer_info(&info)];
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points binding 5 of `set` at a shadow map.
pub(super) fn write_shadow_map(device: &Device, set: vk::DescriptorSet, map: &ShadowMap) {
    let info = [vk::DescriptorImageInfo::default()
        .sampler(map.sampler.raw())
        .image_view(map.image.view())
        .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)];
    let writes = [write(set, 5).image_info(&info)];
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

fn write(set: vk::DescriptorSet, binding: u32) -> vk::WriteDescriptorSet<'static> {
    vk::WriteDescriptorSet::default()
        .dst_set(set)
        .dst_binding(binding)
        .descriptor_type(bindings()[binding as usize].0)
}

/// Bindings of descriptor set 0. The texture (4, 6) and the shadow map (5) are read
/// only by the pipelines of a textured model or a frame with shadows, the body (7–9)
/// only by those of a skinned one.
pub(super) fn bindings() -> [(vk::DescriptorType, vk::ShaderStageFlags); 10] {
    let hair_stages = vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::TESSELLATION_CONTROL
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION
        | vk::ShaderStageFlags::GEOMETRY;
    let shaded = vk::ShaderStageFlags::GEOMETRY | vk::ShaderStageFlags::FRAGMENT;
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
        (vk::DescriptorType::COMBINED_IMAGE_SAMPLER, shaded),
        (vk::DescriptorType::COMBINED_IMAGE_SAMPLER, shaded),
        (
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        ),
        (
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::TESSELLATION_CONTROL,
        ),
        (
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::TESSELLATION_CONTROL,
        ),
        (
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::VERTEX,
        ),
    ]
}
