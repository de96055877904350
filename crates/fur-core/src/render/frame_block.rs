//! The `Frame` uniform block every render shader reads: one std140 struct per purpose
//! (the camera, the lighting, the drawing, the strands, the shadow, the fibre), every
//! value in a member of its own name, each written once, by [`FrameUniforms::new`] (the
//! drawing's by [`FurStyle::drawing`](super::FurStyle::drawing), beside the style).
//! Each struct is declared here, in Rust, by [`std140_struct!`]; [`glsl`] makes the
//! shaders' declarations from them (`frame_block.glsl`, which `shaders/common.glsl`
//! includes). The light's view of the fur is a second block of the same layout
//! ([`LightView::caster_uniforms`]).

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::dual_scattering::{cached_table, TABLE_VEC4S};
use super::std140::{declared, std140_struct, Declared};
use super::style::{DrawingBlock, DrawingInputs, FLAG_COUNT};
use super::uniforms::{FrameSettings, StrandShape};
use super::{Lighting, LightingModel};

/// The flags of [`LightingBlock::flags`]: the secondary highlight on, and the Marschner
/// model without its R, TT, TRT or multiple-scattering term, or without the coat's
/// light ([`super::marschner::Lobes`]).
pub const FLAG_SECONDARY_HIGHLIGHT: u32 = 8;
pub const FLAG_NO_R: u32 = 64;
pub const FLAG_NO_TT: u32 = 128;
pub const FLAG_NO_TRT: u32 = 256;
pub const FLAG_NO_MULTIPLE: u32 = 512;
pub const FLAG_NO_COAT: u32 = 1024;

/// The lighting block's flags by the names the shaders know them by.
pub const LIGHTING_FLAGS: [(&str, u32); 6] = [
    ("FLAG_SECONDARY_HIGHLIGHT", FLAG_SECONDARY_HIGHLIGHT),
    ("FLAG_NO_R", FLAG_NO_R),
    ("FLAG_NO_TT", FLAG_NO_TT),
    ("FLAG_NO_TRT", FLAG_NO_TRT),
    ("FLAG_NO_MULTIPLE", FLAG_NO_MULTIPLE),
    ("FLAG_NO_COAT", FLAG_NO_COAT),
];

/// The fraction of the frame's hair density drawn into the shadow map.
pub const CASTER_DENSITY: f32 = 0.5;

std140_struct! {
    /// The `Frame` uniform block (std140), declared for the shaders by [`glsl`]. The
    /// `_pad` fields are where std140 rounds a struct up to 16 bytes; the shaders do
    /// not see them.
    pub struct FrameUniforms("Frame") {
        pub camera: CameraBlock,
        pub lighting: LightingBlock,
        pub drawing: DrawingBlock,
        pub strands: StrandsBlock,
        pub shadow: ShadowBlock,
        pub fibre: FibreBlock,
    }
}

std140_struct! {
    /// What every pass projects with (`Camera` in GLSL).
    pub struct CameraBlock("Camera") {
        /// World to clip space.
        pub view_proj: Mat4,
        /// Clip to world space: where the compute lighting pass finds a strand
        /// vertex's world point from its place on the screen.
        pub inverse_view_proj: Mat4,
        /// The head transform H, model to world (the mesh pass's).
        pub model: Mat4,
        /// The camera's position, world space.
        pub eye: Vec3,
        /// World size of a pixel at distance 1 from the eye.
        pub pixel_at_unit_distance: f32,
        /// The target's width and height, pixels.
        pub viewport: Vec2,
        pub _pad: [f32; 2],
    }
}

