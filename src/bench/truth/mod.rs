//! Section `truth`: fur's drawings against a path-traced reference of the same frame.
//!
//! For each scene, the settled frame (as the render-quality section takes it) is drawn
//! at the scene's own settings with every hair captured, exported (`fur export-frame`'s
//! USD) and path-traced by `tools/reference` with Mitsuba 3's hair model, twice with
//! different seeds: the two references' distance is the reference's own noise. Then
//! every rung of the quality ladder and every look on and off (the other strand
//! rasteriser among them) is drawn and measured
//! against the first reference (ꟻLIP on sRGB, RMSE in linear light), with its frame
//! time. References are cached under the output folder by a hash of the export, the
//! sample count and the renderer script, so reruns path-trace nothing.
//!
//! What the distance is made of: the same frame against a reference limited to
//! single scattering (paths of one bounce off the hair: no multiple scattering), and
//! fur's own supersampled drawing (coverage exact, the model unchanged) against the
//! full reference.
//!
//! Beside the references it writes, per scene, the reference and the drawings of both
//! lighting models as PNGs (`truth/{scene}-reference.png`, `-kajiya-kay.png`,
//! `-marschner.png`) for a side-by-side.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use ash::vk;

use super::plot::{Plot, Series, PALETTE};
use super::quality::{Look, Shot};
use super::Bench;
use crate::export::compare::{errors, rmse_linear, to_srgb8};
use crate::export::reference::{Reference, Variant};
use crate::export::{write_usda, FrameExport};
use fur_core::render::budget::MOST_RUNGS;
use fur_core::render::direction_spread::direction_spread;
use fur_core::render::marschner::Lobes;
use fur_core::render::{flip, RgbaImage};
use fur_core::scene::ModelSpec;
use fur_core::scene_file::Scene;
use fur_gpu::error::Result;
use fur_gpu::render::CapturedHairs;

mod cache;
mod colours;
mod groom;
mod lights;
mod looks;
mod noise;
mod scales;
mod terms;

use cache::{cached_trace, cached_traces, Sampling};
use looks::{looks, LOOKS};
use noise::{delta_cell, differences, noise_sentence, resolved, seed_spread, unresolved_pairs};

/// The variants the section draws the first scene in: three fur presets and the texture
/// (the quick suite's two: the lightest preset and the texture, each path of the code).
const COLOURS: u64 = 4;
const COLOURS_QUICK: u64 = 2;

/// Frames of the critter's walk before its shot (in the quick suite: a few).
const WALK_FRAMES: u32 = 45;
const WALK_FRAMES_QUICK: u32 = 4;
/// Samples a pixel of the full run's references.
const FULL_SPP: u32 = 1024;

/// The progress ticks of the section: per scene (the default scenes and the walking
/// critter, or one scene file's) its references, rungs, looks, attribution and terms.
pub(super) fn tasks(quick: bool, scenes: usize) -> u64 {
    let terms = Lobes::each_dropped().len() as u64;
    let colours = if quick { COLOURS_QUICK } else { COLOURS };
    scenes as u64 * (3 + MOST_RUNGS as u64 + LOOKS as u64 + 1 + terms)
        + colours * (2 + terms + lights::Light::BOTH.len() as u64)
}

/// Where a run's references come from and go.
struct Truth<'a> {
    reference: &'a Reference,
    dir: &'a Path,
    sampling: Sampling,
}

/// One drawing measured against the truth.
struct Measured {
    name: String,
    frame_ms: f64,
    flip: f64,
    rmse: f64,
    /// ꟻLIP against the second reference (another seed).
    flip_second: f64,
}

