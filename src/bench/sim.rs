//! The simulation's sections: accuracy against the converged CPU reference, the cost of
//! each step, and scaling with the number of strands.

use std::fmt::Write as _;
use std::time::Instant;

use glam::{DMat4, DVec3};

use super::metrics::{max_stretch, median, pareto_front, position_error};
use super::plot::{Plot, Series, PALETTE};
use super::Bench;
use fur_core::scene::{GroomParams, Mesh, Strands};
use fur_core::scene_file::Scene;
use fur_core::scene_file::SceneOptions;
use fur_core::sim::{CpuSim, Motion, MotionKind, Sdf, SimParams, SimStep};
use fur_gpu::error::Result;
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;

/// The head's motion while the simulation's cost is timed: a shake, so hair moves and
/// touches the body.
pub(super) fn bench_shake() -> Motion {
    Motion {
        kind: MotionKind::Shake,
        amplitude: 0.2,
        rate: 1.0,
    }
}

/// One simulation [`Bench::sims_taking_turns_ms`] times.
pub(super) struct SimRun<'a> {
    pub params: SimParams,
    pub skinned: Option<fur_gpu::sim::SkinnedMotion>,
    pub field: Option<&'a Sdf>,
    pub steps: Option<&'a [SimStep]>,
}

/// The settings being measured for the simulation trade: iterations (local and length
/// alike) and substeps.
const DEFAULT_ITERATIONS: u32 = 2;
const DEFAULT_SUBSTEPS: u32 = 1;

pub(super) fn accuracy_tasks(quick: bool) -> u64 {
    if quick {
        4
    } else {
        15
    }
}

pub(super) fn scaling_tasks(quick: bool) -> u64 {
    if quick {
        2
    } else {
        4
    }
}

/// The master hairs of the default scene.
pub(super) fn blob_strands() -> Result<Strands> {
    let blob = Mesh::blob();
    let (groom, _) = SceneOptions::default().resolve(&blob)?;
    Ok(Strands::grow(&blob, &groom)?)
}

/// The default scene's body at `params`' resolution (as a session builds it).
pub(super) fn blob_body(strands: &Strands, params: &SimParams) -> Result<Sdf> {
    Ok(Sdf::for_hair(&Mesh::blob(), params, strands.hair_length(), false)?.0)
}

