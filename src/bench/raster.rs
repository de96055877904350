//! The two strand rasterisers side by side: the fixed-function rasteriser (the
//! geometry stage's ribbons or lines into MSAA) and the compute passes (`--raster
//! compute`: strands binned to screen tiles, exact coverage, the nearest fragments of
//! each pixel blended front to back). For each scene: the simulated frame's wall-clock
//! and GPU time and the fur's GPU time; each still frame's ꟻLIP and RMSE against the
//! supersampled reference, and between the two; the compute passes step by step
//! (timestamps, and on a CPU driver each step left out in turn); and what their pools
//! counted.

use std::fmt::Write as _;
use std::time::Instant;

use super::metrics::{flip, median, rmse, Frames};
use super::quality::Shot;
use super::{Bench, BenchScene};
use fur_core::render::FurStyle;
use fur_core::render::{Raster, MAX_NEAREST};
use fur_gpu::error::Result;
use fur_gpu::render::STEP_NAMES;

/// The fragments a pixel keeps in order that the compute rows also measure, beside the
/// scene's own.
const NEAREST_SWEEP: [u32; 2] = [4, MAX_NEAREST];

/// The tile sides the compute rows also measure, beside the device's.
const TILE_SWEEP: [u32; 3] = [4, 8, 16];

/// Progress ticks per scene: the reference, then each row, then the steps left out
/// (at most).
pub(super) fn tasks(scenes: usize) -> u64 {
    (4 + NEAREST_SWEEP.len() as u64 + TILE_SWEEP.len() as u64) * scenes as u64
}

/// One rasteriser's measurements on one scene.
struct Measured {
    name: String,
    hairs: u64,
    segments: u64,
    wall: f64,
    gpu: f64,
    fur: f64,
    flip: f64,
    rmse: f64,
    /// The compute passes: (step, median GPU ms), the geometry stage's first.
    steps: Vec<(&'static str, f64)>,
    counts: Option<fur_gpu::render::ComputeCounts>,
}

impl Bench<'_> {
    pub(super) fn raster(&mut self) -> Result<()> {
        let extent = self.frame_extent();
        let tile = fur_core::render::DEFAULT_TILE;
        let factor = if self.quick { 2 } else { 4 };
        // The quick suite's frames are few (CI runs it on lavapipe): its test checks their
        // errors, not their times.
        let (warm, measured) = if self.quick { (1, 2) } else { (5, 20) };
        let _ = writeln!(
            self.md,
            "## The two strand rasterisers ({}×{})\n\n*Hardware*: the geometry stage's \
             strands drawn by the fixed-function rasteriser (`--raster hardware`); *compute*: the \
             same strands drawn by compute passes (the default), each pixel keeping the \
             scene's number of fragments in depth order (`nearest`), then {} and {}, and \
             binned to tiles of the device's side ({tile}×{tile} px), then the other sides \
             of {:?}. All with the scene's other settings. Simulated frames as in the frame-time table (median of {measured} after \
             {warm} warm-up): wall clock, GPU time of the whole frame and of the fur (the \
             geometry stage to the last compute step). ꟻLIP and RMSE: a still frame against \
             the same frame at {factor}×{factor} the pixels with 4× MSAA ribbons lit per \
             fragment ({} samples per pixel); *between*: the compute frame against the \
             hardware one.\n\n\
             | scene | rasteriser | hairs drawn | segments | wall ms | GPU ms | fur GPU ms | \
             ꟻLIP | RMSE |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
            extent.width,
            extent.height,
            NEAREST_SWEEP[0],
            NEAREST_SWEEP[1],
            TILE_SWEEP,
            factor * factor * 4
        );
        let mut all = Vec::new();
        let mut alone = Vec::new();
        for scene in self.scenes.clone() {
            let shot = Shot::new(self.device, &scene.scene, extent)?;
            let reference = shot.reference(factor)?;
            (self.progress)(&format!("{} reference", scene.name));
            let mut images = Vec::new();
            let mut rows = Vec::new();
            let own = scene.scene.options.draw.nearest;
            let own_tile = scene.scene.options.draw.tile;
            let mut cases = vec![
                ("hardware".to_string(), Raster::Hardware, own, own_tile),
                ("compute".to_string(), Raster::Compute, own, own_tile),
            ];
            for k in NEAREST_SWEEP.into_iter().filter(|k| *k != own) {
                cases.push((
                    format!("compute, {k} in order"),
                    Raster::Compute,
                    k,
                    own_tile,
                ));
            }
            let scene_tile = shot.style(&scene.scene.options.draw).tile_side();
            for t in TILE_SWEEP.into_iter().filter(|t| *t != scene_tile) {
                cases.push((format!("compute, {t}×{t} tiles"), Raster::Compute, own, t));
            }
            for (name, raster, nearest, tile) in cases {
                let draw = FurStyle {
                    raster,
                    nearest,
                    tile,
                    ..scene.scene.options.draw.clone()
                };
                // Only its image is used: one frame.
                let still = shot.draw(&shot.style(&draw), Frames::STILL)?;
                let mut m = self.simulated(&scene, &draw, Frames { warm, measured }, None)?;
                m.name = name.clone();
                m.flip = flip(&reference, &still.image);
                m.rmse = rmse(&reference, &still.image);
                images.push(still.image);
                rows.push(m);
                (self.progress)(&format!("{}, {name}", scene.name));
            }
            let between = flip(&images[0], &images[1]);
            let name = &scene.name;
            for m in &rows {
                let case = format!("{name}, {}", m.name);
                for (metric, value, unit) in [
                    ("hairs_drawn", m.hairs as f64, "count"),
                    ("segments_drawn", m.segments as f64, "count"),
                    ("wall_ms", m.wall, "ms"),
                    ("gpu_ms", m.gpu, "ms"),
                    ("fur_gpu_ms", m.fur, "ms"),
                    ("flip", m.flip, "0..1"),
                    ("rmse", m.rmse, "0..1"),
                ] {
                    self.row("raster", case.clone(), metric, value, unit);
                }
                let _ = writeln!(
                    self.md,
                    "| {name} | {} | {} | {} | {:.1} | {:.2} | {:.2} | {:.4} | {:.4} |",
                    m.name, m.hairs, m.segments, m.wall, m.gpu, m.fur, m.flip, m.rmse
                );
            }
            self.row(
                "raster",
                format!("{name}, between"),
                "flip",
                between,
                "0..1",
            );
            let _ = writeln!(self.md, "| {name} | between | | | | | | {between:.4} | |");
            let compute = rows.swap_remove(1);
            let whole = compute.wall;
            all.push((name.clone(), scene_tile, compute));
            // A CPU driver's timestamps misattribute (lavapipe bins): each step is
            // measured by leaving it out too, the frame with every step being the
            // compute row's.
            if self.device.info().is_cpu() {
                let draw = FurStyle {
                    raster: Raster::Compute,
                    ..scene.scene.options.draw.clone()
                };
                let mut walls = (0..STEP_NAMES.len())
                    .map(|kept| {
                        self.simulated(&scene, &draw, Frames { warm, measured }, Some(kept))
                            .map(|m| m.wall)
                    })
                    .collect::<Result<Vec<f64>>>()?;
                walls.push(whole);
                (self.progress)(&format!("{name}, compute steps left out"));
                alone.push((name.clone(), walls));
            }
        }
        self.raster_steps(&all);
        self.raster_steps_left_out(&alone);
        Ok(())
    }

