//! Strands drawn in compute (`--raster compute`): the fur pass's geometry stage writes
//! each strand into buffers and emits nothing; then compute passes light its vertices
//! (under the Marschner model), find each tile's farthest body depth, count the segments per tile,
//! place each tile's list in one pool, list the segments, sort each list front to back
//! into depth bins, and draw each tile's pixels with exact coverage and their nearest
//! fragments blended front to back, each stopping once opaque; a last pass
//! composites the hair layer over the target. The shaders are `strand_*`; the CPU twin
//! is `fur_core::render::strand_raster`.
//!
//! Every buffer is sized from a per-pixel budget ([`PoolBudget`]); what does not fit
//! is counted ([`ComputeCounts`]), never written past the end.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::super::bindings::{render_defines, RasterBinding};
use super::super::target::RenderTarget;
use super::raster_pools::Pools;
use super::raster_steps::{lighting_groups, Step, StepPass, StrandLighting};
use crate::error::Result;
use crate::gpu::{
    Buffer, DescriptorPool, DescriptorSetLayout, Device, Pipeline, PipelineLayout, Sampler,
    Specialization,
};
use fur_core::render::strand_raster::pools::{Demand, PoolBudget};
use fur_core::render::FurStyle;

pub use super::strand_counts_reset::ComputeCounts;
use super::strand_counts_reset::CountWords;

/// The workgroups a CPU driver scatters in, one for each half of the segments
/// (strand_bin.comp, SERIAL_SCATTER).
const SCATTER_GROUPS: u32 = 2;

/// The workgroups the scatter runs as on a device of `info`: on a CPU driver one for
/// each half of the segments, each filling a part of every tile's list of its own, so
/// every frame lists each tile's segments in the same order (strand_bin.comp,
/// SERIAL_SCATTER); elsewhere as many as the segments ask (None: the indirect dispatch
/// the geometry stage leaves).
pub(super) fn scatter_groups(info: &crate::gpu::DeviceInfo) -> Option<u32> {
    info.is_cpu().then_some(SCATTER_GROUPS)
}

/// The invocations of the workgroup of a pass that works a tile of `tile` pixels a
/// side at a time and meets at barriers (the tiles and sort passes: TILE_GROUP) on a
/// device of `info`: on a CPU driver one subgroup (a SIMD vector), since a workgroup of
/// several vectors makes lavapipe switch between them at each barrier (a workgroup of 64 made the sort pass 2.7× as dear on the original's
/// sphere: `fur render`, its steps left out); elsewhere an invocation a pixel.
pub(super) fn tile_group(info: &crate::gpu::DeviceInfo, tile: u32) -> u32 {
    let pixels = tile * tile;
    if info.is_cpu() {
        info.subgroup_size.clamp(1, pixels)
    } else {
        pixels
    }
}

/// What the pipelines are built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PipelineKey {
    /// The target's samples per pixel (the body's depth the passes read).
    samples: u32,
    /// The fragments a pixel keeps in order.
    nearest: u32,
    /// The tile side, pixels.
    tile: u32,
    /// Whether the composite shows the tiles (`--show tiles`).
    tiles_view: bool,
    /// How the lighting pass lights the strands (None: the geometry stage colours them,
    /// under Kajiya–Kay and in the stage views).
    lighting: Option<StrandLighting>,
}

/// The compute rasteriser: its pools, its sets (one per frame in flight, each with its
/// own counts), its pipelines and the steps of the frame.
pub struct ComputeRaster {
    device: Arc<Device>,
    pub(super) budget: PoolBudget,
    _layout: DescriptorSetLayout,
    _pool: DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    /// What each set was last pointed at: the depth image it reads (pools change with it).
    written: Vec<vk::Image>,
    counts: Vec<Buffer>,
    sampler: Sampler,
    pub(super) pools: Option<Pools>,
    /// The most any frame has asked the pools for, with room to spare.
    demand: Demand,
    /// The pipelines, and what they were built for.
    pipelines: Option<(PipelineKey, Vec<(Step, Pipeline)>)>,
    steps: Vec<StepPass>,
    /// The steps of [`STEP_NAMES`](super::STEP_NAMES) from this place on are left out
    /// of the frame (`Renderer::leave_out_raster_steps`).
    pub(super) kept: usize,
}