std140_struct! {
    /// The light and the hair's and skin's colours (`Lighting` in GLSL).
    pub struct LightingBlock("Lighting") {
        /// Unit vector towards the light.
        pub direction: Vec3,
        pub intensity: f32,
        pub root_color: Vec3,
        /// Darkening at the root, 0..1.
        pub root_occlusion: f32,
        pub tip_color: Vec3,
        /// Kajiya–Kay's diffuse weight.
        pub kd: f32,
        pub skin_color: Vec3,
        /// Kajiya–Kay's specular weight.
        pub ks: f32,
        /// Kajiya–Kay's specular exponent.
        pub shininess: f32,
        pub ambient: f32,
        /// cos and sin of the primary highlight's shift.
        pub primary_shift: Vec2,
        /// cos and sin of the secondary highlight's shift.
        pub secondary_shift: Vec2,
        pub secondary_shininess: f32,
        pub secondary_strength: f32,
        /// [`FLAG_SECONDARY_HIGHLIGHT`] and the `FLAG_NO_*` lobes.
        pub flags: u32,
        pub _pad: [u32; 3],
    }
}

std140_struct! {
    /// The master strands' texture (`Strands` in GLSL).
    pub struct StrandsBlock("Strands") {
        pub vertices_per_strand: u32,
        pub strands_per_row: u32,
        /// A master hair whose tip is this close to its root is a bald stub (`fur.tesc`).
        pub stub_length: f32,
        pub _pad: u32,
    }
}

std140_struct! {
    /// The light's way through the fur (`Shadow` in GLSL).
    pub struct ShadowBlock("Shadow") {
        /// World to the shadow map's clip space (orthographic); identity without a map.
        pub light_view_proj: Mat4,
        /// The light each hair layer stops.
        pub opacity: f32,
        /// Hair layers per scene unit (the coat's estimate, `fur.geom`).
        pub layers_per_unit: f32,
        /// Hair layers per unit of the map's depth (0 without a map).
        pub layers_per_depth: f32,
        /// The map's depth bias, in its depth units.
        pub depth_bias: f32,
        /// Hair layers over the skin (`mesh.frag`): under the Marschner model without a
        /// shadow map, the coat's mean height at the layer spacing; 0 otherwise.
        pub skin_layers: f32,
        pub _pad: [f32; 3],
    }
}

std140_struct! {
    /// The Marschner model's fibre (`Fibre` in GLSL).
    pub struct FibreBlock("Fibre") {
        /// −1 / (2 sd²) of the R lobe's Gaussian ([`super::marschner::shader_terms`]).
        pub r_exponent: f32,
        /// 1 / (√(2π) sd) of the R lobe's Gaussian.
        pub r_norm: f32,
        /// Reflectance at normal incidence.
        pub f0: f32,
        /// 1 / d(β_n) of the colour mapping.
        pub colour_scale: f32,
        /// The cuticle's tilt, radians.
        pub cuticle_tilt: f32,
        pub _pad: [f32; 3],
        /// The dual-scattering table ([`super::dual_scattering::table`]) under the
        /// Marschner model, zeros otherwise: node (angle i, colour j) at
        /// `DS_NODE_VEC4S · (i · DS_COLOUR_NODES + j)`, [a_f, β_f², Ā_b, Δ_b] then
        /// [σ_b², a_b, α, β²].
        pub table: [Vec4; TABLE_VEC4S],
    }
}

/// The `Frame` block's structs, each as declared: the block itself first, then the
/// struct of each of its members, in order. The shaders' declarations
/// ([`glsl`]) and the reflection test both read this one list.
pub fn structs() -> Vec<Declared> {
    vec![
        declared::<FrameUniforms>(),
        declared::<CameraBlock>(),
        declared::<LightingBlock>(),
        declared::<DrawingBlock>(),
        declared::<StrandsBlock>(),
        declared::<ShadowBlock>(),
        declared::<FibreBlock>(),
    ]
}

