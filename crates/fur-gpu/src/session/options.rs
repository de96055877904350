//! The check that refuses work too large before it starts.

use ash::vk;

use crate::error::{Error, Result};
use fur_core::render::strand_raster::pools::{Demand, PoolBudget, PoolSizes};
use fur_core::render::{FrameSettings, Raster};
use fur_core::scene::{GroomParams, Mesh};

/// Strand vertices (master hairs × their vertices) a scene may have: 8 M take 512 MiB
/// of strand textures.
pub const MAX_STRAND_VERTICES: u64 = 8_000_000;
/// Hair segments a frame may draw at most (a frame of many seconds on a CPU driver).
pub const MAX_SEGMENTS_PER_FRAME: u64 = 20_000_000;
/// Render-target memory an image may take (colour, depth and resolve), and, apart,
/// the compute rasteriser's pools for it.
pub const MAX_TARGET_BYTES: u64 = 4 << 30;

/// Refuses, before any work, a scene whose size would run for minutes or exhaust
/// memory, naming the limit and the value: the strand vertices, the hairs the density
/// asks for (an upper bound: every triangle in view at full density), the render
/// target's memory and, with `--raster compute`, its pools' (sized per pixel before any
/// frame asks for more).
pub fn check_work(
    mesh: &Mesh,
    groom: &GroomParams,
    settings: &FrameSettings,
    extent: vk::Extent2D,
) -> Result<()> {
    let vertices = u64::from(groom.vertices_per_strand());
    let strand_vertices = mesh.vertex_count() as u64 * vertices;
    if strand_vertices > MAX_STRAND_VERTICES {
        return Err(Error::parameter(format!(
            "the model's {} vertices each grow a master hair of {vertices} vertices: {strand_vertices} \
             strand vertices, over the limit of {MAX_STRAND_VERTICES}; use fewer --segments or a \
             model with fewer vertices",
            mesh.vertex_count()
        )));
    }
    // Points a triangle can generate at the largest tessellation level (64).
    let most_per_triangle = 3.0 * 64.0 * 64.0 / 4.0 + 3.0 * 64.0;
    let density = f64::from(settings.style.density);
    let hairs: f64 = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize].as_dvec3());
            let area = 0.5 * (b - a).cross(c - a).length();
            let edges = (b - a).length() + (c - b).length() + (a - c).length();
            (area * density + edges * density.sqrt()).min(most_per_triangle)
        })
        .sum();
    let segments = hairs * f64::from(groom.segments);
    if segments > MAX_SEGMENTS_PER_FRAME as f64 {
        return Err(Error::parameter(format!(
            "the density asks for up to {:.3e} hairs of {} segments a frame ({:.3e} segments), over \
             the limit of {MAX_SEGMENTS_PER_FRAME:.0e}; lower --density-scale or --segments",
            hairs, groom.segments, segments
        )));
    }
    let samples = u64::from(settings.style.samples);
    let bytes = u64::from(extent.width) * u64::from(extent.height) * (8 * samples + 8);
    if bytes > MAX_TARGET_BYTES {
        return Err(Error::parameter(format!(
            "a {}×{} image at {samples} samples per pixel needs {:.1} GiB of render target, over \
             the limit of {} GiB",
            extent.width,
            extent.height,
            bytes as f64 / f64::from(1u32 << 30),
            MAX_TARGET_BYTES >> 30
        )));
    }
    if settings.style.raster == Raster::Compute {
        let tile = settings.style.tile_side();
        let pools = PoolSizes::of(
            &PoolBudget {
                tile,
                ..PoolBudget::default()
            },
            extent.width,
            extent.height,
            &Demand::default(),
        )
        .total();
        if pools > MAX_TARGET_BYTES {
            return Err(Error::parameter(format!(
                "the compute rasteriser's pools for a {}×{} image need {:.1} GiB, over the \
                 limit of {} GiB; draw it smaller or with --raster hardware",
                extent.width,
                extent.height,
                pools as f64 / f64::from(1u32 << 30),
                MAX_TARGET_BYTES >> 30
            )));
        }
    }
    Ok(())
}