impl ComputeRaster {
    /// The raster set's layout (set 2 of the render pipeline layout).
    pub fn set_layout(device: &Arc<Device>) -> Result<DescriptorSetLayout> {
        DescriptorSetLayout::new(device, "raster.set_layout", &RasterBinding::set_layout())
    }

    /// A rasteriser for `slots` frames in flight, its sets of `layout`; nothing sized yet.
    pub fn new(device: &Arc<Device>, layout: DescriptorSetLayout, slots: usize) -> Result<Self> {
        let slots = slots.max(1);
        let pool = DescriptorPool::new(
            device,
            "raster.descriptor_pool",
            slots as u32,
            &RasterBinding::set_layout(),
        )?;
        let sets = pool.allocate(&layout, slots)?;
        let counts = (0..slots)
            .map(|slot| {
                let mut counts = Buffer::new(
                    device,
                    &format!("raster.counts[{slot}]"),
                    ComputeCounts::BUFFER_BYTES,
                    vk::BufferUsageFlags::STORAGE_BUFFER
                        | vk::BufferUsageFlags::INDIRECT_BUFFER
                        | vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )?;
                // `prepare` reads what the slot's last frame asked the pools for before
                // its first frame: nothing, not what the memory held before (another
                // buffer's words, which once asked for four billion vertices).
                counts.write(0, bytemuck::bytes_of(&CountWords::default()));
                Ok(counts)
            })
            .collect::<Result<Vec<_>>>()?;
        let sampler = Sampler::nearest(device, "raster.depth_sampler")?;
        Ok(Self {
            device: device.clone(),
            budget: PoolBudget::default(),
            _layout: layout,
            _pool: pool,
            written: vec![vk::Image::null(); sets.len()],
            sets,
            counts,
            sampler,
            pools: None,
            demand: Demand::default(),
            pipelines: None,
            steps: Vec::new(),
            kept: usize::MAX,
        })
    }

    /// The device it draws on.
    pub(super) fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// The composited image (null before the first frame drawn in compute).
    pub fn composited(&self) -> vk::Image {
        self.pools
            .as_ref()
            .map_or(vk::Image::null(), |p| p.composited.raw())
    }

    /// The set of frame slot `slot`.
    pub fn set(&self, slot: usize) -> vk::DescriptorSet {
        self.sets[slot]
    }

    /// The counts buffer of frame slot `slot`.
    pub fn counts_buffer(&self, slot: usize) -> vk::Buffer {
        self.counts[slot].raw()
    }

    /// What frame slot `slot`'s last frame counted (read once it has finished).
    pub fn counts(&self, slot: usize) -> ComputeCounts {
        let bytes = self.counts[slot].mapped();
        let words: CountWords =
            bytemuck::pod_read_unaligned(&bytes[..ComputeCounts::BUFFER_BYTES as usize]);
        words.into()
    }

    /// The tile side `style` asks for on this device, pixels.
    pub fn tile_for(&self, style: &FurStyle) -> u32 {
        style.tile_side()
    }

    /// The tile side the pools were last sized for, pixels.
    pub fn tile(&self) -> u32 {
        self.budget.tile
    }