    /// On a CPU driver, the compute steps measured by leaving them out: `alone` holds
    /// each scene's name and its frame's wall-clock median with the first k steps kept,
    /// for k from none to all.
    fn raster_steps_left_out(&mut self, alone: &[(String, Vec<f64>)]) {
        if alone.is_empty() {
            return;
        }
        let short = |step: &str| step.trim_start_matches("strand ").to_string();
        let header: Vec<String> = std::iter::once("the rest".to_string())
            .chain(STEP_NAMES.iter().map(|s| short(s)))
            .chain(std::iter::once("frame".to_string()))
            .collect();
        let _ = writeln!(
            self.md,
            "The compute frame step by step on this CPU driver, whose timestamps between \
             passes misattribute: simulated frames (wall-clock ms, medians as above) with \
             the steps from each one on left out (recorded without their work), each \
             step's cost the frame with it less the frame without it (so noise can make \
             one negative); *the rest*: the frame with every step left out (the \
             simulation, the mesh pass and the geometry stage writing the strands).\n\n\
             | scene | {} |\n| --- |{}",
            header.join(" | "),
            " --- |".repeat(header.len())
        );
        for (name, walls) in alone {
            let costs: Vec<f64> = std::iter::once(walls[0])
                .chain(walls.windows(2).map(|w| w[1] - w[0]))
                .chain(walls.last().copied())
                .collect();
            for (step, ms) in header.iter().zip(&costs) {
                self.row(
                    "raster_steps_left_out",
                    format!("{name}, {step}"),
                    "wall_ms",
                    *ms,
                    "ms",
                );
            }
            let cells: Vec<String> = costs.iter().map(|ms| format!("{ms:.1}")).collect();
            let _ = writeln!(self.md, "| {name} | {} |", cells.join(" | "));
        }
        self.md.push('\n');
    }

