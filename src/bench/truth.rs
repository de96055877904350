//! Section `truth`: fur's drawings against a path-traced reference of the same frame.
//!
//! For each scene, the settled frame (as the render-quality section takes it) is drawn
//! at the scene's own settings with every hair captured, exported (`fur export-frame`'s
//! USD) and path-traced by `tools/reference` with Mitsuba 3's hair model, twice with
//! different seeds: the two references' distance is the reference's own noise. Then
//! every rung of the quality ladder and every look on and off is drawn and measured
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

use super::plot::{Plot, Series, PALETTE};
use super::quality::{Look, Shot};
use super::Bench;
use crate::error::Result;
use crate::export::compare::{errors, rmse_linear, to_srgb8};
use crate::export::reference::{read_pfm, LinearImage, Reference, TraceOptions, SCRIPT};
use crate::export::{write_usda, FrameExport};
use crate::render::budget::LADDER;
use crate::render::{flip, FurPreset, LightingModel, RgbaImage};

/// The looks switched one at a time, each against the scene's own drawing.
const LOOKS: usize = 6;

/// The fur presets the section draws the first scene in.
const COLOURS: u64 = 3;

pub(super) fn tasks(scenes: usize) -> u64 {
    scenes as u64 * (3 + LADDER.len() as u64 + LOOKS as u64 + 1) + 2 * COLOURS
}

/// One drawing measured against the truth.
struct Measured {
    name: String,
    frame_ms: f64,
    flip: f64,
    rmse: f64,
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
        let extent = if self.quick {
            ash::vk::Extent2D {
                width: 96,
                height: 54,
            }
        } else {
            ash::vk::Extent2D {
                width: 320,
                height: 180,
            }
        };
        let spp = if self.quick { 16 } else { 256 };
        let dir = out_dir.join("truth");
        std::fs::create_dir_all(&dir)
            .map_err(|e| crate::error::Error::io("create the folder", &dir, e))?;
        let _ = writeln!(
            self.md,
            "Each scene's settled frame at {}×{}, drawn by fur and path-traced by \
             `tools/reference` (Mitsuba 3, Chiang et al.'s hair model, the same camera, \
             lights and hairs; {spp} samples a pixel, up to 64 bounces). *Noise*: the \
             reference against a second one with another seed, its own uncertainty. ꟻLIP \
             on sRGB, RMSE in linear light; frame time as in the ladder.\n",
            extent.width, extent.height
        );
        let mut series = Vec::new();
        for (k, bench_scene) in self.scenes.clone().iter().enumerate() {
            let scene = &bench_scene.name;
            let shot = Shot::new(self.device, &bench_scene.scene, extent)?;
            let own = shot.look(&shot.settings.style);
            // The capture draws the scene's own look: that image is its drawing here.
            let (own_image, usda, text) = export(&shot, &own, &dir.join(format!("{scene}.usda")))?;
            (self.progress)(&format!("{scene}: exported"));
            let trace = |seed: u32, depth: Option<u32>| -> Result<LinearImage> {
                cached_trace(&reference, &usda, &text, spp, seed, depth)
            };
            let truth = trace(0, None)?;
            (self.progress)(&format!("{scene}: reference"));
            let second = trace(1, None)?;
            (self.progress)(&format!("{scene}: noise"));
            let noise_flip = flip(&to_srgb8(&truth), &to_srgb8(&second));
            let noise_rmse = rmse_linear(&truth, &second)?;
            let single = trace(0, Some(2))?;
            (self.progress)(&format!("{scene}: single scattering"));
            let mut measured = Vec::new();
            for (r, rung) in LADDER.iter().enumerate() {
                let style = rung.apply(&shot.settings.style);
                let drawn = shot.draw(&style, self.frames())?;
                let (f, e) = errors(&drawn.image, &truth)?;
                measured.push(Measured {
                    name: format!("rung {r} ({})", rung.name),
                    frame_ms: drawn.frame_ms,
                    flip: f,
                    rmse: e,
                });
                (self.progress)(&format!("{scene}: rung {r}"));
            }
            for (i, (name, look)) in looks(&own).into_iter().enumerate() {
                let drawn = shot.draw_look(&look, self.frames())?;
                let (f, e) = errors(&drawn.image, &truth)?;
                if i == 0 {
                    // The other lighting model's drawing, for the side-by-side.
                    let file = format!("{scene}-{}.png", look.lighting.model.name());
                    drawn.image.write_png(&dir.join(file))?;
                }
                (self.progress)(&format!("{scene}: {name}"));
                measured.push(Measured {
                    name,
                    frame_ms: drawn.frame_ms,
                    flip: f,
                    rmse: e,
                });
            }
            let supersampled = shot.reference(4)?;
            let (ss_flip, ss_rmse) = errors(&supersampled, &truth)?;
            let file = format!("{scene}-{}.png", own.lighting.model.name());
            own_image.write_png(&dir.join(file))?;
            to_srgb8(&truth).write_png(&dir.join(format!("{scene}-reference.png")))?;
            let (own_flip, own_rmse) = errors(&own_image, &truth)?;
            let (own_single, _) = errors(&own_image, &single)?;
            (self.progress)(&format!("{scene}: attribution"));
            self.truth_table(scene, &measured, (noise_flip, noise_rmse));
            let _ = writeln!(
                self.md,
                "What the distance of the scene's own drawing (ꟻLIP {own_flip:.4}) is made \
                 of, one thing changed at a time:\n\n| change | ꟻLIP | RMSE |\n| --- | --- | \
                 --- |\n| none: the scene's drawing against the reference | {own_flip:.4} | \
                 {:.4} |\n| coverage exact: fur's 4×4 supersampled drawing against the \
                 reference | {ss_flip:.4} | {ss_rmse:.4} |\n| no multiple scattering: the \
                 drawing against a single-scattering reference | {own_single:.4} | – |\n",
                own_rmse
            );
            for (metric, value) in [
                ("own_flip", own_flip),
                ("noise_flip", noise_flip),
                ("noise_rmse", noise_rmse),
                ("supersampled_flip", ss_flip),
                ("single_scattering_flip", own_single),
            ] {
                self.row("truth", scene.clone(), metric, value, "0..1");
            }
            series.push(Series {
                name: scene.to_string(),
                points: measured[..LADDER.len()]
                    .iter()
                    .map(|m| (m.frame_ms, m.flip))
                    .collect(),
                color: PALETTE[k % PALETTE.len()],
                line: true,
            });
        }
        self.truth_colours(&reference, &dir, extent, spp)?;
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