/// The GLSL of the `Frame` block, as `shaders/common.glsl` includes it
/// (`frame_block.glsl`): each member's struct, then the block at the frame set's
/// uniform binding (`SET_FRAME`, `B_FRAME_UNIFORMS`, defined by the GPU layer).
pub fn glsl() -> String {
    let mut structs = structs().into_iter();
    let block = structs.next().expect("the block is first");
    let mut text =
        String::from("// Made from crates/fur-core/src/render/frame_block.rs: not a file.\n");
    for member in structs {
        text += &format!("\n{}", member.glsl);
    }
    text += &format!(
        "\nlayout(set = SET_FRAME, binding = B_FRAME_UNIFORMS, std140) uniform {} {{\n",
        block.name
    );
    for m in &block.members {
        text += &format!("    {} {};\n", m.glsl_type, m.name);
    }
    text + "} frame;\n"
}

/// What a frame's block takes besides its settings.
#[derive(Clone, Copy, Debug)]
pub struct FrameInputs<'a> {
    /// The target's width and height, pixels.
    pub size: (u32, u32),
    pub strands: &'a StrandShape,
    /// The device's largest tessellation level.
    pub max_level: f32,
    /// The texels of the fur's texture (0: none).
    pub texels: f32,
    /// The light's view when the frame draws shadows.
    pub light: Option<&'a LightView>,
}

impl FrameUniforms {
    pub fn new(settings: &FrameSettings, inputs: FrameInputs) -> Self {
        let (width, height) = inputs.size;
        let (w, h) = (width as f32, height as f32);
        let s = &settings.style;
        let l = &settings.lighting;
        let highlights = &l.highlights;
        let mut lighting_flags = 0;
        if highlights.secondary {
            lighting_flags |= FLAG_SECONDARY_HIGHLIGHT;
        }
        for (on, flag) in [
            (l.lobes.r, FLAG_NO_R),
            (l.lobes.tt, FLAG_NO_TT),
            (l.lobes.trt, FLAG_NO_TRT),
            (l.lobes.multiple, FLAG_NO_MULTIPLE),
            (l.lobes.coat, FLAG_NO_COAT),
        ] {
            if !on {
                lighting_flags |= flag;
            }
        }
        let (primary_sin, primary_cos) = if highlights.secondary {
            highlights.primary_shift_deg.to_radians().sin_cos()
        } else {
            (0.0, 1.0)
        };
        let (secondary_sin, secondary_cos) = highlights.secondary_shift_deg.to_radians().sin_cos();
        let layers_per_unit = l.shadows.layers_per_unit(s.density);
        // The map's depth runs over `depth_range` scene units: its layers per unit of
        // depth, and a bias of half a layer and a texel's slope.
        let (light_view_proj, layers_per_depth, depth_bias) = match inputs.light {
            Some(light) => {
                let spacing = 1.0 / layers_per_unit;
                (
                    light.view_proj,
                    light.depth_range / spacing,
                    (0.5 * spacing + light.texel) / light.depth_range,
                )
            }
            None => (Mat4::IDENTITY, 0.0, 0.0),
        };
        let terms = super::marschner::shader_terms(&l.fibre);
        let view_proj = settings.camera.view_projection(w / h);
        Self {
            camera: CameraBlock {
                view_proj,
                inverse_view_proj: view_proj.inverse(),
                model: settings.head,
                eye: settings.camera.eye(),
                pixel_at_unit_distance: settings.pixel_at_unit_distance(height),
                viewport: Vec2::new(w, h),
                _pad: [0.0; 2],
            },
            lighting: LightingBlock {
                direction: l.light_direction.normalize_or(Vec3::Y),
                intensity: l.intensity,
                root_color: l.root_color,
                root_occlusion: l.root_occlusion,
                tip_color: l.tip_color,
                kd: l.kd,
                skin_color: l.skin_color,
                ks: l.ks,
                shininess: l.shininess,
                ambient: l.ambient,
                primary_shift: Vec2::new(primary_cos, primary_sin),
                secondary_shift: Vec2::new(secondary_cos, secondary_sin),
                secondary_shininess: highlights.secondary_shininess,
                secondary_strength: highlights.secondary_strength,
                flags: lighting_flags,
                _pad: [0; 3],
            },
            drawing: s.drawing(DrawingInputs {
                max_level: inputs.max_level,
                texels: inputs.texels,
                arrow_scale: settings.arrow_scale,
                count_hairs: settings.count_hairs,
            }),
            strands: StrandsBlock {
                vertices_per_strand: inputs.strands.vertices_per_strand,
                strands_per_row: inputs.strands.strands_per_row,
                stub_length: inputs.strands.stub_length,
                _pad: 0,
            },
            shadow: ShadowBlock {
                light_view_proj,
                opacity: l.shadows.opacity,
                layers_per_unit,
                layers_per_depth,
                depth_bias,
                skin_layers: skin_layers(l, layers_per_unit, inputs.strands.coat_height),
                _pad: [0.0; 3],
            },
            fibre: FibreBlock {
                r_exponent: terms[0],
                r_norm: terms[1],
                f0: terms[2],
                colour_scale: terms[3],
                cuticle_tilt: l.fibre.cuticle_tilt_deg.to_radians(),
                _pad: [0.0; 3],
                table: if l.model == LightingModel::Marschner {
                    *cached_table(&l.fibre)
                } else {
                    [Vec4::ZERO; TABLE_VEC4S]
                },
            },
        }
    }
}

