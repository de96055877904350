//! The fur pass: mesh triangles as 3-point patches through
//! vertex → tessellation control → tessellation evaluation (point mode) → geometry →
//! fragment. See the shaders `fur.*` for what each stage does.
//!
//! The geometry stage comes in two forms, line strips and ribbons, each with lighting
//! per vertex or per fragment; only the forms a frame draws are built (on first use)
//! and drawn.

use std::sync::Arc;

use ash::vk;

use super::super::graph::{FrameContext, Pass};
use super::super::pipeline::{
    graphics_pipeline, Blend, ColourAttachment, DepthAttachment, GraphicsDesc,
};
use super::super::target::{sample_flag, COLOR_FORMAT, DEPTH_FORMAT};
use super::mesh_pass::BodyTraits;
use crate::error::Result;
use crate::frame::{uses, Resource, Use};
use crate::gpu::{Access, Device, Pipeline, PipelineLayout, ShaderModule};
use fur_core::render::uniforms::{FrameSettings, FurStyle, Primitive, Raster, Shading, Stage};
use fur_core::render::LightingModel;

/// One compiled form of the fur pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    pub lines: bool,
    pub shading: Shading,
    /// Ribbons carry their coverage in alpha (thin-hair anti-aliasing); lines always do.
    pub coverage: bool,
    /// Reads the shadow map.
    pub shadows: bool,
    /// The light's view into the shadow map: depth only, lines.
    pub caster: bool,
    /// How the hair is lit.
    pub model: LightingModel,
    /// The stage view it draws (`Stage::code`: 0 lit).
    pub view: u32,
    /// Writes the strands for the compute passes instead of drawing them
    /// (`--raster compute`): lit per vertex (under the Marschner model by the compute
    /// lighting pass), nothing emitted.
    pub compute: bool,
}

impl Variant {
    /// The form that draws the fur into the shadow map.
    pub const CASTER: Variant = Variant {
        lines: true,
        shading: Shading::Fragment,
        coverage: false,
        shadows: false,
        caster: true,
        model: LightingModel::KajiyaKay,
        view: 0,
        compute: false,
    };
}

pub struct FurPass {
    device: Arc<Device>,
    vertices_per_strand: u32,
    samples: u32,
    /// Whether hairs take their colour from the model's texture.
    textured: bool,
    /// Whether the body is skinned (density from the rest pose, binding 8).
    skinned: bool,
    /// Whether the geometry stage may count what it draws (the device supports stores
    /// and atomics in vertex-pipeline stages).
    counts: bool,
    pipelines: Vec<(Variant, Pipeline)>,
}

impl FurPass {
    /// The pass's name (its debug label; the frame's timestamps follow it).
    pub const NAME: &'static str = "fur pass";

    /// A pass for strands of `vertices_per_strand` vertices (the geometry shader's
    /// output size is fixed at compile time) into a target of `samples` per pixel,
    /// coloured by the model's texture when `textured`.
    pub fn new(
        device: &Arc<Device>,
        vertices_per_strand: u32,
        samples: u32,
        BodyTraits { textured, skinned }: BodyTraits,
    ) -> Self {
        Self {
            device: device.clone(),
            vertices_per_strand,
            samples,
            textured,
            skinned,
            counts: device.info.vertex_pipeline_stores,
            pipelines: Vec::new(),
        }
    }

    /// The forms `style` draws with hairs `root_px` pixels wide at the root (the range
    /// over the model), lit by `model` or coloured by the stage view `stage`: ribbons
    /// first, then the blended lines over them. A stage view is unlit and unshadowed,
    /// its colour made per vertex.
    pub fn variants(
        style: &FurStyle,
        shadows: bool,
        model: LightingModel,
        stage: Stage,
        root_px: std::ops::RangeInclusive<f32>,
    ) -> Vec<Variant> {
        let view = stage.fur_code();
        let compute = style.raster == Raster::Compute || stage.needs_compute();
        let (lines, ribbons) = match style.primitive {
            // One form: the compute passes draw every width.
            _ if compute => (true, false),
            Primitive::Lines => (true, false),
            Primitive::Ribbons => (false, true),
            Primitive::Auto => (
                *root_px.start() < style.ribbon_above_px,
                *root_px.end() >= style.ribbon_above_px,
            ),
        };
        [(ribbons, false), (lines, true)]
            .into_iter()
            .filter(|(wanted, _)| *wanted)
            .map(|(_, lines)| Variant {
                lines,
                shading: if view == 0 && !compute {
                    style.shading
                } else {
                    Shading::Vertex
                },
                coverage: style.thin_hair_aa,
                // The shadow view shows the shadowing term: it reads the map.
                shadows: shadows && (view == 0 || stage == Stage::Shadow),
                caster: false,
                // The lit frame and the shadow view (Marschner's light through the
                // fibres is coloured) depend on the model; the other views do not.
                model: if view == 0 || stage == Stage::Shadow {
                    model
                } else {
                    LightingModel::KajiyaKay
                },
                view,
                compute,
            })
            .collect()
    }

