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

#[cfg(test)]
mod tests {
    use std::mem::offset_of;

    use super::bindings;
    use crate::gpu::reflect::{check_bindings, check_struct, reflect};
    use crate::gpu::shader::compile;
    use crate::render::uniforms::{shader_defines, FrameUniforms};

    /// The `Frame` uniform block as Rust lays it out: (member, byte offset).
    fn frame_fields() -> Vec<(&'static str, usize)> {
        macro_rules! fields {
            ($($f:ident),+) => { vec![$((stringify!($f), offset_of!(FrameUniforms, $f))),+] };
        }
        fields!(
            view_proj,
            model,
            light_view_proj,
            eye,
            light,
            root_color,
            tip_color,
            skin_color,
            shading,
            lod,
            hair,
            viewport,
            draw,
            highlight,
            secondary,
            shadow,
            strands,
            fibre
        )
    }

    /// Every render shader, compiled with every option that adds a binding, uses the
    /// bindings of the Rust layout with their types, and lays out the `Frame` block as
    /// `FrameUniforms` is (names, order, offsets); every binding of the layout is used.
    /// Swapping two members in GLSL, or adding a field in Rust only, fails here.
    #[test]
    fn the_render_shaders_agree_with_the_rust_layouts() {
        let layout: Vec<_> = bindings().iter().map(|b| b.0).collect();
        let mut used = std::collections::BTreeSet::new();
        for lines in ["0", "1"] {
            let mut defines: Vec<(&str, String)> = [
                ("STRAND_VERTICES", "17"),
                ("TEXTURED", "1"),
                ("SHADOWS", "1"),
                ("BODY_SKINNED", "1"),
                ("COUNT_HAIRS", "1"),
                ("MARSCHNER", "1"),
                ("COVERAGE_SAMPLES", "4"),
                ("LINES", lines),
            ]
            .into_iter()
            .map(|(k, v)| (k, v.to_string()))
            .collect();
            defines.extend(shader_defines());
            for shader in [
                "fur.vert",
                "fur.tesc",
                "fur.tese",
                "fur.geom",
                "fur.frag",
                "mesh.vert",
                "mesh.frag",
            ] {
                let words = compile(shader, &defines).unwrap_or_else(|e| panic!("{shader}: {e}"));
                let found = reflect(&words);
                check_bindings(shader, &found, &layout).unwrap();
                if found.structs.contains_key("Frame") {
                    check_struct(shader, &found, "Frame", &frame_fields()).unwrap();
                }
                used.extend(found.bindings.keys().map(|&(_, b)| b));
            }
        }
        assert_eq!(used.len(), layout.len(), "bindings used: {used:?}");
        assert_eq!(
            std::mem::size_of::<FrameUniforms>(),
            frame_fields().last().unwrap().1 + 16,
            "FrameUniforms ends with its last vec4"
        );
    }

    /// Without the shared defines a render shader does not compile.
    #[test]
    fn render_shaders_take_their_flags_from_rust() {
        let error = compile("fur.tesc", &[]).unwrap_err().to_string();
        assert!(error.contains("shader_defines"), "{error}");
    }
}