/// The hair layers over the skin that the mesh pass lights it through: under the
/// Marschner model without a shadow map, the coat's mean height at the layer spacing
/// (the coat's estimate, as the hairs' own, `coat_layers` of `fur.geom`); 0 otherwise
/// (Kajiya–Kay lights the skin as the seed does; a shadow map measures the light's way
/// through the fur itself).
fn skin_layers(lighting: &Lighting, layers_per_unit: f32, coat_height: f32) -> f32 {
    if lighting.model == LightingModel::Marschner
        && !lighting.shadows.enabled
        && lighting.lobes.coat
    {
        coat_height * layers_per_unit
    } else {
        0.0
    }
}

/// Where the light looks from and what its map's depth means. The light is
/// directional: an orthographic view along it that holds a sphere around the model.
#[derive(Clone, Copy, Debug)]
pub struct LightView {
    pub view_proj: Mat4,
    /// A point far along the light (for the fur pass's culling and level of detail).
    pub eye: Vec3,
    /// Scene units from the map's near to its far plane.
    pub depth_range: f32,
    /// Scene units one texel spans.
    pub texel: f32,
}

impl LightView {
    /// The view along `settings`' light that holds a sphere of `radius` around
    /// `centre` (world space) in a map of `resolution` texels.
    pub fn new(settings: &FrameSettings, centre: Vec3, radius: f32, resolution: u32) -> Self {
        let l = settings.lighting.light_direction.normalize_or(Vec3::Y);
        let up = if l.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let eye = centre + l * (2.0 * radius);
        let view = Mat4::look_at_rh(eye, centre, up);
        // Glam's orthographic projection maps depth to Vulkan's [0, 1].
        let proj = Mat4::orthographic_rh(-radius, radius, -radius, radius, radius, 3.0 * radius);
        Self {
            view_proj: proj * view,
            eye,
            depth_range: 2.0 * radius,
            texel: 2.0 * radius / resolution as f32,
        }
    }

    /// The view along `settings`' light that holds a model of bounding sphere `centre`,
    /// `radius` (model space) grown by its hair (`hair_length`), as the frame's head
    /// transform carries it.
    pub fn of_model(
        settings: &FrameSettings,
        centre: Vec3,
        radius: f32,
        hair_length: f32,
        resolution: u32,
    ) -> Self {
        let head = settings.head;
        let scale = head.transform_vector3(Vec3::X).length().max(1e-12);
        let reach = (radius + 1.25 * hair_length) * scale;
        Self::new(settings, head.transform_point3(centre), reach, resolution)
    }

