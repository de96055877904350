//! What skipping work the scene does not need saves: the same frame with and without
//! the saving, as ratios.

use std::fmt::Write as _;

use super::quality::Shot;
use super::sim::{blob_body, blob_strands};
use super::Bench;
use fur_core::render::FurStyle;
use fur_core::scene::{Mesh, ModelSpec};
use fur_core::scene_file::Scene;
use fur_core::sim::SimParams;
use fur_gpu::error::Result;

pub(super) const TASKS: u64 = 5;

impl Bench<'_> {
    pub(super) fn savings(&mut self) -> Result<()> {
        let _ = writeln!(
            self.md,
            "## Work the scene does not need\n\nThe default blob; frame times are whole still frames \
             (wall clock), simulation times one dispatch per frame.\n\n\
             | saving | with the work | without | ratio |\n| --- | --- | --- | --- |"
        );
        let strands = blob_strands()?;
        let blob = Scene::defaults(ModelSpec::Blob);
        let full = blob.sim.clone();
        let sim_cases = [
            (
                "wind off: wind step compiled out",
                SimParams {
                    wind: glam::Vec3::ZERO,
                    ..full.clone()
                },
            ),
            (
                "S_G = 0: global-shape step compiled out",
                SimParams {
                    global_stiffness: 0.0,
                    ..full.clone()
                },
            ),
            (
                "collision off: collision step compiled out",
                SimParams {
                    collision: false,
                    ..full.clone()
                },
            ),
        ];
        let body = blob_body(&strands, &full)?;
        let (_, with_all) = self.sim_ms_with_steps(&strands, &full, None, Some(&body))?;
        for (name, params) in sim_cases {
            let (_, without) = self.sim_ms_with_steps(&strands, &params, None, Some(&body))?;
            self.saving(name, with_all, without, "simulation ms/frame");
            (self.progress)(name);
        }

        let frames = self.frames();
        let shot = Shot::new(self.device, &blob, self.frame_extent())?;
        let style = shot.settings.style.clone();
        let culled = shot.draw(&style, frames)?;
        let all = shot.draw(
            &FurStyle {
                cull: false,
                ..style.clone()
            },
            frames,
        )?;
        self.saving(
            "culling back-facing and off-screen triangles",
            all.frame_ms,
            culled.frame_ms,
            "frame ms",
        );
        let hairs = |d: &super::quality::Drawn| d.counts.map_or(f64::NAN, |c| c.hairs as f64);
        self.saving("culling: hairs drawn", hairs(&all), hairs(&culled), "hairs");
        (self.progress)("culling");

        let mesh = Mesh::blob();
        let framing = blob.options.framing_distance(&mesh) / mesh.bounds().1;
        let mut far_scene = blob.clone();
        far_scene.options.distance = Some(4.0 * framing);
        let mut far = Shot::new(self.device, &far_scene, self.frame_extent())?;
        let lod = far.draw(&far.settings.style.clone(), frames)?;
        far.settings.style.lod_distance = 1e9;
        let dense = far.draw(&far.settings.style.clone(), frames)?;
        self.saving(
            "density LOD at 4× the distance",
            dense.frame_ms,
            lod.frame_ms,
            "frame ms",
        );
        self.saving(
            "density LOD: hairs drawn",
            hairs(&dense),
            hairs(&lod),
            "hairs",
        );
        (self.progress)("level of detail");
        self.md.push('\n');
        Ok(())
    }

    fn saving(&mut self, name: &str, with: f64, without: f64, unit: &'static str) {
        let ratio = with / without;
        self.row("savings", name, "with", with, unit);
        self.row("savings", name, "without", without, unit);
        self.row("savings", name, "ratio", ratio, "x");
        let _ = writeln!(
            self.md,
            "| {name} | {with:.3} {unit} | {without:.3} | {ratio:.2}× |"
        );
    }
}