    /// Light and dark fur (the first scene in the fur presets `white`, `blond` and
    /// `black`): each lighting model, alone and with shadows, against its reference.
    fn truth_colours(
        &mut self,
        reference: &Reference,
        dir: &Path,
        extent: ash::vk::Extent2D,
        spp: u32,
    ) -> Result<()> {
        let Some(base) = self.scenes.first().cloned() else {
            return Ok(());
        };
        let _ = writeln!(
            self.md,
            "### Light and dark fur ({})\n\nThe {} scene in three fur presets (colours as \
             melanin, docs/design.md), each against its own reference; the Marschner model \
             with shadows also with coloured shadows (`--coloured-shadows`).\n\n| fur | \
             drawing | frame ms | ꟻLIP | RMSE |\n| --- | --- | --- | --- | --- |",
            base.name, base.name
        );
        let mut noises = Vec::new();
        for preset in [FurPreset::White, FurPreset::Blond, FurPreset::Black] {
            let mut scene = base.scene.clone();
            scene.options.lighting.preset = preset;
            let shot = Shot::new(self.device, &scene, extent)?;
            let own = shot.look(&shot.settings.style);
            let name = format!("{}-{}", base.name, preset.name());
            let (_, usda, text) = export(&shot, &own, &dir.join(format!("{name}.usda")))?;
            let truth = cached_trace(reference, &usda, &text, spp, 0, None)?;
            let second = cached_trace(reference, &usda, &text, spp, 1, None)?;
            let noise = flip(&to_srgb8(&truth), &to_srgb8(&second));
            (self.progress)(&format!("{name}: references"));
            to_srgb8(&truth).write_png(&dir.join(format!("{name}-reference.png")))?;
            let mut drawings = Vec::new();
            let cases = [
                (LightingModel::KajiyaKay, false, false),
                (LightingModel::KajiyaKay, true, false),
                (LightingModel::Marschner, false, false),
                (LightingModel::Marschner, true, false),
                (LightingModel::Marschner, true, true),
            ];
            {
                for (model, shadows, coloured) in cases {
                    let mut look = own.clone();
                    look.lighting.model = model;
                    look.lighting.shadows.enabled = shadows;
                    look.lighting.shadows.coloured = coloured;
                    let drawn = shot.draw_look(&look, self.frames())?;
                    let (f, e) = errors(&drawn.image, &truth)?;
                    if shadows && !coloured {
                        let file = format!("{name}-{}.png", model.name());
                        drawn.image.write_png(&dir.join(file))?;
                    }
                    let what = format!(
                        "{}{}{}",
                        model.label(),
                        if shadows { ", shadows on" } else { "" },
                        if coloured { ", coloured" } else { "" }
                    );
                    drawings.push((what, drawn.frame_ms, f, e));
                }
            }
            (self.progress)(&format!("{name}: drawings"));
            for (what, ms, f, e) in drawings {
                let _ = writeln!(
                    self.md,
                    "| {} | {what} | {ms:.1} | {f:.4} | {e:.4} |",
                    preset.name()
                );
                let case = format!("{name}: {what}");
                self.row("truth", case.clone(), "frame_ms", ms, "ms");
                self.row("truth", case.clone(), "flip", f, "0..1");
                self.row("truth", case, "rmse", e, "linear");
            }
            self.row("truth", name, "noise_flip", noise, "0..1");
            noises.push(format!("{} {noise:.4}", preset.name()));
        }
        let _ = writeln!(
            self.md,
            "\nReference noise (ꟻLIP): {}.\n",
            noises.join(", ")
        );
        Ok(())
    }

