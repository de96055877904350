//! One frame: the shadow pass (with shadows), then the mesh pass and the fur pass into
//! the offscreen target, recorded as a list of passes (`super::graph`), with
//! timestamps around each pass, pipeline statistics over the target's passes and, on
//! request, counts of the hairs and segments drawn.
//!
//! On a tiled or binning rasteriser (lavapipe) a timestamp between the passes of one
//! rendering scope lands part-way through the next pass's binning, so the per-pass
//! timestamps misattribute there; `fur bench` measures passes by running each alone.

use std::sync::Arc;

use ash::vk;

use super::bindings::{write_probe, write_shadow_map};
use super::graph::Pass;
use super::slot::{RenderSlot, TS_FRAME, TS_START};
use super::target::{check_samples, RenderTarget};
use super::texture::{GpuTexture, ShadowMap};
use crate::error::Result;
use crate::gpu::{Buffer, DescriptorPool, DescriptorSetLayout, Device, PipelineLayout};
use crate::strand_textures::StrandTextures;
use compute_raster::ComputeRaster;
use fur_core::render::uniforms::{FrameSettings, Raster, Stage, StrandShape};
use fur_core::render::RgbaImage;
use fur_core::render::{FrameInputs, FrameUniforms, LightView, LightingModel};
use fur_pass::FurPass;
use mesh_pass::{BodyTraits, MeshLook, MeshPass};
use registry::{register, FramePass, Phase, Plan};

mod build;
mod capture;
mod raster_capture;
mod raster_pools;
mod raster_steps;
mod record;
mod registry;
mod report;

// The renderer's own passes, which the sample count, the frame slots and the capture
// reach into: the body, the fur and the compute rasteriser's.
pub mod compute_raster;
mod fur_pass;
mod mesh_pass;

// The registered passes: each builds, prepares and places itself (`registry`).
register! {
    counter_reset::CounterReset,
    shadow_pass::ShadowPass,
    masters_pass::MastersPass,
    density_pass::DensityPass,
    strand_counts_reset::StrandCountsReset,
}

pub use fur_pass::Variant;

pub use capture::{CapturedHairs, MAX_CAPTURE_BYTES};
pub use raster_capture::RasterCapture;
use raster_steps::StrandLighting;
pub use raster_steps::STEP_NAMES;
pub use report::{FrameReport, HairCounts};

/// The colour behind the model (linear RGB), where nothing is drawn.
pub const BACKGROUND: glam::Vec3 = glam::Vec3::new(0.02, 0.025, 0.035);

pub struct Renderer {
    device: Arc<Device>,
    /// The frame set's layout and the body set's.
    _set_layouts: (DescriptorSetLayout, DescriptorSetLayout),
    /// The body's descriptor set (set 1), written once.
    body_set: vk::DescriptorSet,
    pipeline_layout: PipelineLayout,
    _pool: DescriptorPool,
    /// Per frame in flight: what the host writes or reads back while other frames run.
    slots: Vec<RenderSlot>,
    _ownership: Buffer,
    /// Per triangle, its rest edge lengths and area; stands in for the posed vertices
    /// of a rigid body too.
    _rest_triangles: Buffer,
    /// The model's texture and its UVs per triangle corner (a white texel and no UVs
    /// for a model drawn without).
    texture: (GpuTexture, Buffer),
    /// Whether the body is textured, and skinned (its posed vertices come from the
    /// skinning pass).
    body: BodyTraits,
    /// The fur pass's patches: the body's triangles, then a drawn groom's own.
    indices: Buffer,
    /// The body's triangles' indices (the mesh and density passes draw these).
    index_count: u32,
    /// The fur pass's patches' indices (the fur and shadow passes draw these).
    hair_index_count: u32,
    shape: StrandShape,
    /// The model's bounding sphere in model space (centre, radius).
    bounds: (glam::Vec3, f32),
    /// The longest master hair at rest (the light's view holds the fur with it).
    hair_length: f32,
    mesh_pass: MeshPass,
    fur_pass: FurPass,
    /// The registered passes (`register!`), in their registration's order.
    registered: Vec<Box<dyn FramePass>>,
    /// The compute rasteriser's passes (`--raster compute`); its pools are made on
    /// first use.
    compute_raster: ComputeRaster,
    pub target: RenderTarget,
    /// The target and fur pass of the sample count in use before the last change, kept
    /// so that changing back (as the frame-time budget does) builds nothing.
    spare: Option<(RenderTarget, FurPass)>,
}

impl Renderer {
    /// Recreates the render target for a new image size.
    pub fn resize(&mut self, extent: vk::Extent2D) -> Result<()> {
        if extent != self.target.extent {
            self.target = RenderTarget::new(&self.device, extent, self.target.samples)?;
            self.spare = None;
        }
        Ok(())
    }

    /// How many frame slots have drawn shadows.
    pub fn shadow_maps(&self) -> usize {
        self.slots.iter().filter(|s| s.shadow_drawn).count()
    }

    /// The sample counts per pixel this device can render.
    pub fn supported_samples(&self) -> Vec<u32> {
        super::target::supported_samples(&self.device)
    }

    /// Switches the target and the fur pass's pipelines to `samples` per pixel, building
    /// them unless they are the spare ones of the last switch. Nothing may be in flight.
    fn set_samples(&mut self, samples: u32) -> Result<()> {
        check_samples(&self.device, samples)?;
        let (target, fur_pass) = match self.spare.take() {
            Some((target, pass)) if target.samples == samples => (target, pass),
            _ => (
                RenderTarget::new(&self.device, self.target.extent, samples)?,
                FurPass::new(
                    &self.device,
                    self.shape.vertices_per_strand,
                    samples,
                    self.body,
                ),
            ),
        };
        self.mesh_pass.set_samples(samples);
        let target = std::mem::replace(&mut self.target, target);
        let fur_pass = std::mem::replace(&mut self.fur_pass, fur_pass);
        self.spare = Some((target, fur_pass));
        Ok(())
    }

