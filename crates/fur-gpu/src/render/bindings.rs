//! The render passes' descriptor sets, defined once here: set 0 holds what changes per
//! frame and per view (the uniforms, the strand positions, the hair counters, the
//! shadow map), set 1 the body (ownership masks, texture, corner UVs, posed vertices,
//! rest triangles, the triangle list), written once. The shaders take the set and
//! binding numbers as defines ([`binding_defines`]: `SET_FRAME`, `B_SHADOW_MAP`, …), so
//! no number is typed twice; a test checks the compiled SPIR-V against the types.

use ash::vk;

use super::texture::{GpuTexture, ShadowMap};
use crate::gpu::{bindings, Buffer, Device, Image, Sampler};

/// The set numbers.
pub(super) const SET_FRAME: u32 = 0;
pub(super) const SET_BODY: u32 = 1;
pub(super) const SET_RASTER: u32 = 2;

/// The hair stages: vertex, tessellation control and evaluation, geometry.
const HAIR_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::VERTEX.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw()
        | vk::ShaderStageFlags::TESSELLATION_EVALUATION.as_raw()
        | vk::ShaderStageFlags::GEOMETRY.as_raw(),
);

/// The stages that shade: geometry (per-vertex lighting) and fragment.
const SHADING_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::GEOMETRY.as_raw() | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);

/// The stages that light hairs, the compute rasteriser's lighting pass among them.
const LIGHTING_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    SHADING_STAGES.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

bindings!(
    /// Set 0: one per frame in flight, per position image and per view (the camera's
    /// and the light's).
    FrameBinding {
        /// The `Frame` uniform block (`FrameUniforms`).
        Uniforms = ("B_FRAME_UNIFORMS", UNIFORM_BUFFER, vk::ShaderStageFlags::from_raw(
            vk::ShaderStageFlags::ALL_GRAPHICS.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw())),
        /// The strand positions the simulation last wrote, sampled (`texelFetch`), never
        /// bound as a storage image: Mesa 22.3's lavapipe (Debian 12) keys a tessellation
        /// or geometry program with four bytes it never writes for each storage image
        /// the stage binds, so a stage with one may be compiled again at any draw (seen:
        /// the compute rasteriser's geometry stage, every frame, with the body at one
        /// sample).
        Positions = ("B_STRAND_POSITIONS", COMBINED_IMAGE_SAMPLER, HAIR_STAGES),
        /// Hairs, segments and culled triangles counted (and the capture behind them).
        Counters = ("B_HAIR_COUNTERS", STORAGE_BUFFER, vk::ShaderStageFlags::from_raw(
            vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw() | vk::ShaderStageFlags::GEOMETRY.as_raw())),
        /// The shadow map (read by the frames with shadows).
        ShadowMap = ("B_SHADOW_MAP", COMBINED_IMAGE_SAMPLER, LIGHTING_STAGES),
        /// The simulation kernel's arrows (the simulation view).
        Probe = ("B_PROBE", STORAGE_BUFFER, vk::ShaderStageFlags::VERTEX),
    }
);

bindings!(
    /// Set 1: the body, one per renderer. The texture and UVs are read only by the
    /// pipelines of a textured model, the posed vertices and rest triangles only by
    /// those of a skinned one.
    BodyBinding {
        /// Which triangle draws each shared edge and corner.
        Ownership = ("B_OWNERSHIP", STORAGE_BUFFER, HAIR_STAGES),
        /// The model's texture.
        Albedo = ("B_ALBEDO", COMBINED_IMAGE_SAMPLER, SHADING_STAGES),
        /// Its UVs per triangle corner.
        CornerUvs = ("B_CORNER_UVS", STORAGE_BUFFER, vk::ShaderStageFlags::TESSELLATION_EVALUATION),
        /// A skinned body's posed vertices (written by the skinning pass).
        Posed = ("B_POSED", STORAGE_BUFFER, vk::ShaderStageFlags::from_raw(
            vk::ShaderStageFlags::VERTEX.as_raw() | vk::ShaderStageFlags::TESSELLATION_CONTROL.as_raw())),
        /// Per triangle, its rest edge lengths and area.
        RestTriangles = ("B_REST_TRIANGLES", STORAGE_BUFFER, vk::ShaderStageFlags::TESSELLATION_CONTROL),
        /// The triangle list.
        Indices = ("B_INDICES", STORAGE_BUFFER, vk::ShaderStageFlags::VERTEX),
    }
);