    /// The smallest and largest width, in pixels, of a hair's root anywhere on the
    /// model (bounding sphere `centre`, `radius`) in a target `height` pixels tall.
    pub fn root_pixel_range(
        settings: &FrameSettings,
        centre: glam::Vec3,
        radius: f32,
        height: u32,
    ) -> std::ops::RangeInclusive<f32> {
        let style = &settings.style;
        let centre = settings.head.transform_point3(centre);
        let eye = settings.camera.eye();
        let near = (eye.distance(centre) - radius).max(1e-6);
        let far = eye.distance(centre) + radius;
        let pixel = settings.pixel_at_unit_distance(height);
        let width_px = |d: f32| {
            let lod = (style.lod_distance / d).powi(2).min(1.0);
            let thickness = if style.thickness_compensation {
                style.hair_width / lod
            } else {
                style.hair_width
            };
            (thickness / (pixel * d)).max(style.min_pixel_width)
        };
        // Without compensation the width falls with distance; with it, it falls up to
        // the full-density distance and grows beyond.
        let mut samples = vec![width_px(near), width_px(far)];
        if (near..=far).contains(&style.lod_distance) {
            samples.push(width_px(style.lod_distance));
        }
        let lo = samples.iter().copied().fold(f32::MAX, f32::min);
        let hi = samples.iter().copied().fold(0.0, f32::max);
        lo..=hi
    }

    /// Whether the body is skinned.
    pub fn skinned(&self) -> bool {
        self.skinned
    }

    /// Builds the pipelines of `variants` that do not exist yet.
    pub fn prepare(&mut self, layout: &PipelineLayout, variants: &[Variant]) -> Result<()> {
        for &variant in variants {
            if !self.pipelines.iter().any(|(v, _)| *v == variant) {
                let pipeline = self.build(layout, variant)?;
                self.pipelines.push((variant, pipeline));
            }
        }
        Ok(())
    }

    fn build(&self, layout: &PipelineLayout, variant: Variant) -> Result<Pipeline> {
        let flag = |on: bool| u32::from(on).to_string();
        let textured = flag(self.textured && !variant.caster);
        // Coverage under MSAA as a dithered sample mask (see fur.frag); alpha, blended,
        // at one sample per pixel; none for opaque ribbons.
        let covers = (variant.lines || variant.coverage) && !variant.caster;
        let coverage_samples = if covers && self.samples > 1 {
            self.samples
        } else {
            0
        };
        let shared = super::super::bindings::render_defines();
        let mut common = vec![
            ("VERTEX_SHADING", flag(variant.shading == Shading::Vertex)),
            ("TEXTURED", textured.clone()),
            ("SHADOWS", flag(variant.shadows)),
            ("MARSCHNER", flag(variant.model == LightingModel::Marschner)),
            ("COVERAGE_SAMPLES", coverage_samples.to_string()),
            ("STAGE_VIEW", variant.view.to_string()),
        ];
        common.extend(shared.iter().cloned());
        let mut geometry_defines = vec![
            ("STRAND_VERTICES", self.vertices_per_strand.to_string()),
            ("LINES", flag(variant.lines)),
            ("SHADOW_CASTER", flag(variant.caster)),
            ("COUNT_HAIRS", flag(self.counts && !variant.caster)),
            ("COMPUTE_RASTER", flag(variant.compute)),
        ];
        geometry_defines.extend(common.iter().cloned());
        let device = &self.device;
        let vert = ShaderModule::new(device, "fur.vert", &shared)?;
        let mut tesc_defines = vec![
            ("COUNT_HAIRS", flag(self.counts && !variant.caster)),
            ("BODY_SKINNED", flag(self.skinned)),
            ("TEXTURED", textured.clone()),
        ];
        tesc_defines.extend(shared.iter().cloned());
        let tesc = ShaderModule::new(device, "fur.tesc", &tesc_defines)?;
        let mut tese_defines = vec![("TEXTURED", textured)];
        tese_defines.extend(shared.iter().cloned());
        let tese = ShaderModule::new(device, "fur.tese", &tese_defines)?;
        let geom = ShaderModule::new(device, "fur.geom", &geometry_defines)?;
        let frag = ShaderModule::new(device, "fur.frag", &common)?;
        // All forms write depth: a blended hair hides the hairs drawn after it behind
        // it, a measured trade (without depth writes, hairs behind drawn later cover
        // the ones in front, far worse).
        let blend = if covers && self.samples == 1 {
            Blend::Alpha
        } else {
            Blend::Opaque
        };
        let colour = [ColourAttachment {
            format: COLOR_FORMAT,
            blend,
        }];
        let name = if variant.caster {
            "fur shadow pass".to_string()
        } else {
            format!(
                "fur pass ({}, {} {} shading{}{})",
                if variant.compute {
                    "strands for compute"
                } else if variant.lines {
                    "lines"
                } else {
                    "ribbons"
                },
                variant.shading.name(),
                variant.model.label(),
                if variant.coverage { ", coverage" } else { "" },
                if variant.shadows { ", shadows" } else { "" },
            ) + if variant.view == 0 {
                ""
            } else {
                ", stage view"
            }
        };
        let mut stages = vec![
            (vk::ShaderStageFlags::VERTEX, &vert),
            (vk::ShaderStageFlags::TESSELLATION_CONTROL, &tesc),
            (vk::ShaderStageFlags::TESSELLATION_EVALUATION, &tese),
            (vk::ShaderStageFlags::GEOMETRY, &geom),
        ];
        if !variant.caster && !variant.compute {
            stages.push((vk::ShaderStageFlags::FRAGMENT, &frag));
        }
        graphics_pipeline(
            device,
            layout,
            &GraphicsDesc {
                name: &name,
                stages: &stages,
                topology: vk::PrimitiveTopology::PATCH_LIST,
                vertex_bindings: &[],
                vertex_attributes: &[],
                patch_control_points: Some(3),
                samples: if variant.caster {
                    vk::SampleCountFlags::TYPE_1
                } else {
                    sample_flag(self.samples)
                },
                colour: if variant.caster { &[] } else { &colour },
                depth: Some(DepthAttachment::nearest(DEPTH_FORMAT)),
            },
        )
    }