    /// Prepares frame slot `slot` for `settings`: builds the pipelines it needs and
    /// writes its uniforms. Call before recording the frame, once the slot's previous
    /// frame has finished; a change of sample count needs the device idle.
    pub fn update(&mut self, slot: usize, settings: &FrameSettings) -> Result<()> {
        Self::check_device(&self.device.info, settings)?;
        if settings.style.samples != self.target.samples {
            self.set_samples(settings.style.samples)?;
        }
        // The fur casts shadows even when it is not drawn (the skin shows them); the
        // stage views are unlit and unshadowed but for the shadow view, which draws
        // shadows whatever the scene says.
        let forced;
        let settings = if settings.show == Stage::Shadow && !settings.lighting.shadows.enabled {
            let mut s = settings.clone();
            s.lighting.shadows.enabled = true;
            forced = s;
            &forced
        } else {
            settings
        };
        let shadows = settings.lighting.shadows.enabled
            && matches!(settings.show, Stage::Lit | Stage::Shadow);
        let (centre, radius) = self.bounds;
        let mut variants = Vec::new();
        if settings.show.draws_fur() {
            variants = FurPass::variants(
                &settings.style,
                shadows,
                settings.lighting.model,
                settings.show,
                FurPass::root_pixel_range(settings, centre, radius, self.target.extent.height),
            );
            self.fur_pass.prepare(&self.pipeline_layout, &variants)?;
        }
        let plan = Plan {
            settings,
            shadows,
            layout: &self.pipeline_layout,
            samples: self.target.samples,
        };
        for pass in &mut self.registered {
            if pass.wanted(&plan) {
                pass.prepare(&plan)?;
            }
        }
        if Self::draws_in_compute(settings) {
            // The lit frame's strands under the Marschner model are lit by a compute
            // pass; the geometry stage colours the others.
            let lighting = variants
                .iter()
                .find(|v| v.compute && v.view == 0 && v.model == LightingModel::Marschner)
                .map(|v| StrandLighting { shadows: v.shadows });
            self.compute_raster.prepare(
                &self.target,
                &self.pipeline_layout,
                slot,
                &settings.style,
                (settings.show == Stage::Tiles, lighting),
            )?;
        }
        self.mesh_pass.prepare(
            &self.device,
            &self.pipeline_layout,
            MeshLook::of(settings.show, shadows),
        )?;
        let (extent, max_level) = (self.target.extent, self.max_level());
        let resolution = settings.lighting.shadows.resolution;
        let hair_length = self.hair_length;
        let light =
            shadows.then(|| LightView::of_model(settings, centre, radius, hair_length, resolution));
        let frame = &mut self.slots[slot];
        if shadows {
            if frame.shadow.resolution != resolution {
                let map = ShadowMap::new(&self.device, &format!("shadow_map[{slot}]"), resolution)?;
                for set in frame.sets.iter().chain(&frame.light_sets) {
                    write_shadow_map(&self.device, *set, &map);
                }
                frame.shadow = map;
            }
            frame.shadow_drawn = true;
        }
        let uniforms = FrameUniforms::new(
            settings,
            FrameInputs {
                size: (extent.width, extent.height),
                strands: &self.shape,
                max_level,
                texels: self.texture.0.texels,
                light: light.as_ref(),
            },
        );
        if let Some(light) = &light {
            let caster = light.caster_uniforms(&uniforms);
            frame.light_uniforms.write(0, bytemuck::bytes_of(&caster));
        }
        frame.uniforms.write(0, bytemuck::bytes_of(&uniforms));
        frame.variants = variants;
        frame.shadows = shadows;
        frame.compute = Self::draws_in_compute(settings);
        Ok(())
    }

    /// Points every frame set at `strands`' probe, after the simulation view sized it
    /// (`GpuSim::set_probe`). The device must be idle.
    pub fn bind_probe(&self, strands: &StrandTextures) {
        for slot in &self.slots {
            for set in slot.sets.iter().chain(&slot.light_sets) {
                write_probe(&self.device, *set, &strands.probe);
            }
        }
    }

    /// The largest tessellation level the device generates (the density view's scale
    /// ends there).
    pub fn max_level(&self) -> f32 {
        self.device.info.limits.max_tessellation_generation_level as f32
    }

    /// The frame's passes, phase by phase ([`Phase`]): the registered passes the frame
    /// wants, then the renderer's own: the body, and the fur (with the compute
    /// rasteriser's passes) when the frame shows it. Only what the frame needs is in
    /// the list.
    fn passes(&self, settings: &FrameSettings, shadows: bool) -> Vec<&dyn Pass> {
        let plan = Plan {
            settings,
            shadows,
            layout: &self.pipeline_layout,
            samples: self.target.samples,
        };
        let compute = Self::draws_in_compute(settings);
        let mut passes: Vec<&dyn Pass> = Vec::new();
        for phase in Phase::ALL {
            for pass in &self.registered {
                if pass.phase() == phase && pass.wanted(&plan) {
                    passes.push(pass.as_pass());
                }
            }
            match phase {
                Phase::Body => passes.push(&self.mesh_pass),
                Phase::Stage if settings.show.draws_fur() => {
                    passes.push(&self.fur_pass);
                    if compute {
                        passes.extend(self.compute_raster.draw_passes().map(|p| p as &dyn Pass));
                    }
                }
                _ => {}
            }
        }
        passes
    }
}