/// The stages that touch the compute rasteriser's strands and counts: the geometry
/// stage writes them, the compute passes bin and draw them.
const RASTER_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::GEOMETRY.as_raw() | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

bindings!(
    /// Set 2: the compute rasteriser's (`--raster compute`), one per frame in flight
    /// (each with its own counts).
    RasterBinding {
        /// What the passes counted, and the bin passes' indirect dispatch.
        Counts = ("B_RASTER_COUNTS", STORAGE_BUFFER, RASTER_STAGES),
        /// The strands' vertices: on the screen, and their colours (or, under the
        /// Marschner model, what lights them, until the lighting pass does).
        Vertices = ("B_STRAND_VERTICES", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// The segments: first vertex and strand.
        Segments = ("B_STRAND_SEGMENTS", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// The vertices' memory again, as the geometry stage writes it: a storage buffer,
        /// not a texel buffer (`FrameBinding::Positions` says why).
        VerticesWritten = ("B_STRAND_VERTICES_WRITTEN", STORAGE_BUFFER, vk::ShaderStageFlags::GEOMETRY),
        /// The segments' memory again, as the geometry stage writes it.
        SegmentsWritten = ("B_STRAND_SEGMENTS_WRITTEN", STORAGE_BUFFER, vk::ShaderStageFlags::GEOMETRY),
        /// Per tile: the body's depth and the tile's list in the entry pool.
        TileBins = ("B_TILE_BINS", STORAGE_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// The entry pool: segments listed per tile.
        TileEntries = ("B_TILE_ENTRIES", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// The entry pool again, each tile's list sorted front to back by depth bin.
        TileOrder = ("B_TILE_ORDER", STORAGE_TEXEL_BUFFER, vk::ShaderStageFlags::COMPUTE),
        /// Per pixel: the hair, premultiplied, and the light it lets through.
        HairLayer = ("B_HAIR_LAYER", STORAGE_BUFFER, RASTER_STAGES),
        /// The mesh pass's depth.
        BodyDepth = ("B_BODY_DEPTH", COMBINED_IMAGE_SAMPLER, vk::ShaderStageFlags::COMPUTE),
        /// The target's resolved colour, which the hair layer is composited over.
        TargetColor = ("B_TARGET_COLOR", COMBINED_IMAGE_SAMPLER, vk::ShaderStageFlags::COMPUTE),
        /// The composited image, copied onto the target.
        Composited = ("B_COMPOSITED", STORAGE_IMAGE, vk::ShaderStageFlags::COMPUTE),
    }
);

/// The defines every render shader is compiled with: the set numbers and each
/// binding's number.
pub(super) fn binding_defines() -> Vec<(&'static str, String)> {
    let mut defines = vec![
        ("SET_FRAME", SET_FRAME.to_string()),
        ("SET_BODY", SET_BODY.to_string()),
        ("SET_RASTER", SET_RASTER.to_string()),
    ];
    defines.extend(RasterBinding::defines());
    defines.extend(FrameBinding::defines());
    defines.extend(BodyBinding::defines());
    defines
}

/// Every define a render shader takes from Rust: the drawing's flags
/// ([`fur_core::render::uniforms::shader_defines`]) and the set and binding numbers.
pub(crate) fn render_defines() -> Vec<(&'static str, String)> {
    let mut defines = fur_core::render::uniforms::shader_defines();
    defines.extend(binding_defines());
    defines
}

/// The body as the passes read it.
pub(super) struct BodyResources<'a> {
    pub ownership: &'a Buffer,
    pub texture: &'a GpuTexture,
    pub corner_uvs: &'a Buffer,
    /// The posed vertices of a skinned body (a placeholder for a rigid one).
    pub posed: vk::Buffer,
    pub rest_triangles: &'a Buffer,
    pub indices: &'a Buffer,
}

fn buffer_info(buffer: vk::Buffer) -> [vk::DescriptorBufferInfo; 1] {
    [vk::DescriptorBufferInfo::default()
        .buffer(buffer)
        .range(vk::WHOLE_SIZE)]
}

fn sampled(sampler: vk::Sampler, view: vk::ImageView) -> [vk::DescriptorImageInfo; 1] {
    [vk::DescriptorImageInfo::default()
        .sampler(sampler)
        .image_view(view)
        .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)]
}

/// Points the body set at its resources.
pub(super) fn write_body_set(device: &Device, set: vk::DescriptorSet, body: &BodyResources<'_>) {
    let write = |binding: BodyBinding| binding.write(set);
    let ownership = buffer_info(body.ownership.raw());
    let albedo = sampled(body.texture.sampler.raw(), body.texture.image.view());
    let uvs = buffer_info(body.corner_uvs.raw());
    let posed = buffer_info(body.posed);
    let rest = buffer_info(body.rest_triangles.raw());
    let indices = buffer_info(body.indices.raw());
    let writes = [
        write(BodyBinding::Ownership).buffer_info(&ownership),
        write(BodyBinding::Albedo).image_info(&albedo),
        write(BodyBinding::CornerUvs).buffer_info(&uvs),
        write(BodyBinding::Posed).buffer_info(&posed),
        write(BodyBinding::RestTriangles).buffer_info(&rest),
        write(BodyBinding::Indices).buffer_info(&indices),
    ];
    // SAFETY: the set is not in use by the device (just allocated) and every resource
    // written into it outlives it (the renderer owns them all).
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points a frame set at its uniforms, position image, hair counters, shadow map and
/// the simulation's arrows.
pub(super) fn write_frame_set(
    device: &Device,
    set: vk::DescriptorSet,
    uniforms: &Buffer,
    positions: (&Image, &Sampler),
    probe: &Buffer,
    counters: &Buffer,
    shadow: &ShadowMap,
) {
    let ubo = buffer_info(uniforms.raw());
    // In the simulation's GENERAL layout (`Access::HairStagesSampled`).
    let image = [vk::DescriptorImageInfo::default()
        .sampler(positions.1.raw())
        .image_view(positions.0.view())
        .image_layout(vk::ImageLayout::GENERAL)];
    let counts = buffer_info(counters.raw());
    let map = sampled(shadow.sampler.raw(), shadow.image.view());
    let arrows = buffer_info(probe.raw());
    let writes = [
        FrameBinding::Uniforms.write(set).buffer_info(&ubo),
        FrameBinding::Positions.write(set).image_info(&image),
        FrameBinding::Counters.write(set).buffer_info(&counts),
        FrameBinding::ShadowMap.write(set).image_info(&map),
        FrameBinding::Probe.write(set).buffer_info(&arrows),
    ];
    // SAFETY: the set belongs to a slot whose frames have finished (or never run); the
    // resources outlive it.
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points the hair counters of `set` (and the capture after them) at `counters`.
pub(super) fn write_counters(device: &Device, set: vk::DescriptorSet, counters: &Buffer) {
    let info = buffer_info(counters.raw());
    let writes = [FrameBinding::Counters.write(set).buffer_info(&info)];
    // SAFETY: as for `write_frame_set`: the slot's frames have finished.
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points the shadow map of `set` at `map`.
pub(super) fn write_shadow_map(device: &Device, set: vk::DescriptorSet, map: &ShadowMap) {
    let info = sampled(map.sampler.raw(), map.image.view());
    let writes = [FrameBinding::ShadowMap.write(set).image_info(&info)];
    // SAFETY: as for `write_frame_set`: the slot's frames have finished.
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

/// Points a frame set at the simulation's arrows (resized by the simulation view).
pub(super) fn write_probe(device: &Device, set: vk::DescriptorSet, probe: &Buffer) {
    let info = buffer_info(probe.raw());
    let writes = [FrameBinding::Probe.write(set).buffer_info(&info)];
    // SAFETY: as for `write_frame_set`: the device is idle (the caller waited).
    unsafe { device.raw.update_descriptor_sets(&writes, &[]) };
}

#[cfg(test)]
mod tests {
    use super::{
        binding_defines, BodyBinding, FrameBinding, RasterBinding, SET_BODY, SET_FRAME, SET_RASTER,
    };
    use crate::gpu::reflect::{check_bindings, check_struct, reflect, Reflection};
    use crate::gpu::shader::compile;
    use fur_core::render::uniforms::shader_defines;
    use fur_core::render::FrameUniforms;

    /// Each struct of the `Frame` uniform block as Rust lays it out: the GLSL struct's
    /// name and its members (name, byte offset); the `_pad` fields, std140's rounding,
    /// are not the shaders'.
    fn frame_structs() -> Vec<(&'static str, Vec<(&'static str, usize)>)> {
        let unpadded = |members: Vec<fur_core::render::std140::Member>| {
            let kept = members.into_iter().filter(|m| !m.is_padding());
            kept.map(|m| (m.name, m.offset)).collect()
        };
        fur_core::render::frame_block::structs()
            .into_iter()
            .map(|s| (s.name, unpadded(s.members)))
            .collect()
    }

    /// Every render shader embedded (all but the simulation's kernels and the includes,
    /// the compute rasteriser's passes included), compiled with every option that adds
    /// a binding, in each of its forms (the two hardware ones, then the geometry stage
    /// writing for the compute passes): (form, shader, what it declares).
    fn every_render_shader() -> Vec<(&'static str, &'static str, Reflection)> {
        let mut all = Vec::new();
        for (form, lines, compute) in [
            ("ribbons", "0", "0"),
            ("lines", "1", "0"),
            ("compute", "1", "1"),
        ] {
            let mut defines: Vec<(&str, String)> = [
                ("STRAND_VERTICES", "17"),
                ("TEXTURED", "1"),
                ("SHADOWS", "1"),
                ("BODY_SKINNED", "1"),
                ("COUNT_HAIRS", "1"),
                ("MARSCHNER", "1"),
                ("COVERAGE_SAMPLES", "4"),
                ("LINES", lines),
                ("COMPUTE_RASTER", compute),
                ("VERTEX_SHADING", compute),
                ("TILE", "8"),
                ("NEAREST", "4"),
                ("SCATTER", "1"),
                ("DEPTH_SAMPLES", "4"),
                ("TILE_GROUP", "64u"),
            ]
            .into_iter()
            .map(|(k, v)| (k, v.to_string()))
            .collect();
            defines.extend(shader_defines());
            defines.extend(binding_defines());
            let render_shaders = crate::gpu::shader::SOURCES
                .iter()
                .map(|(name, _)| *name)
                .filter(|name| {
                    [".vert", ".tesc", ".tese", ".geom", ".frag"]
                        .iter()
                        .any(|e| name.ends_with(e))
                        || (name.starts_with("strand_") && name.ends_with(".comp"))
                });
            for shader in render_shaders {
                let words = compile(shader, &defines).unwrap_or_else(|e| panic!("{shader}: {e}"));
                all.push((form, shader, reflect(&words)));
            }
        }
        all
    }

    /// Every render shader, compiled with every option that adds a binding, uses the
    /// bindings of the Rust layout with their types, and lays out the `Frame` block and
    /// each of its structs as `FrameUniforms` is (names, order, offsets); every binding
    /// of the layout is used. The block's GLSL is made from the Rust declarations, so
    /// what the offsets check is std140's layout against `#[repr(C)]`'s: a `vec3`
    /// member after a `float` (std140 aligns it to 16 bytes, Rust to 4) fails here.
    #[test]
    fn the_render_shaders_agree_with_the_rust_layouts() {
        let types = |layout: Vec<(ash::vk::DescriptorType, _)>| -> Vec<_> {
            layout.into_iter().map(|b| b.0).collect()
        };
        let (frame, body) = (
            types(FrameBinding::set_layout()),
            types(BodyBinding::set_layout()),
        );
        let mut sets = vec![Vec::new(); 3];
        sets[SET_FRAME as usize] = frame;
        sets[SET_BODY as usize] = body;
        sets[SET_RASTER as usize] = types(RasterBinding::set_layout());
        let layout: Vec<&[ash::vk::DescriptorType]> = sets.iter().map(Vec::as_slice).collect();
        let mut used = std::collections::BTreeSet::new();
        for (_, shader, found) in every_render_shader() {
            check_bindings(shader, &found, &layout).unwrap();
            if found.structs.contains_key("Frame") {
                for (name, fields) in frame_structs() {
                    check_struct(shader, &found, name, &fields).unwrap();
                }
            }
            used.extend(found.bindings.keys().copied());
        }
        let declared: usize = layout.iter().map(|s| s.len()).sum();
        assert_eq!(used.len(), declared, "bindings used: {used:?}");
        // The last struct ends with its table, and the block with the last struct.
        let (fibre, table) = (
            std::mem::offset_of!(FrameUniforms, fibre),
            std::mem::offset_of!(fur_core::render::frame_block::FibreBlock, table),
        );
        assert_eq!(
            std::mem::size_of::<FrameUniforms>(),
            fibre + table + 16 * fur_core::render::dual_scattering::TABLE_VEC4S,
            "FrameUniforms ends with the fibre's table"
        );
    }

    /// No tessellation or geometry stage, in any form, binds a storage image or a storage
    /// texel buffer: Mesa 22.3's lavapipe keys such a stage's program with bytes it never
    /// writes for each one, and compiled the compute rasteriser's geometry stage again
    /// every frame with the body at one sample (`FrameBinding::Positions`). Seen failing
    /// with the strand positions declared as a storage image in `common.glsl`.
    #[test]
    fn no_tessellation_or_geometry_stage_binds_a_storage_image() {
        use ash::vk::DescriptorType as T;
        let mut checked = 0;
        for (form, shader, found) in every_render_shader() {
            if ![".tesc", ".tese", ".geom"]
                .iter()
                .any(|e| shader.ends_with(e))
            {
                continue;
            }
            checked += 1;
            for (binding, (name, kind)) in &found.bindings {
                assert!(
                    ![T::STORAGE_IMAGE, T::STORAGE_TEXEL_BUFFER].contains(kind),
                    "{shader} ({form}) binds {name} {binding:?} as {kind:?}"
                );
            }
        }
        // fur.tesc, fur.tese, fur.geom, density.tese and density.geom (and any added
        // since) in each of the three forms.
        assert!(checked >= 15, "{checked} stages checked");
    }

    /// Without the shared defines a render shader does not compile.
    #[test]
    fn render_shaders_take_their_flags_from_rust() {
        let error = compile("fur.tesc", &[]).unwrap_err().to_string();
        assert!(error.contains("shader_defines"), "{error}");
        let flags_only = shader_defines();
        for shader in ["fur.vert", "fur.tesc", "mesh.vert", "mesh.frag"] {
            let error = compile(shader, &flags_only).unwrap_err().to_string();
            assert!(error.contains("binding_defines"), "{shader}: {error}");
        }
    }
}