    /// Records the draws of `variants` (prepared before); the caller has bound the
    /// descriptor set.
    pub fn draw(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        index_count: u32,
        variants: &[Variant],
    ) {
        for variant in variants {
            let Some((_, pipeline)) = self.pipelines.iter().find(|(v, _)| v == variant) else {
                continue;
            };
            // SAFETY: recording inside a rendering scope with the sets bound; the pipeline lives
            // as long as the pass, which outlives the frame (the renderer waits before dropping it).
            unsafe {
                device
                    .raw
                    .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw());
                // Unindexed: fur.vert reads each corner's master hair from the triangle
                // list and numbers the triangles itself.
                device.raw.cmd_draw(cmd, index_count, 1, 0, 0);
            }
        }
    }
}

/// The hair stages read the strands and the posed body; with `counts`, the control and
/// geometry stages count what they cull and draw into the counters.
pub(super) fn hair_uses(skinned: bool, counts: bool) -> Vec<Use> {
    let mut list = vec![uses(Resource::Positions, Access::HairStagesSampled)];
    if skinned {
        list.push(uses(Resource::Posed, Access::HairStagesRead));
    }
    if counts {
        list.push(uses(Resource::Counters, Access::CounterStagesReadWrite));
    }
    list
}

impl Pass for FurPass {
    fn name(&self) -> &'static str {
        FurPass::NAME
    }

    /// The fur's end, or, when its strands are drawn in compute, the geometry stage's
    /// writing of them (the compute steps then time the rest).
    fn timestamp(&self, frame: &FrameContext<'_>) -> Option<u32> {
        use super::super::slot::{TS_FUR, TS_STRANDS};
        let compute = frame.slot.variants.iter().any(|v| v.compute);
        Some(if compute { TS_STRANDS } else { TS_FUR })
    }

    fn uses(&self, frame: &FrameContext<'_>) -> Vec<Use> {
        // The shading samples the shadow map.
        let mut list = hair_uses(self.skinned, frame.settings.count_hairs);
        if frame.slot.variants.iter().any(|v| v.compute) {
            // The geometry stage writes the strands for the compute passes.
            list.push(uses(Resource::Strands, Access::CounterStagesReadWrite));
        }
        if frame.slot.shadows {
            list.push(uses(Resource::ShadowMap, Access::ShadingSampled));
        }
        list
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        if !frame.settings.draw_fur {
            return;
        }
        self.draw(
            frame.device,
            cmd,
            frame.hair_index_count,
            &frame.slot.variants,
        );
    }
}
