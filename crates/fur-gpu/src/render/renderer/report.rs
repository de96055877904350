//! What a rendered frame reports: its timestamps, pipeline statistics and counts of
//! the hairs drawn and triangles culled, read from its slot once it has finished.

use super::super::slot::{
    TIMESTAMPS, TS_FRAME, TS_FUR, TS_HARDWARE, TS_MESH, TS_START, TS_STRANDS,
};
use super::raster_steps::STEP_NAMES;
use super::*;
use crate::gpu::FurStatistics;

/// What the fur pass drew (counted by its geometry stage) and culled (counted by its
/// tessellation control stage).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HairCounts {
    pub hairs: u64,
    pub segments: u64,
    /// Triangles given no hairs: facing away past the cull margin, or off screen.
    pub triangles_culled: u64,
}

/// What a rendered frame reports.
#[derive(Clone, Debug)]
pub struct FrameReport {
    pub statistics: Option<FurStatistics>,
    /// Hairs and segments drawn, when the frame counted them and the device can.
    pub counts: Option<HairCounts>,
    /// GPU milliseconds of the mesh pass and the fur pass (timestamps; misattributed
    /// on binning rasterisers, see the module documentation).
    pub mesh_ms: f64,
    pub fur_ms: f64,
    /// GPU milliseconds of the whole frame, simulation included.
    pub frame_ms: f64,
    /// What the compute rasteriser counted (`--raster compute`): pools overflowed,
    /// the fragments the pixels took and those blended past each pixel's nearest.
    pub raster: Option<super::compute_raster::ComputeCounts>,
    /// When the strands are drawn in compute: GPU milliseconds of the geometry stage
    /// that writes them (`strand geometry`), then of each compute step
    /// ([`STEP_NAMES`]), each from the previous one's end. Empty otherwise, or without
    /// timestamps. Misattributed on binning rasterisers, as `fur_ms`.
    pub raster_steps_ms: Vec<(&'static str, f64)>,
}

impl Renderer {
    /// Reads the queries of slot `slot`'s last submitted frame (waits for them).
    pub fn report(&self, slot: usize, settings: &FrameSettings) -> Result<FrameReport> {
        let frame = &self.slots[slot];
        // What the slot's last frame drew, whatever `settings` ask of the next.
        let compute = frame.compute;
        let mut raster_steps_ms = Vec::new();
        let (mesh_ms, fur_ms, frame_ms) = match &frame.timestamps {
            Some(q) => {
                // A frame drawn by the fixed-function rasteriser wrote only the first.
                let t = q.timestamps_ms(if compute { TIMESTAMPS } else { TS_HARDWARE })?;
                let [frame, start, mesh, fur] =
                    [TS_FRAME, TS_START, TS_MESH, TS_FUR].map(|i| t[i as usize]);
                if compute {
                    let ends = &t[TS_STRANDS as usize..];
                    raster_steps_ms.push(("strand geometry", ends[0] - mesh));
                    for (name, pair) in STEP_NAMES.iter().zip(ends.windows(2)) {
                        raster_steps_ms.push((*name, pair[1] - pair[0]));
                    }
                }
                (mesh - start, fur - mesh, fur - frame)
            }
            None => (f64::NAN, f64::NAN, f64::NAN),
        };
        let statistics = match (&frame.statistics, settings.draw_fur) {
            (Some(q), true) => Some(q.fur_statistics_result()?),
            _ => None,
        };
        // The master hairs' views draw no interpolated hairs and count nothing; the
        // density view counts the triangles it culls (and draws no hairs).
        let counted = settings.count_hairs && !settings.show.draws_masters();
        let counts = (counted && self.device.info.vertex_pipeline_stores).then(|| {
            let words: &[u32] = bytemuck::cast_slice(&frame.counters.mapped()[..12]);
            HairCounts {
                hairs: u64::from(words[0]),
                segments: u64::from(words[1]),
                triangles_culled: u64::from(words[2]),
            }
        });
        let raster = compute.then(|| self.compute_raster.counts(slot));
        Ok(FrameReport {
            statistics,
            counts,
            mesh_ms,
            fur_ms,
            frame_ms,
            raster,
            raster_steps_ms,
        })
    }
}
