//! Steady-state frame time: the default blob and the original demo's sphere scene,
//! simulated (shake and wind) and drawn every frame, with today's default drawing and
//! with the reference-quality drawing (4× MSAA ribbons lit per fragment, every strand
//! vertex); then each pass of a default frame alone.

use std::fmt::Write as _;
use std::time::Instant;

use super::metrics::{median, Frames};
use super::{Bench, BenchScene};
use fur_core::render::FurStyle;
use fur_core::scene_file::SceneOptions;
use fur_gpu::error::Result;
use fur_gpu::session::{FurSession, SessionSetup};

/// The original OpenGL demo's frame on its own scene, measured on this project's
/// 2-core machine kind with Mesa's llvmpipe (1,345–1,641 ms; ~1,400 ms typical).
pub const ORIGINAL_FRAME_MS: f64 = 1400.0;

pub(super) fn tasks(scenes: usize) -> u64 {
    3 * scenes as u64
}

/// Medians of one configuration's frames: (wall ms, GPU ms).
pub(super) struct FrameTimes {
    pub(super) wall: f64,
    pub(super) gpu: f64,
}

impl Bench<'_> {
    /// A session of `scene` (its simulation and motion included) drawn with `draw`.
    pub(super) fn session(&self, scene: &BenchScene, draw: &FurStyle) -> Result<FurSession> {
        let scene = &scene.scene;
        let mesh = scene.model.prepare(scene.options.texture.as_ref())?.0;
        let options = SceneOptions {
            draw: draw.clone(),
            ..scene.options.clone()
        };
        let (groom, settings) = options.resolve(&mesh)?;
        let motion = scene.motion.motion(mesh.bounds().1);
        FurSession::new(
            self.device,
            SessionSetup {
                mesh,
                rig: None,
                groom: &groom,
                sim: scene.sim.clone(),
                motion,
                settings,
                extent: self.frame_extent(),
                frames_in_flight: 1,
            },
        )
    }

    /// At least 20 measured frames (5 in the quick suite) after warm-up.
    fn frame_counts(&self) -> Frames {
        let (warm, measured) = if self.quick { (1, 5) } else { (5, 20) };
        Frames { warm, measured }
    }

    /// Simulated and drawn frames, each its own submission.
    pub(super) fn time_frames(&self, session: &mut FurSession) -> Result<FrameTimes> {
        let Frames { warm, measured } = self.frame_counts();
        let (mut wall, mut gpu) = (Vec::new(), Vec::new());
        for frame in 0..warm + measured {
            fur_core::interrupt::check()?;
            let start = Instant::now();
            let (_, timings) = session.step_and_render()?;
            if frame >= warm {
                wall.push(start.elapsed().as_secs_f64() * 1e3);
                gpu.push(timings.render.frame_ms);
            }
        }
        Ok(FrameTimes {
            wall: median(&wall),
            gpu: median(&gpu),
        })
    }

    /// Still frames (no simulation) with the passes `session.settings` asks for.
    fn time_still(&self, session: &mut FurSession) -> Result<f64> {
        let Frames { warm, measured } = self.frame_counts();
        let mut wall = Vec::new();
        for frame in 0..warm + measured {
            fur_core::interrupt::check()?;
            let start = Instant::now();
            session.render()?;
            if frame >= warm {
                wall.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        Ok(median(&wall))
    }

    pub(super) fn frame(&mut self) -> Result<()> {
        let extent = self.frame_extent();
        let Frames { warm, measured } = self.frame_counts();
        let _ = writeln!(
            self.md,
            "## Frame time ({}×{})\n\nSimulated (shake, wind, gravity) and drawn every frame; median \
             of {measured} frames after {warm} warm-up frames; wall clock from submission to fence \
             (simulation, both passes, resolve, copy to the host), and GPU time from timestamps. \
             *Default*: this release's drawing settings; *reference quality*: 4× MSAA ribbons lit \
             per fragment, every strand vertex; *fixed-function strands*: the default's strands drawn \
             by the fixed-function rasteriser as 4× MSAA ribbons (`--raster hardware`, the default \
             before strands were drawn in compute). The original \
             OpenGL demo took ~{ORIGINAL_FRAME_MS:.0} ms (1,345–1,641) a frame on its sphere scene \
             on this machine kind at 1280×720{}.\n\n\
             | scene | drawing | hairs drawn | segments | wall ms | GPU ms | × the original's frame rate |\n\
             | --- | --- | --- | --- | --- | --- | --- |",
            extent.width,
            extent.height,
            if self.quick {
                " (the quick suite's small frames are not comparable)"
            } else {
                ""
            }
        );
        for scene in self.scenes.clone() {
            let name = &scene.name;
            for (label, draw) in [
                ("default", scene.scene.options.draw.clone()),
                (
                    "reference quality",
                    scene.scene.options.draw.reference_quality(),
                ),
                (
                    "fixed-function strands",
                    FurStyle {
                        raster: fur_core::render::Raster::Hardware,
                        ..scene.scene.options.draw.clone()
                    },
                ),
            ] {
                let mut session = self.session(&scene, &draw)?;
                let times = self.time_frames(&mut session)?;
                session.settings.count_hairs = true;
                let counts = session.render()?.1.counts;
                let hairs = counts.map_or(f64::NAN, |c| c.hairs as f64);
                let segments = counts.map_or(f64::NAN, |c| c.segments as f64);
                let case = format!("{name}, {label}");
                let speedup = ORIGINAL_FRAME_MS / times.wall;
                self.row("frame", case.clone(), "wall_ms", times.wall, "ms");
                self.row("frame", case.clone(), "gpu_ms", times.gpu, "ms");
                self.row("frame", case.clone(), "hairs_drawn", hairs, "count");
                self.row("frame", case.clone(), "segments_drawn", segments, "count");
                self.row("frame", case.clone(), "speedup_vs_original", speedup, "x");
                let _ = writeln!(
                    self.md,
                    "| {name} | {label} | {hairs} | {segments} | {:.1} | {:.1} | {speedup:.1}× |",
                    times.wall, times.gpu
                );
                (self.progress)(&case);
            }
        }
        let _ = writeln!(
            self.md,
            "\nEach pass of a default frame alone (still frames, each drawing that pass only, \
             so each holds the work of the last column too; the simulation alone is one \
             dispatch per submission):\n\n\
             | scene | simulation | mesh pass | fur pass | neither (clear, resolve, copy; with \
             strands in compute, their passes over the screen's tiles) |\n\
             | --- | --- | --- | --- | --- |"
        );
        for scene in self.scenes.clone() {
            let name = &scene.name;
            let mut session = self.session(&scene, &scene.scene.options.draw)?;
            let mut sim_ms = Vec::new();
            for frame in 0..warm + measured {
                fur_core::interrupt::check()?;
                let start = Instant::now();
                let (user, motion) = (session.user, session.motion);
                session
                    .sim
                    .run_frames(&mut session.textures, 1, |t| user * motion.head(t))?;
                if frame >= warm {
                    sim_ms.push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
            let sim = median(&sim_ms);
            let mut passes = Vec::new();
            for (mesh, fur) in [(true, false), (false, true), (false, false)] {
                session.settings.draw_mesh = mesh;
                session.settings.draw_fur = fur;
                passes.push(self.time_still(&mut session)?);
            }
            for (pass, ms) in [
                ("simulation", sim),
                ("mesh pass", passes[0]),
                ("fur pass", passes[1]),
                ("clear, resolve, copy", passes[2]),
            ] {
                self.row(
                    "frame_passes",
                    format!("{name}, {pass}"),
                    "wall_ms",
                    ms,
                    "ms",
                );
            }
            let _ = writeln!(
                self.md,
                "| {name} | {sim:.2} | {:.1} | {:.1} | {:.1} |",
                passes[0], passes[1], passes[2]
            );
            (self.progress)(&format!("{name} passes alone"));
        }
        self.md.push('\n');
        Ok(())
    }
}