    /// The block of the light's view of the fur, from the frame's: its camera, lines
    /// only, no counting, [`CASTER_DENSITY`] of the hairs, full density at any distance.
    pub fn caster_uniforms(&self, frame: &FrameUniforms) -> FrameUniforms {
        let mut u = *frame;
        u.camera.view_proj = self.view_proj;
        u.camera.inverse_view_proj = self.view_proj.inverse();
        // The eye is the map's depth range from the centre: a texel there is `texel` wide.
        u.camera.eye = self.eye;
        u.camera.pixel_at_unit_distance = self.texel / self.depth_range;
        u.drawing.density *= CASTER_DENSITY;
        u.drawing.lod_distance = f32::MAX;
        u.drawing.ribbon_above_px = f32::MAX;
        u.drawing.flags &= !FLAG_COUNT;
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::uniforms::StrandShape;

    /// A strand vertex's world point, found again as the compute lighting pass finds it
    /// (`world_position` in shaders/strand_raster.glsl) from where the geometry stage
    /// puts it on the screen (pixels, NDC z; fur.geom's keep_vertex), all in f32, is
    /// within 1.5·10⁻⁵ of the camera's distance of the point across the view out to the
    /// camera's target (seen: 1.1·10⁻⁵), and within 3·10⁻⁵ out to twice that (seen:
    /// 2.5·10⁻⁵); and the light's view carries its own inverse. Seen failing with the
    /// inverse left the identity and with the camera's inverse kept in the light's
    /// view.
    #[test]
    fn the_inverse_projection_finds_each_strand_vertex_again() {
        let settings = FrameSettings::default();
        let (width, height) = (1280u32, 720u32);
        let shape = StrandShape {
            vertices_per_strand: 8,
            strands_per_row: 64,
            stub_length: 0.0,
            coat_height: 0.1,
        };
        let inputs = |light| FrameInputs {
            size: (width, height),
            strands: &shape,
            max_level: 64.0,
            texels: 0.0,
            light,
        };
        let u = FrameUniforms::new(&settings, inputs(None));
        let camera = &u.camera;
        let viewport = Vec2::new(width as f32, height as f32);
        let eye = settings.camera.eye();
        let distance = settings.camera.distance;
        let forward = (settings.camera.target - eye).normalize();
        let side = forward.cross(Vec3::Y).normalize();
        let up = side.cross(forward);
        let mut worst = 0.0f32;
        for along in [0.1, 0.5, 1.0, 1.5, 2.0] {
            for (a, b) in [(0.0, 0.0), (0.3, 0.2), (-0.4, 0.1), (0.2, -0.35)] {
                let p = eye + distance * (along * forward + along * (a * side + b * up));
                // As the geometry stage puts it on the screen.
                let clip = camera.view_proj * p.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                let pixel = (ndc.truncate() * 0.5 + 0.5) * viewport;
                // As the lighting pass finds it again.
                let back = pixel / viewport * 2.0 - 1.0;
                let world = camera.inverse_view_proj * Vec4::new(back.x, back.y, ndc.z, 1.0);
                let found = world.truncate() / world.w;
                let off = (found - p).length() / distance;
                // The depth's float spacing grows with the square of the depth.
                let bound = if along <= 1.0 { 1.5e-5 } else { 3e-5 };
                assert!(
                    off < bound,
                    "{along} of the distance out: off by {off} of it"
                );
                worst = worst.max(off);
            }
        }
        assert!(
            worst > 0.0,
            "the round trip is exact: the test measures nothing"
        );
        let light = LightView::new(&settings, Vec3::ZERO, 2.0, 512);
        let caster = light.caster_uniforms(&u);
        let identity = caster.camera.inverse_view_proj * caster.camera.view_proj;
        assert!(identity.abs_diff_eq(Mat4::IDENTITY, 1e-4), "{identity}");
    }
}