    /// The compute passes' tables: each step's GPU time, then what the pools counted;
    /// `all` holds each scene's name, tile side and compute measurements.
    fn raster_steps(&mut self, all: &[(String, u32, Measured)]) {
        let short = |step: &str| step.trim_start_matches("strand ").to_string();
        let pixels = {
            let e = self.frame_extent();
            e.width * e.height
        };
        let header: Vec<String> = std::iter::once("geometry".to_string())
            .chain(STEP_NAMES.iter().map(|s| short(s)))
            .collect();
        let _ = writeln!(
            self.md,
            "\nThe compute frame step by step: GPU ms of each pass from the previous one's \
             end (median; timestamps, which a binning rasteriser such as lavapipe's \
             misattributes), the geometry stage's writing of the strands first.\n\n\
             | scene | {} |\n| --- |{}",
            header.join(" | "),
            " --- |".repeat(header.len())
        );
        for (name, _, m) in all {
            let cells: Vec<String> = m.steps.iter().map(|(_, ms)| format!("{ms:.2}")).collect();
            for (step, ms) in &m.steps {
                self.row(
                    "raster_steps",
                    format!("{name}, {}", short(step)),
                    "gpu_ms",
                    *ms,
                    "ms",
                );
            }
            let _ = writeln!(self.md, "| {name} | {} |", cells.join(" | "));
        }
        let _ = writeln!(
            self.md,
            "\nWhat the compute passes counted on the last frame: strand vertices and \
             segments written, (segment, tile) entries binned and their mean over the \
             scene's tiles (side in pixels), the fragments the pixels took (every segment's \
             share of a pixel in front of the body) and their mean over the image's {pixels} \
             pixels, fragments blended past a pixel's nearest (its tail), pixels \
             that stopped walking their tile's list once opaque, and what \
             found a pool full (hairs not drawn, entries missing).\n\n\
             | scene | vertices | segments | entries | tile | per tile | fragments | per pixel | \
             tail fragments | pixels stopped | hairs lost | entries lost |\n\
             | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
        );
        for (name, tile, m) in all {
            let tile = *tile;
            let Some(c) = m.counts else { continue };
            let extent = self.frame_extent();
            let tiles = extent.width.div_ceil(tile) * extent.height.div_ceil(tile);
            let per_tile = f64::from(c.entries) / f64::from(tiles.max(1));
            let per_pixel = c.fragments as f64 / f64::from(pixels.max(1));
            for (metric, value) in [
                ("vertices", u64::from(c.vertices)),
                ("segments", u64::from(c.segments)),
                ("entries", u64::from(c.entries)),
                ("fragments", c.fragments),
                ("tail_fragments", c.tail_fragments),
                ("pixels_stopped", u64::from(c.pixels_stopped)),
                ("hairs_lost", u64::from(c.hairs_lost)),
                ("entries_lost", u64::from(c.entries_lost)),
            ] {
                self.row("raster_counts", name.clone(), metric, value as f64, "count");
            }
            let _ = writeln!(
                self.md,
                "| {name} | {} | {} | {} | {tile}×{tile} | {per_tile:.0} | {} | {per_pixel:.1} | {} \
                 | {} | {} | {} |",
                c.vertices,
                c.segments,
                c.entries,
                c.fragments,
                c.tail_fragments,
                c.pixels_stopped,
                c.hairs_lost,
                c.entries_lost
            );
        }
        self.md.push('\n');
    }

    /// Simulated frames of `scene` drawn with `draw`: medians, counts and steps; with
    /// `kept`, the compute steps from that one on left out.
    fn simulated(
        &self,
        scene: &BenchScene,
        draw: &FurStyle,
        Frames { warm, measured }: Frames,
        kept: Option<usize>,
    ) -> Result<Measured> {
        let mut session = self.session(scene, draw)?;
        session.renderer.leave_out_raster_steps(kept);
        let (mut wall, mut gpu, mut fur) = (Vec::new(), Vec::new(), Vec::new());
        let mut steps: Vec<Vec<f64>> = Vec::new();
        let mut names = Vec::new();
        for frame in 0..warm + measured {
            fur_core::interrupt::check()?;
            let start = Instant::now();
            let (_, timings) = session.step_and_render()?;
            if frame < warm {
                continue;
            }
            wall.push(start.elapsed().as_secs_f64() * 1e3);
            gpu.push(timings.render.frame_ms);
            fur.push(timings.render.fur_ms);
            let report = &timings.render.raster_steps_ms;
            steps.resize(report.len(), Vec::new());
            names = report.iter().map(|(name, _)| *name).collect();
            for (i, (_, ms)) in report.iter().enumerate() {
                steps[i].push(*ms);
            }
        }
        session.settings.count_hairs = true;
        let report = session.render()?.1;
        let counts = report.counts.unwrap_or_default();
        Ok(Measured {
            name: String::new(),
            hairs: counts.hairs,
            segments: counts.segments,
            wall: median(&wall),
            gpu: median(&gpu),
            fur: median(&fur),
            flip: f64::NAN,
            rmse: f64::NAN,
            steps: names
                .into_iter()
                .zip(steps.iter().map(|v| median(v)))
                .collect(),
            counts: report.raster,
        })
    }
}
