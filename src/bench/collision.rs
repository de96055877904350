//! Body collision: what the distance field costs to build and hold at each resolution,
//! what the collision step adds to a simulated frame, and how far hair still gets into
//! the body (measured with exact distances) against the field's resolution.

use std::fmt::Write as _;

use glam::Vec3;

use super::sim::{bench_shake, blob_body, blob_strands, SimRun};
use super::Bench;
use fur_core::scene::{Mesh, Strands};
use fur_core::sim::{Sdf, SimParams};
use fur_gpu::error::Result;
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;

fn resolutions(quick: bool) -> &'static [u32] {
    if quick {
        &[16, 32]
    } else {
        &[16, 32, 64, 128]
    }
}

pub(super) fn tasks(quick: bool) -> u64 {
    2 + resolutions(quick).len() as u64
}

impl Bench<'_> {
    /// Hair combed down over the blob, shaken under strong gravity for `frames` frames
    /// on the GPU, colliding with `body` (or not): (mean, max) depth of strand vertices
    /// inside the body, fractions of the hair length, from exact distances.
    fn penetration(
        &self,
        strands: &Strands,
        body: &Sdf,
        frames: usize,
        collision: bool,
    ) -> Result<(f64, f64)> {
        let mesh = Mesh::blob();
        let (_, params, motion) = fur_core::sim::sdf::pressing_case(mesh.bounds().1, collision);
        let mut textures = StrandTextures::new(self.device, strands, motion.head(0.0).as_mat4())?;
        let mut gpu = GpuSim::with_body(self.device, &textures, params, 1, Some(body))?;
        let v = strands.vertices_per_strand as usize;
        let mut depths = super::metrics::Depths::default();
        // Sample the depth over the run's second half.
        for chunk in 0..4 {
            fur_core::interrupt::check()?;
            gpu.run_frames(&mut textures, frames / 4, |t| motion.head(t))?;
            if chunk < 2 {
                continue;
            }
            let to_model = motion.head(gpu.time).inverse().as_mat4();
            let model: Vec<Vec3> = textures
                .read_positions(textures.current)?
                .iter()
                .enumerate()
                .filter(|(i, _)| i % v != 0)
                .map(|(_, p)| to_model.transform_point3(*p))
                .collect();
            depths.add(&mesh, &model);
        }
        Ok(depths.relative_to(f64::from(strands.hair_length())))
    }

    pub(super) fn collision(&mut self) -> Result<()> {
        let frames = if self.quick { 20 } else { 200 };
        let blob = Mesh::blob();
        let (_, radius) = blob.bounds();
        let (groom, _, _) = fur_core::sim::sdf::pressing_case(radius, true);
        let pressed = Strands::grow(&blob, &groom)?;
        let hair = pressed.hair_length();
        let default_cells = Sdf::cells_for_hair(&blob, &SimParams::default(), hair, false);
        let _ = writeln!(
            self.md,
            "## Collision\n\nThe blob's distance field at each resolution (cells along the longest \
             axis of the box padded by the hair length): build time on the CPU and size on the \
             device; then hair 0.3 × the radius long, combed down hard, shaken under 4× \
             gravity for {frames} frames on the GPU: the depth of strand vertices inside the body \
             over the second half, from exact distances, as fractions of the hair length \
             (default margin {}: vertices are kept that far outside; default resolution here \
             {default_cells}).\n\n\
             | resolution | grid points | build ms | MiB | mean depth | max depth |\n\
             | --- | --- | --- | --- | --- | --- |",
            SimParams::default().collision_margin
        );
        let mut resolutions = resolutions(self.quick).to_vec();
        if !resolutions.contains(&default_cells) {
            resolutions.push(default_cells);
            resolutions.sort_unstable();
        }
        for cells in resolutions {
            let (sdf, report) = Sdf::build(&blob, cells, hair)?;
            let (mean, max) = self.penetration(&pressed, &sdf, frames, true)?;
            let label = if cells == default_cells {
                format!("resolution {cells} (default)")
            } else {
                format!("resolution {cells}")
            };
            let points = sdf.values.len();
            let mib = sdf.bytes() as f64 / (1024.0 * 1024.0);
            self.row(
                "collision",
                label.clone(),
                "grid_points",
                points as f64,
                "count",
            );
            self.row(
                "collision",
                label.clone(),
                "build_ms",
                report.build_ms,
                "ms",
            );
            self.row("collision", label.clone(), "device_mib", mib, "MiB");
            self.row(
                "collision",
                label.clone(),
                "mean_penetration",
                mean,
                "fraction of hair length",
            );
            self.row(
                "collision",
                label.clone(),
                "max_penetration",
                max,
                "fraction of hair length",
            );
            let _ = writeln!(
                self.md,
                "| {label} | {points} | {:.1} | {mib:.2} | {mean:.2e} | {max:.2e} |",
                report.build_ms
            );
            (self.progress)(&label);
        }
        // Without collision, for scale.
        let (sdf, _) = Sdf::build(&blob, default_cells, hair)?;
        let (mean, max) = self.penetration(&pressed, &sdf, frames, false)?;
        self.row(
            "collision",
            "collision off",
            "mean_penetration",
            mean,
            "fraction of hair length",
        );
        self.row(
            "collision",
            "collision off",
            "max_penetration",
            max,
            "fraction of hair length",
        );
        let _ = writeln!(self.md, "| collision off | | | | {mean:.2e} | {max:.2e} |");
        (self.progress)("collision off");

        // The cost in the default scene.
        let strands = blob_strands()?;
        let body = blob_body(&strands, &SimParams::default())?;
        let params = fur_core::scene_file::Scene::default_sim();
        let motion = bench_shake();
        let run = |collision| SimRun {
            params: SimParams {
                collision,
                ..params.clone()
            },
            skinned: None,
            field: Some(&body),
            steps: None,
        };
        let times =
            self.sims_taking_turns_ms(&strands, &[run(true), run(false)], |t| motion.head(t))?;
        let (with, without) = (times[0], times[1]);
        self.row(
            "collision",
            "default scene, collision on",
            "ms_per_frame",
            with,
            "ms",
        );
        self.row(
            "collision",
            "default scene, collision off",
            "ms_per_frame",
            without,
            "ms",
        );
        self.row(
            "collision",
            "default scene",
            "added_fraction",
            with / without - 1.0,
            "fraction",
        );
        let _ = writeln!(
            self.md,
            "\nThe default blob ({} strands), simulation per frame with wind (the two taking \
             turns frame by frame): {with:.3} ms with collision, {without:.3} ms without: \
             collision adds {:.0} %.\n",
            strands.count(),
            100.0 * (with / without - 1.0)
        );
        (self.progress)("collision cost");
        Ok(())
    }
}