    /// Sizes the pools for `target` and `style`'s tiles and builds the pipelines for its
    /// sample count, `style`'s fragments a pixel and the strands' `lighting` (none where
    /// the geometry stage colours them), unless they are; points frame slot `slot`'s set at them; the
    /// composite shows the tiles instead of the hair when `tiles_view`. The slot's last
    /// frame has finished; a new size or new pipelines need the device idle (other
    /// slots' frames may still use the old).
    pub fn prepare(
        &mut self,
        target: &RenderTarget,
        layout: &PipelineLayout,
        slot: usize,
        style: &FurStyle,
        (tiles_view, lighting): (bool, Option<StrandLighting>),
    ) -> Result<()> {
        let extent = target.extent;
        let tile = self.tile_for(style);
        let retiled = tile != self.budget.tile;
        self.budget.tile = tile;
        // What this slot's last frame asked for (nothing before its first): pools too
        // small for it grow, a quarter beyond, for the frames that follow.
        let last = self.counts(slot);
        let asked = Demand {
            vertices: u64::from(last.vertices),
            segments: u64::from(last.segments),
            entries: u64::from(last.entries) + u64::from(last.entries_lost),
        };
        let outgrown = self
            .pools
            .as_ref()
            .is_some_and(|p| asked.exceeds(&p.capacity));
        if outgrown {
            let roomy = |n: u64| n + n / 4;
            self.demand = self.demand.max(Demand {
                vertices: roomy(asked.vertices),
                segments: roomy(asked.segments),
                entries: roomy(asked.entries),
            });
        }
        // The steps hold the pools' and pipelines' handles: remade when those are.
        let mut remade = self.steps.is_empty();
        let fits = |p: &Pools| p.extent == extent;
        if outgrown || retiled || !self.pools.as_ref().is_some_and(fits) {
            // Other slots' frames may still read the old pools.
            self.device.wait_idle()?;
            self.pools = Some(Pools::new(
                &self.device,
                (&self.budget, &self.demand),
                extent,
            )?);
            self.written.fill(vk::Image::null());
            remade = true;
        }
        let key = PipelineKey {
            samples: target.samples,
            nearest: style.nearest,
            tile,
            tiles_view,
            lighting,
        };
        if self.pipelines.as_ref().map(|p| p.0) != Some(key) {
            if self.pipelines.is_some() {
                self.device.wait_idle()?;
            }
            self.pipelines = Some((key, self.build(layout, key)?));
            remade = true;
        }
        if self.written[slot] != target.depth.raw() {
            self.write_set(target, slot);
            self.written[slot] = target.depth.raw();
        }
        if !remade {
            return Ok(());
        }
        let pools = self.pools.as_ref().expect("sized above");
        let grid = (pools.columns, pools.rows);
        let pipelines = &self.pipelines.as_ref().expect("built above").1;
        self.steps = Step::ALL
            .into_iter()
            .map(|step| StepPass {
                step,
                pipeline: pipelines
                    .iter()
                    .find(|(s, _)| *s == step)
                    .map_or(vk::Pipeline::null(), |(_, p)| p.raw()),
                grid,
                composited: pools.composited.raw(),
                extent,
                left_out: step.timed().is_some_and(|i| i >= self.kept),
                lighting_groups: lighting_groups(
                    self.device.info.is_cpu(),
                    pools.capacity.vertices,
                ),
            })
            .collect();
        Ok(())
    }