    fn truth_table(&mut self, scene: &str, measured: &[Measured], noise: (f64, f64)) {
        let _ = writeln!(
            self.md,
            "### {scene}\n\nReference noise: ꟻLIP {:.4}, RMSE {:.4}.\n\n| drawing | frame ms | \
             ꟻLIP | RMSE |\n| --- | --- | --- | --- |",
            noise.0, noise.1
        );
        for m in measured {
            let _ = writeln!(
                self.md,
                "| {} | {:.1} | {:.4} | {:.4} |",
                m.name, m.frame_ms, m.flip, m.rmse
            );
            let case = format!("{scene}: {}", m.name);
            self.row("truth", case.clone(), "frame_ms", m.frame_ms, "ms");
            self.row("truth", case.clone(), "flip", m.flip, "0..1");
            self.row("truth", case, "rmse", m.rmse, "linear");
        }
        self.md.push('\n');
    }
}

/// The scene's look with one thing switched: the lighting model (alone, and with
/// shadows), shadows, the secondary highlight, thin-hair AA. Sample counts and lines
/// against ribbons are the ladder's rungs (rung 1: 4× lines, rung 2: 1× ribbons,
/// rung 3: 1× lines), not drawn again here.
fn looks(own: &Look) -> Vec<(String, Look)> {
    let with = |edit: &dyn Fn(&mut Look)| {
        let mut look = own.clone();
        edit(&mut look);
        look
    };
    let l = &own.lighting;
    let other = match l.model {
        LightingModel::KajiyaKay => LightingModel::Marschner,
        LightingModel::Marschner => LightingModel::KajiyaKay,
    };
    let switched = |on: bool, what: &str| format!("{what} {}", if on { "off" } else { "on" });
    let looks = vec![
        (
            format!("{} lighting", other.label()),
            with(&|k| k.lighting.model = other),
        ),
        (
            format!("{} lighting, shadows on", other.label()),
            with(&|k| {
                k.lighting.model = other;
                k.lighting.shadows.enabled = true;
            }),
        ),
        (
            "Marschner lighting, shadows on, coloured shadows".to_string(),
            with(&|k| {
                k.lighting.model = LightingModel::Marschner;
                k.lighting.shadows.enabled = true;
                k.lighting.shadows.coloured = true;
            }),
        ),
        (
            switched(l.shadows.enabled, "shadows"),
            with(&|k| k.lighting.shadows.enabled = !l.shadows.enabled),
        ),
        (
            switched(l.highlights.secondary, "secondary highlight"),
            with(&|k| k.lighting.highlights.secondary = !l.highlights.secondary),
        ),
        (
            switched(own.style.thin_hair_aa, "thin-hair AA"),
            with(&|k| k.style.thin_hair_aa = !own.style.thin_hair_aa),
        ),
    ];
    debug_assert_eq!(looks.len(), LOOKS);
    looks
}

/// The shot drawn in `look` with every hair captured, exported to `usda`: the drawing,
/// the file and its text.
fn export(shot: &Shot, look: &Look, usda: &Path) -> Result<(RgbaImage, PathBuf, String)> {
    let (image, hairs, settings) = shot.capture(look)?;
    let extent = shot.extent;
    let frame = FrameExport::new(
        hairs,
        &shot.mesh,
        None,
        &settings,
        (extent.width, extent.height),
    );
    frame.check_size()?;
    let text = write_usda(&frame, "fur bench")?;
    crate::files::write_output(usda, text.as_bytes(), "write the frame to")?;
    Ok((image, usda.to_path_buf(), text))
}

/// The reference of `usda` (whose text is `text`) at `spp` samples, seed `seed` and at
/// most `depth` bounces, path-traced unless a file of the same hash is there.
fn cached_trace(
    reference: &Reference,
    usda: &Path,
    text: &str,
    spp: u32,
    seed: u32,
    depth: Option<u32>,
) -> Result<LinearImage> {
    let key = fnv64(&[
        text.as_bytes(),
        SCRIPT.as_bytes(),
        format!("{spp} {seed} {depth:?}").as_bytes(),
    ]);
    let dir = usda.parent().map_or(PathBuf::from("."), Path::to_path_buf);
    let pfm = dir.join(format!("reference-{key:016x}.pfm"));
    if !pfm.is_file() {
        let options = TraceOptions {
            spp,
            seed,
            ..Default::default()
        };
        let depth_arg = depth.map(|d| d.to_string());
        let extra: Vec<&str> = depth_arg
            .as_deref()
            .map(|d| vec!["--max-depth", d])
            .unwrap_or_default();
        reference.trace(usda, &pfm, &options, &extra)?;
    }
    read_pfm(&pfm)
}

/// FNV-1a, 64 bits, over the parts in order.
fn fnv64(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for part in parts {
        for &b in *part {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}