impl Bench<'_> {
    pub(super) fn truth(&mut self) -> Result<()> {
        let _ = writeln!(self.md, "## Against the path-traced truth\n");
        let Some((out_dir, root)) = self.work.clone() else {
            let _ = writeln!(self.md, "Not run: no output folder.\n");
            return Ok(());
        };
        let reference = match Reference::find(&root) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("truth: skipped: {e}");
                let _ = writeln!(self.md, "Not run: {e}.\n");
                return Ok(());
            }
        };
        // The quick run's few samples take the scalar variant: the LLVM one spends
        // longer compiling than they take.
        let (extent, sampling, walk) = if self.quick {
            (
                vk::Extent2D {
                    width: 96,
                    height: 54,
                },
                Sampling {
                    spp: 16,
                    variant: Variant::Scalar,
                },
                WALK_FRAMES_QUICK,
            )
        } else {
            (
                vk::Extent2D {
                    width: 320,
                    height: 180,
                },
                Sampling {
                    spp: FULL_SPP,
                    variant: reference.fastest_variant(),
                },
                WALK_FRAMES,
            )
        };
        let spp = sampling.spp;
        let variant = sampling.variant.name();
        let dir = out_dir.join("truth");
        std::fs::create_dir_all(&dir)
            .map_err(|e| fur_gpu::error::Error::io("create the folder", &dir, e))?;
        let _ = writeln!(
            self.md,
            "Each scene's settled frame at {}×{}, drawn by fur and path-traced by \
             `tools/reference` (Mitsuba 3, Chiang et al.'s hair model, the same camera, \
             lights and hairs; {spp} samples a pixel, up to 64 bounces, Mitsuba's \
             `{variant}`). *Noise*: the \
             reference against a second one with another seed, its own uncertainty. ꟻLIP \
             on sRGB, RMSE in linear light; frame time as in the ladder.\n",
            extent.width, extent.height
        );
        let truth = Truth {
            reference: &reference,
            dir: &dir,
            sampling,
        };
        let mut series = Vec::new();
        // One line of the chart per scene, each its own colour.
        let add = |series: &mut Vec<Series>, name: &str, points| {
            series.push(Series {
                name: name.to_string(),
                points,
                color: PALETTE[series.len() % PALETTE.len()],
                line: true,
            })
        };
        for bench_scene in self.scenes.clone() {
            let shot = Shot::new(self.device, &bench_scene.scene, extent)?;
            let points = self.truth_scene(&bench_scene.name, &shot, &truth)?;
            add(&mut series, &bench_scene.name, points);
        }
        if self.default_scenes {
            let name = "critter-walking";
            let _ = writeln!(
                self.md,
                "The walking critter (`{name}`): the built-in critter at its defaults after \
                 {walk} frames of its walk, simulated on its skinned body, then drawn as a \
                 still (the body as posed, the hair as simulated).\n"
            );
            let scene = Scene::defaults(ModelSpec::Critter);
            let shot = Shot::walking(self.device, &scene, extent, walk)?;
            (self.progress)(&format!("{name}: walked"));
            let points = self.truth_scene(name, &shot, &truth)?;
            add(&mut series, name, points);
            let name = groom::NAME;
            let _ = writeln!(
                self.md,
                "A groom file drawn as it is (`{name}`): the blob's master hairs, curled, \
                 written as a groom file and drawn with `--groom-mode draw`, each guide one \
                 hair (no interpolated hairs).\n"
            );
            let scene = groom::scene(&dir.join(format!("{name}-guides.usda")))?;
            let shot = Shot::new(self.device, &scene, extent)?;
            let points = self.truth_scene(name, &shot, &truth)?;
            add(&mut series, name, points);
        }
        self.truth_colours(&reference, &dir, extent, sampling)?;
        self.plots.push((
            "truth.svg",
            Plot {
                title: "Against the path-traced truth: ꟻLIP and frame time, rung by rung".into(),
                x_label: "frame ms (wall clock)".into(),
                y_label: "ꟻLIP against the path-traced reference".into(),
                log_x: true,
                log_y: false,
                series,
                highlight: None,
            },
        ));
        Ok(())
    }

    /// One scene's shot against its references: every rung and look, then what the
    /// distance is made of. Returns the rungs' (frame ms, ꟻLIP) for the chart.
    fn truth_scene(&mut self, scene: &str, shot: &Shot, t: &Truth) -> Result<Vec<(f64, f64)>> {
        let own = shot.look(&shot.settings.style);
        // The capture draws the scene's own look: that image is its drawing here.
        let (own_image, usda, text, hairs) =
            export(shot, &own, &t.dir.join(format!("{scene}.usda")))?;
        let spread = direction_spread(&hairs.points, hairs.vertices_per_strand);
        (self.progress)(&format!("{scene}: exported"));
        // The reference, another seed's (its noise) and a single-scattering one,
        // path-traced together (the frame loaded once).
        let mut traced = cached_traces(
            t.reference,
            &usda,
            &text,
            t.sampling,
            &[(0, None), (1, None), (0, Some(2))],
        )?;
        let (first, second, single) = (traced.remove(0), traced.remove(0), traced.remove(0));
        let (truth, second, single) = (first.image, second.image, single.image);
        (self.progress)(&format!("{scene}: reference"));
        (self.progress)(&format!("{scene}: noise"));
        let noise_flip = flip(&to_srgb8(&truth), &to_srgb8(&second));
        let noise_rmse = rmse_linear(&truth, &second)?;
        let cost = first.seconds;
        if let Some(seconds) = cost {
            self.row(
                "truth",
                scene.to_string(),
                "reference_seconds",
                seconds,
                "s",
            );
        }
        let mut notes = cost.map_or(String::new(), |s| {
            format!(
                " One reference ({} samples a pixel) took {s:.0} s to path-trace here.",
                t.sampling.spp
            )
        });
        if let Some(spread) = spread {
            self.row(
                "truth",
                scene.to_string(),
                "direction_spread",
                spread,
                "rad²",
            );
            let _ = write!(
                notes,
                " Its drawn hairs' directions spread by {spread:.3} rad² (neighbours' mean \
                 squared angle; the Marschner model takes {}).",
                shot.settings.lighting.fibre.direction_spread
            );
        }
        (self.progress)(&format!("{scene}: single scattering"));
        let ladder = self.device.info.ladder(shot.settings.style.raster);
        let mut measured = Vec::new();
        for (r, rung) in ladder.rungs.iter().enumerate() {
            let style = rung.apply(&shot.settings.style);
            let drawn = shot.draw(&style, self.frames())?;
            let (f, e) = errors(&drawn.image, &truth)?;
            measured.push(Measured {
                name: format!("rung {r} ({})", rung.name),
                frame_ms: drawn.frame_ms,
                flip: f,
                rmse: e,
                flip_second: errors(&drawn.image, &second)?.0,
            });
            (self.progress)(&format!("{scene}: rung {r}"));
        }
        for (i, (name, look)) in looks(&own).into_iter().enumerate() {
            let drawn = shot.draw_look(&look, self.frames())?;
            let (f, e) = errors(&drawn.image, &truth)?;
            if i == 0 {
                // The other lighting model's drawing, for the side-by-side.
                let file = format!("{scene}-{}.png", look.lighting.model.name());
                drawn.image.write_png(&t.dir.join(file))?;
            }
            (self.progress)(&format!("{scene}: {name}"));
            measured.push(Measured {
                name,
                frame_ms: drawn.frame_ms,
                flip: f,
                rmse: e,
                flip_second: errors(&drawn.image, &second)?.0,
            });
        }
        let supersampled = shot.reference(4)?;
        let (ss_flip, ss_rmse) = errors(&supersampled, &truth)?;
        let file = format!("{scene}-{}.png", own.lighting.model.name());
        own_image.write_png(&t.dir.join(file))?;
        to_srgb8(&truth).write_png(&t.dir.join(format!("{scene}-reference.png")))?;
        let (own_flip, own_rmse) = errors(&own_image, &truth)?;
        let (own_single, _) = errors(&own_image, &single)?;
        (self.progress)(&format!("{scene}: attribution"));
        self.truth_table(scene, &measured, noise_flip, noise_rmse, &notes);
        let share = |changed: f64| percent(100.0 * (own_flip - changed) / own_flip);
        let _ = writeln!(
            self.md,
            "What the distance of the scene's own drawing (ꟻLIP {own_flip:.4}) is made \
             of, one thing changed at a time; *share*: the part of the distance the change \
             removes (negative: it adds).\n\n| change | ꟻLIP | RMSE | share |\n| --- | --- \
             | --- | --- |\n| none: the scene's drawing against the reference | \
             {own_flip:.4} | {own_rmse:.4} | – |\n| coverage exact: fur's 4×4 supersampled \
             drawing against the reference | {ss_flip:.4} | {ss_rmse:.4} | {} |\n| no \
             multiple scattering: the drawing against a single-scattering reference | \
             {own_single:.4} | – | {} |\n",
            share(ss_flip),
            share(own_single)
        );
        for (metric, value) in [
            ("own_flip", own_flip),
            ("noise_flip", noise_flip),
            ("noise_rmse", noise_rmse),
            ("supersampled_flip", ss_flip),
            ("single_scattering_flip", own_single),
        ] {
            self.row("truth", scene.to_string(), metric, value, "0..1");
        }
        self.truth_terms(scene, shot, &own, &truth)?;
        Ok(measured[..ladder.len()]
            .iter()
            .map(|m| (m.frame_ms, m.flip))
            .collect())
    }

    /// The scene's table: the references' noise and `notes` (what a reference cost and
    /// the hairs' direction spread: sentences, or nothing), then every drawing against
    /// the first reference.
    fn truth_table(
        &mut self,
        scene: &str,
        measured: &[Measured],
        noise_flip: f64,
        noise_rmse: f64,
        notes: &str,
    ) {
        let pairs: Vec<(f64, f64)> = measured.iter().map(|m| (m.flip, m.flip_second)).collect();
        let names: Vec<String> = measured.iter().map(|m| m.name.clone()).collect();
        let (spread, gap) = seed_spread(&pairs);
        let deltas = differences(&pairs);
        let _ = writeln!(
            self.md,
            "### {scene}\n\nReference noise: ꟻLIP {:.4}, RMSE {:.4}.{notes} {}\n\n| drawing | \
             frame ms | ꟻLIP | Δ ꟻLIP (noise) | RMSE |\n| --- | --- | --- | --- | --- |",
            noise_flip,
            noise_rmse,
            noise::capitalised(&noise_sentence(&pairs, &names, "the scene's drawing"))
        );
        self.row(
            "truth",
            scene.to_string(),
            "seed_spread_flip",
            spread,
            "0..1",
        );
        self.row("truth", scene.to_string(), "closest_gap_flip", gap, "0..1");
        self.difference_rows(scene, &pairs);
        for (m, delta) in measured.iter().zip(&deltas) {
            let _ = writeln!(
                self.md,
                "| {} | {:.1} | {:.4} | {} | {:.4} |",
                m.name,
                m.frame_ms,
                m.flip,
                delta_cell(*delta),
                m.rmse
            );
            let case = format!("{scene}: {}", m.name);
            self.row("truth", case.clone(), "frame_ms", m.frame_ms, "ms");
            self.row("truth", case.clone(), "flip", m.flip, "0..1");
            self.row("truth", case, "rmse", m.rmse, "linear");
        }
        self.md.push('\n');
    }

    /// The CSV rows of a table's noise ([`noise`]): the most the second reference moves
    /// a difference from the first drawing, how many of those differences and of all
    /// pairs of drawings are ten times their noise or more, and how many there are.
    pub(super) fn difference_rows(&mut self, case: &str, pairs: &[(f64, f64)]) {
        let (told, all, worst) = resolved(&differences(pairs));
        let pair_count = pairs.len() * pairs.len().saturating_sub(1) / 2;
        let pairs_told = pair_count - unresolved_pairs(pairs).len();
        for (metric, value, unit) in [
            ("difference_noise_flip", worst, "0..1"),
            ("differences_resolved", told as f64, "count"),
            ("differences", all as f64, "count"),
            ("pairs_resolved", pairs_told as f64, "count"),
            ("pairs", pair_count as f64, "count"),
        ] {
            self.row("truth", case.to_string(), metric, value, unit);
        }
    }
}

/// Writes the frame `shot` draws with `look` to `usda`: its image, the file, the file's
/// text, and the hairs it drew.
fn export(
    shot: &Shot,
    look: &Look,
    usda: &Path,
) -> Result<(RgbaImage, PathBuf, String, CapturedHairs)> {
    let (image, hairs, settings) = shot.capture(look)?;
    let frame = FrameExport::new(
        hairs,
        &shot.mesh,
        shot.texture(),
        None,
        &settings,
        shot.extent,
    );
    frame.check_size()?;
    let text = write_usda(&frame, "fur bench")?;
    fur_core::files::write_output(usda, text.as_bytes(), "write the frame to")?;
    Ok((image, usda.to_path_buf(), text, frame.hairs))
}

/// A signed percentage to the nearest whole one ("+3 %", "−12 %", "0 %").
fn percent(x: f64) -> String {
    let rounded = x.round();
    if rounded == 0.0 {
        "0 %".to_string()
    } else {
        format!("{rounded:+.0} %")
    }
}