    fn write_set(&self, target: &RenderTarget, slot: usize) {
        let pools = self.pools.as_ref().expect("sized before");
        let info = |b: &Buffer| {
            [vk::DescriptorBufferInfo::default()
                .buffer(b.raw())
                .range(vk::WHOLE_SIZE)]
        };
        let (tiles, layer) = (info(&pools.tiles), info(&pools.layer));
        let (vertices_written, segments_written) =
            (info(&pools.vertices.buffer), info(&pools.segments.buffer));
        let (vertices, segments, entries, sorted) = (
            [pools.vertices.view()],
            [pools.segments.view()],
            [pools.entries.view()],
            [pools.sorted.view()],
        );
        let sampled = |view: vk::ImageView| {
            [vk::DescriptorImageInfo::default()
                .sampler(self.sampler.raw())
                .image_view(view)
                .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)]
        };
        let (depth, under) = (sampled(target.depth.view()), sampled(target.resolve.view()));
        let composited = [vk::DescriptorImageInfo::default()
            .image_view(pools.composited.view())
            .image_layout(vk::ImageLayout::GENERAL)];
        {
            let set = &self.sets[slot];
            let counts = info(&self.counts[slot]);
            let writes = [
                RasterBinding::Counts.write(*set).buffer_info(&counts),
                RasterBinding::Vertices
                    .write(*set)
                    .texel_buffer_view(&vertices),
                RasterBinding::Segments
                    .write(*set)
                    .texel_buffer_view(&segments),
                RasterBinding::TileBins.write(*set).buffer_info(&tiles),
                RasterBinding::TileEntries
                    .write(*set)
                    .texel_buffer_view(&entries),
                RasterBinding::TileOrder
                    .write(*set)
                    .texel_buffer_view(&sorted),
                RasterBinding::VerticesWritten
                    .write(*set)
                    .buffer_info(&vertices_written),
                RasterBinding::SegmentsWritten
                    .write(*set)
                    .buffer_info(&segments_written),
                RasterBinding::HairLayer.write(*set).buffer_info(&layer),
                RasterBinding::BodyDepth.write(*set).image_info(&depth),
                RasterBinding::TargetColor.write(*set).image_info(&under),
                RasterBinding::Composited
                    .write(*set)
                    .image_info(&composited),
            ];
            // SAFETY: the slot's last frame has finished (the caller's contract); every
            // resource written is owned by this rasteriser or the target, which outlive
            // the set's use.
            unsafe { self.device.raw.update_descriptor_sets(&writes, &[]) };
        }
    }

    fn build(&self, layout: &PipelineLayout, key: PipelineKey) -> Result<Vec<(Step, Pipeline)>> {
        let mut defines = render_defines();
        defines.extend([
            ("TILE", key.tile.to_string()),
            ("NEAREST", key.nearest.to_string()),
            ("DEPTH_SAMPLES", key.samples.to_string()),
            ("TILES_VIEW", u32::from(key.tiles_view).to_string()),
        ]);
        let groups = scatter_groups(&self.device.info);
        let kernel = |shader: &str, scatter: bool| {
            let mut d = defines.clone();
            d.push(("SCATTER", u32::from(scatter).to_string()));
            d.push(("SERIAL_SCATTER", u32::from(groups.is_some()).to_string()));
            d.push(("SCATTER_GROUPS", groups.unwrap_or(1).to_string()));
            d.push((
                "TILE_GROUP",
                format!("{}u", tile_group(&self.device.info, key.tile)),
            ));
            Pipeline::compute(&self.device, shader, &d, layout, &Specialization::new(&[]))
        };
        let mut kernels = Vec::new();
        if let Some(lighting) = key.lighting {
            let mut d = defines.clone();
            d.extend(lighting.defines());
            let shade = Pipeline::compute(
                &self.device,
                "strand_shade.comp",
                &d,
                layout,
                &Specialization::new(&[]),
            )?;
            kernels.push((Step::Shade, shade));
        }
        kernels.extend([
            (Step::Tiles, kernel("strand_tiles.comp", false)?),
            (Step::Count, kernel("strand_bin.comp", false)?),
            (Step::Scan, kernel("strand_scan.comp", false)?),
            (Step::Scatter, kernel("strand_bin.comp", true)?),
            (Step::Sort, kernel("strand_sort.comp", false)?),
            (Step::Fine, kernel("strand_fine.comp", false)?),
            (Step::Composite, kernel("strand_composite.comp", false)?),
        ]);
        Ok(kernels)
    }

    /// The steps remade at the next frame (which steps are left out changed).
    pub(super) fn remake_steps(&mut self) {
        self.steps.clear();
    }

    /// The steps of a frame after the fur pass, in order (the counts are reset before
    /// it, by `StrandCountsReset`).
    pub(in super::super) fn draw_passes(&self) -> impl Iterator<Item = &StepPass> {
        self.steps.iter()
    }
}