impl Bench<'_> {
    /// GPU simulation against the converged CPU f64 reference (8× substeps, 64
    /// iterations), over iterations and substeps; cost measured on the default blob.
    pub(super) fn simulation_accuracy(&mut self) -> Result<()> {
        let iterations: &[u32] = if self.quick {
            &[1, 2]
        } else {
            &[1, 2, 4, 8, 16]
        };
        let substeps: &[u32] = if self.quick { &[1, 2] } else { &[1, 2, 4] };
        let frames = if self.quick { 10 } else { 60 };
        let mesh = Mesh::icosphere(if self.quick { 1 } else { 2 });
        let groom = GroomParams {
            segment_length: 0.2 / 16.0,
            curl: 0.4,
            ..Default::default()
        };
        let hair_length = f64::from(groom.segment_length * groom.segments as f32);
        let strands = Strands::grow(&mesh, &groom)?;
        let motion = Motion {
            kind: MotionKind::Shake,
            amplitude: 0.25,
            rate: 1.0,
        };
        let base = Scene::default_sim();
        let reference = {
            let params = SimParams {
                substeps: 8 * DEFAULT_SUBSTEPS,
                local_iterations: 64,
                length_iterations: 64,
                ..base.clone()
            };
            let mut cpu = CpuSim::<f64>::new(&strands, params, motion.head(0.0));
            for _ in 0..frames {
                fur_core::interrupt::check()?;
                cpu.step_frame(|t| motion.head(t));
            }
            cpu
        };
        let reference_positions: Vec<DVec3> = reference
            .current
            .iter()
            .map(|p| DVec3::new(p.0, p.1, p.2))
            .collect();
        let rest_lengths = reference.rest.lengths.clone();
        let blob_strands = blob_strands()?;

        let mut points = Vec::new();
        for &sub in substeps {
            for &it in iterations {
                let params = SimParams {
                    substeps: sub,
                    local_iterations: it,
                    length_iterations: it,
                    ..base.clone()
                };
                let mut textures =
                    StrandTextures::new(self.device, &strands, motion.head(0.0).as_mat4())?;
                let mut gpu = GpuSim::new(self.device, &textures, params.clone())?;
                gpu.run_frames(&mut textures, frames, |t| motion.head(t))?;
                let positions = textures.read_positions(textures.current)?;
                let (mean, max) = position_error(&positions, &reference_positions, hair_length);
                let stretch = max_stretch(
                    &positions,
                    &rest_lengths,
                    strands.vertices_per_strand as usize,
                );
                let (_, ms) = self.sim_ms_per_frame(&blob_strands, &params)?;
                let case = format!("iterations {it}, substeps {sub}");
                self.row(
                    "sim_accuracy",
                    case.clone(),
                    "mean_position_error",
                    mean,
                    "fraction of hair length",
                );
                self.row(
                    "sim_accuracy",
                    case.clone(),
                    "max_position_error",
                    max,
                    "fraction of hair length",
                );
                self.row(
                    "sim_accuracy",
                    case.clone(),
                    "max_stretch",
                    stretch,
                    "fraction of rest length",
                );
                self.row("sim_accuracy", case.clone(), "wall_ms_per_frame", ms, "ms");
                points.push((it, sub, ms, mean, max, stretch));
                (self.progress)(&case);
            }
        }
        let front = pareto_front(&points.iter().map(|p| (p.2, p.3)).collect::<Vec<_>>());
        let _ = writeln!(
            self.md,
            "## Simulation: accuracy against cost\n\nError after {frames} frames of shake + wind + \
             gravity on {} strands, against the CPU f64 reference at 8 substeps and 64 iterations; \
             cost on the default blob ({} strands). Errors are fractions of the hair length; \
             iterations apply to the local-shape and edge-length constraints alike.\n\n\
             | iterations | substeps | ms/frame | mean error | max error | max stretch | Pareto |\n\
             | --- | --- | --- | --- | --- | --- | --- |",
            strands.count(),
            blob_strands.count()
        );
        for (p, on_front) in points.iter().zip(&front) {
            let default = p.0 == DEFAULT_ITERATIONS && p.1 == DEFAULT_SUBSTEPS;
            self.row(
                "sim_accuracy",
                format!("iterations {}, substeps {}", p.0, p.1),
                "pareto",
                f64::from(u8::from(*on_front)),
                "bool",
            );
            let _ = writeln!(
                self.md,
                "| {}{} | {} | {:.3} | {:.2e} | {:.2e} | {:.2e} | {} |",
                p.0,
                if default { " (default)" } else { "" },
                p.1,
                p.2,
                p.3,
                p.4,
                p.5,
                if *on_front { "yes" } else { "" }
            );
        }
        self.md.push('\n');
        let series = substeps
            .iter()
            .enumerate()
            .map(|(k, &sub)| Series {
                name: format!("{sub} substep{}", if sub > 1 { "s" } else { "" }),
                points: points
                    .iter()
                    .filter(|p| p.1 == sub)
                    .map(|p| (p.2, p.3))
                    .collect(),
                color: PALETTE[k % PALETTE.len()],
                line: true,
            })
            .collect();
        let highlight = points
            .iter()
            .find(|p| p.0 == DEFAULT_ITERATIONS && p.1 == DEFAULT_SUBSTEPS)
            .map(|p| (p.2, p.3, "default".to_string()));
        self.plots.push((
            "sim_pareto.svg",
            Plot {
                title: "Simulation: error against cost (1, 2, 4… iterations)".into(),
                x_label: "ms per frame".into(),
                y_label: "mean error / hair length".into(),
                log_x: true,
                log_y: true,
                series,
                highlight,
            },
        ));
        Ok(())
    }

    /// Median milliseconds per simulated frame for `strands` under `params`, each
    /// frame its own submission: (GPU from timestamps, wall clock from submission to
    /// fence). The tables use the wall clock: it includes the submission (small
    /// on lavapipe) but cannot misattribute, while lavapipe's compute timestamps do once
    /// other work has run on the device.
    pub(super) fn sim_ms_per_frame(
        &self,
        strands: &Strands,
        params: &SimParams,
    ) -> Result<(f64, f64)> {
        self.sim_ms_with_steps(strands, params, None, None)
    }

    /// As [`Bench::sim_ms_per_frame`], colliding with `body` when given, with exactly
    /// `steps` compiled in when given.
    pub(super) fn sim_ms_with_steps(
        &self,
        strands: &Strands,
        params: &SimParams,
        steps: Option<&[SimStep]>,
        body: Option<&Sdf>,
    ) -> Result<(f64, f64)> {
        let mut textures = StrandTextures::new(self.device, strands, glam::Mat4::IDENTITY)?;
        let mut gpu = GpuSim::with_body(self.device, &textures, params.clone(), 1, body)?;
        gpu.force_steps(steps, &textures)?;
        let motion = bench_shake();
        // A dispatch is cheap: many frames steady the medians.
        let (warm, measured) = if self.quick { (1, 3) } else { (5, 60) };
        let (mut gpu_ms, mut wall_ms) = (Vec::new(), Vec::new());
        for frame in 0..warm + measured {
            fur_core::interrupt::check()?;
            let start = Instant::now();
            let t = gpu.run_frames(&mut textures, 1, |t| motion.head(t))?;
            if frame >= warm {
                gpu_ms.push(t);
                wall_ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        Ok((median(&gpu_ms), median(&wall_ms)))
    }

    /// Wall-clock milliseconds per simulated frame (median of warm frames) of `strands`
    /// under each of `runs` (its parameters, its body, only its steps compiled in when
    /// given), the head moving by `head`. The runs take turns frame by frame, so a
    /// machine that slows down or speeds up meanwhile weighs on all of them alike.
    pub(super) fn sims_taking_turns_ms(
        &self,
        strands: &Strands,
        runs: &[SimRun<'_>],
        head: impl Fn(f64) -> DMat4 + Copy,
    ) -> Result<Vec<f64>> {
        let mut sims = Vec::new();
        for run in runs {
            let textures = StrandTextures::new(self.device, strands, glam::Mat4::IDENTITY)?;
            let mut gpu = GpuSim::build(
                self.device,
                &textures,
                run.params.clone(),
                1,
                run.field,
                run.skinned.clone(),
            )?;
            gpu.force_steps(run.steps, &textures)?;
            sims.push((textures, gpu, Vec::new()));
        }
        // 300 frames: medians of 60 put one way's share of the step 10 points apart
        // from one run to the next.
        let (warm, measured) = if self.quick { (1, 3) } else { (5, 300) };
        for frame in 0..warm + measured {
            fur_core::interrupt::check()?;
            for (textures, gpu, wall) in &mut sims {
                let start = Instant::now();
                gpu.run_frames(textures, 1, head)?;
                if frame >= warm {
                    wall.push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
        }
        Ok(sims.iter().map(|(_, _, wall)| median(wall)).collect())
    }

    /// The cost of each step: the kernel with the steps up to it compiled in, minus the
    /// kernel without it (each step's cost measured by running it, not by timestamps
    /// between steps, which the fused kernel has none of).
    pub(super) fn simulation_steps(&mut self) -> Result<()> {
        let strands = blob_strands()?;
        let body = blob_body(&strands, &SimParams::default())?;
        let params = Scene::default_sim();
        let _ = writeln!(
            self.md,
            "## Simulation: cost of each step\n\nThe default blob ({} strands of {} vertices), default \
             parameters with wind; one dispatch per frame running the steps compiled in. A step's \
             cost is the difference it makes.\n\n| steps compiled in | ms/frame | step alone, ms |\n| --- | --- | --- |",
            strands.count(),
            strands.vertices_per_strand
        );
        let mut previous = 0.0;
        for n in 1..=SimStep::ALL.len() {
            let steps = &SimStep::ALL[1..n];
            let (_, ms) = self.sim_ms_with_steps(&strands, &params, Some(steps), Some(&body))?;
            let step = SimStep::ALL[n - 1].name();
            let names: Vec<&str> = SimStep::ALL[..n].iter().map(|s| s.name()).collect();
            self.row("sim_steps", step, "wall_ms_per_frame", ms, "ms");
            self.row("sim_steps", step, "step_ms", ms - previous, "ms");
            let _ = writeln!(
                self.md,
                "| {} | {ms:.3} | {:.3} |",
                names.join(" + "),
                ms - previous
            );
            previous = ms;
        }
        self.md.push('\n');
        (self.progress)("simulation steps");
        Ok(())
    }

    /// Simulation cost against the number of master strands (flat grids of fur).
    pub(super) fn simulation_scaling(&mut self) -> Result<()> {
        let counts: &[u32] = if self.quick {
            &[1_000, 4_000]
        } else {
            &[1_000, 10_000, 50_000, 100_000]
        };
        let params = Scene::default_sim();
        let groom = GroomParams::default();
        let mut points = Vec::new();
        let _ = writeln!(
            self.md,
            "## Simulation: cost against strands\n\n{} vertices per strand, default parameters with wind; \
             wall clock per frame, one submission each (about 0.2 ms of it is the submission).\n\n\
             | master strands | ms/frame | ns per strand |\n| --- | --- | --- |",
            groom.vertices_per_strand()
        );
        for &n in counts {
            let side = (f64::from(n).sqrt().round() as u32).max(2) - 1;
            let mesh = Mesh::grid(side, side, 2.0);
            let strands = Strands::grow(&mesh, &groom)?;
            let (gpu, ms) = self.sim_ms_per_frame(&strands, &params)?;
            let count = strands.count();
            let ns = ms * 1e6 / count as f64;
            let case = format!("{count} strands");
            self.row("sim_scaling", case.clone(), "wall_ms_per_frame", ms, "ms");
            self.row("sim_scaling", case.clone(), "gpu_ms_per_frame", gpu, "ms");
            self.row("sim_scaling", case.clone(), "ns_per_strand", ns, "ns");
            let _ = writeln!(self.md, "| {count} | {ms:.3} | {ns:.0} |");
            points.push((count as f64, ns));
            (self.progress)(&case);
        }
        self.md.push('\n');
        self.plots.push((
            "sim_scaling.svg",
            Plot {
                title: "Simulation: cost per strand".into(),
                x_label: "master strands".into(),
                y_label: "ns per strand per frame".into(),
                log_x: true,
                log_y: false,
                series: vec![Series {
                    name: "all steps".into(),
                    points,
                    color: PALETTE[2],
                    line: true,
                }],
                highlight: None,
            },
        ));
        Ok(())
    }
}
