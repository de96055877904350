//! `fur bench`: what each stage costs on this device, what accuracy the settings buy,
//! how cost scales, and what skipping unneeded work saves. Writes `results.csv` (every
//! measurement), `results.md` (tables) and PNG charts.
//!
//! GPU costs come from timestamp queries (medians over repeated frames after warm-up);
//! hair counts from pipeline statistics.

pub mod metrics;
pub mod plot;

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;

use ash::vk;
use glam::{DVec3, Vec3};

use crate::error::{Error, Result};
use crate::gpu::Device;
use crate::render::{FrameSettings, Renderer, RgbaImage};
use crate::scene::{GroomParams, Mesh, Strands};
use crate::session::{FurSession, SceneOptions};
use crate::sim::{CpuSim, GpuSim, Motion, MotionKind, SimParams};
use crate::strand_textures::StrandTextures;
use metrics::{max_stretch, median, pareto_front, position_error, rmse};
use plot::{Plot, Series, PALETTE};

/// How much to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// A small, fast suite (for CI): fewer cases, frames and pixels.
    pub quick: bool,
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub section: &'static str,
    pub case: String,
    pub metric: &'static str,
    pub value: f64,
    pub unit: &'static str,
}

/// Everything the benchmark produced.
pub struct Report {
    pub device: String,
    pub rows: Vec<Row>,
    pub markdown: String,
    pub plots: Vec<(&'static str, Plot)>,
}

impl Report {
    /// Writes `results.csv`, `results.md` and the charts into `dir`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let io = |e: std::io::Error| Error::ImageWrite {
            path: dir.to_path_buf(),
            message: e.to_string(),
        };
        std::fs::create_dir_all(dir).map_err(io)?;
        let mut csv = String::from("section,case,metric,value,unit\n");
        for r in &self.rows {
            let _ = writeln!(
                csv,
                "{},{},{},{},{}",
                r.section,
                csv_field(&r.case),
                r.metric,
                r.value,
                csv_field(r.unit)
            );
        }
        std::fs::write(dir.join("results.csv"), csv).map_err(io)?;
        std::fs::write(dir.join("results.md"), &self.markdown).map_err(io)?;
        for (name, plot) in &self.plots {
            plot.render().write_png(&dir.join(name))?;
        }
        Ok(())
    }
}

/// Quotes a CSV field when it holds a comma or a quote.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The settings being measured for the simulation trade: iterations (local and length
/// alike) and substeps.
const DEFAULT_ITERATIONS: u32 = 2;
const DEFAULT_SUBSTEPS: u32 = 1;

struct Bench<'a> {
    device: &'a Arc<Device>,
    quick: bool,
    rows: Vec<Row>,
    md: String,
    plots: Vec<(&'static str, Plot)>,
    progress: &'a mut dyn FnMut(&str),
}

/// The number of progress ticks `run` reports.
pub fn task_count(options: &BenchOptions) -> u64 {
    let sim_cases = if options.quick { 4 } else { 15 };
    let render_cases = if options.quick { 3 } else { 6 };
    let scaling = if options.quick { 2 } else { 4 };
    1 + sim_cases + render_cases + scaling + 4
}

/// Runs the suite on `device`, calling `progress` once per finished task.
pub fn run(
    device: &Arc<Device>,
    options: &BenchOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    let mut bench = Bench {
        device,
        quick: options.quick,
        rows: Vec::new(),
        md: String::new(),
        plots: Vec::new(),
        progress,
    };
    let name = &device.info().name;
    let _ = writeln!(
        bench.md,
        "# fur bench\n\nDevice: {name}. Medians over repeated frames after warm-up; GPU times from \
         timestamp queries.{}\n",
        if options.quick { " Quick suite." } else { "" }
    );
    bench.stages()?;
    bench.simulation_accuracy()?;
    bench.render_accuracy()?;
    bench.simulation_scaling()?;
    bench.savings()?;
    Ok(Report {
        device: name.clone(),
        rows: bench.rows,
        markdown: bench.md,
        plots: bench.plots,
    })
}

impl Bench<'_> {
    fn row(
        &mut self,
        section: &'static str,
        case: impl Into<String>,
        metric: &'static str,
        value: f64,
        unit: &'static str,
    ) {
        self.rows.push(Row {
            section,
            case: case.into(),
            metric,
            value,
            unit,
        });
    }

    fn extent(&self) -> vk::Extent2D {
        if self.quick {
            vk::Extent2D {
                width: 160,
                height: 90,
            }
        } else {
            vk::Extent2D {
                width: 640,
                height: 360,
            }
        }
    }

    /// (warm-up, measured) frames.
    fn frames(&self) -> (usize, usize) {
        if self.quick {
            (1, 3)
        } else {
            (3, 15)
        }
    }

    fn scene(&self, options: &SceneOptions, sim: SimParams) -> Result<FurSession> {
        let mesh = Mesh::blob();
        let (groom, settings) = options.resolve(&mesh)?;
        let radius = f64::from(mesh.bounds().1);
        let motion = Motion {
            kind: MotionKind::Shake,
            amplitude: 0.25 * radius,
            rate: 1.0,
        };
        FurSession::new(
            self.device,
            mesh,
            &groom,
            sim,
            motion,
            settings,
            self.extent(),
            1,
        )
    }

    fn quick_scene_options(&self) -> SceneOptions {
        SceneOptions {
            density_scale: if self.quick { 0.25 } else { 1.0 },
            ..SceneOptions::default()
        }
    }

    /// Stage costs of the default scene, simulated and drawn every frame.
    fn stages(&mut self) -> Result<()> {
        let sim = SimParams {
            wind: Vec3::new(6.0, 0.0, 2.0),
            ..SimParams::default()
        };
        let mut session = self.scene(&self.quick_scene_options(), sim)?;
        let (warm, measured) = self.frames();
        let per_step: Vec<(String, Vec<f64>)> = Vec::new();
        let (mut sim_ms, mut mesh_ms, mut fur_ms) = (Vec::new(), Vec::new(), Vec::new());
        let mut stats = None;
        for frame in 0..warm + measured {
            let (_, timings) = session.step_and_render()?;
            if frame < warm {
                continue;
            }
            sim_ms.push(timings.simulation_ms);
            mesh_ms.push(timings.render.mesh_ms);
            fur_ms.push(timings.render.fur_ms);
            stats = timings.render.statistics;
        }
        let _ = writeln!(
            self.md,
            "## Stage costs (default scene, {}×{})\n\n| stage | GPU ms (median) |\n| --- | --- |",
            self.extent().width,
            self.extent().height
        );
        for (name, values) in &per_step {
            let m = median(values);
            self.row("stages", name.clone(), "gpu_ms", m, "ms");
            let _ = writeln!(self.md, "| simulation: {name} | {m:.3} |");
        }
        for (name, values) in [
            ("simulation total", &sim_ms),
            ("mesh pass", &mesh_ms),
            ("fur pass", &fur_ms),
        ] {
            let m = median(values);
            self.row("stages", name, "gpu_ms", m, "ms");
            let _ = writeln!(self.md, "| {name} | {m:.3} |");
        }
        let segments = u64::from(session.strands.vertices_per_strand - 1);
        let stats = stats.unwrap_or_default();
        let counts = [
            ("master hairs", session.strands.count() as u64),
            ("patches", stats.patches),
            ("tessellated points", stats.tess_eval_invocations),
            ("hairs drawn", stats.geometry_primitives / (2 * segments)),
            ("hair segments drawn", stats.geometry_primitives / 2),
        ];
        let _ = writeln!(self.md, "\n| count | per frame |\n| --- | --- |");
        for (name, value) in counts {
            self.row("stages", name, "count", value as f64, "count");
            let _ = writeln!(self.md, "| {name} | {value} |");
        }
        self.md.push('\n');
        (self.progress)("stage costs");
        Ok(())
    }

    /// GPU simulation against the converged CPU f64 reference (8× substeps, 64
    /// iterations), over iterations and substeps; cost measured on the default blob.
    fn simulation_accuracy(&mut self) -> Result<()> {
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
        let base = SimParams {
            wind: Vec3::new(6.0, 0.0, 2.0),
            ..SimParams::default()
        };
        let reference = {
            let params = SimParams {
                substeps: 8 * DEFAULT_SUBSTEPS,
                local_iterations: 64,
                length_iterations: 64,
                ..base.clone()
            };
            let mut cpu = CpuSim::<f64>::new(&strands, params, motion.head(0.0));
            for _ in 0..frames {
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
        let blob = Mesh::blob();
        let (blob_groom, _) = SceneOptions::default().resolve(&blob)?;
        let blob_strands = Strands::grow(&blob, &blob_groom)?;

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
                let ms = self.sim_ms_per_frame(&blob_strands, &params)?;
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
                self.row("sim_accuracy", case.clone(), "gpu_ms_per_frame", ms, "ms");
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
             | iterations | substeps | GPU ms/frame | mean error | max error | max stretch | Pareto |\n\
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
            .map(|p| (p.2, p.3, "DEFAULT".to_string()));
        self.plots.push((
            "sim_pareto.png",
            Plot {
                title: "SIMULATION: ERROR VS COST (1,2,4.. ITERATIONS)".into(),
                x_label: "GPU MS PER FRAME".into(),
                y_label: "MEAN ERROR / HAIR LENGTH".into(),
                log_x: true,
                log_y: true,
                series,
                highlight,
            },
        ));
        Ok(())
    }

    /// Median GPU milliseconds per simulated frame for `strands` under `params`.
    fn sim_ms_per_frame(&self, strands: &Strands, params: &SimParams) -> Result<f64> {
        let mut textures = StrandTextures::new(self.device, strands, glam::Mat4::IDENTITY)?;
        let mut gpu = GpuSim::new(self.device, &textures, params.clone())?;
        let motion = Motion {
            kind: MotionKind::Shake,
            amplitude: 0.2,
            rate: 1.0,
        };
        let (warm, measured) = self.frames();
        let mut ms = Vec::new();
        for frame in 0..warm + measured {
            let t = gpu.run_frames(&mut textures, 1, |t| motion.head(t))?;
            if frame >= warm {
                ms.push(t);
            }
        }
        Ok(median(&ms))
    }

    /// One render of `settings` on `mesh`: (image, median fur ms, hairs drawn).
    fn render_once(
        &self,
        mesh: &Mesh,
        groom: &GroomParams,
        settings: &FrameSettings,
    ) -> Result<(RgbaImage, f64, u64)> {
        let strands = Strands::grow(mesh, groom)?;
        let textures = StrandTextures::new(self.device, &strands, settings.head)?;
        let mut renderer = Renderer::new(self.device, mesh, &textures, self.extent(), 1)?;
        let (warm, measured) = self.frames();
        let mut ms = Vec::new();
        let mut last = None;
        for frame in 0..warm + measured {
            let (image, report) = renderer.render(&textures, settings)?;
            if frame >= warm {
                ms.push(report.fur_ms);
            }
            let hairs = report.statistics.map_or(0, |s| {
                s.geometry_primitives / (2 * u64::from(groom.segments))
            });
            last = Some((image, hairs));
        }
        let (image, hairs) = last.expect("at least one frame");
        Ok((image, median(&ms), hairs))
    }

    /// Image error of lower densities against a 4× density reference render.
    fn render_accuracy(&mut self) -> Result<()> {
        let scales: &[f32] = if self.quick {
            &[0.25, 1.0]
        } else {
            &[0.125, 0.25, 0.5, 1.0, 2.0]
        };
        let mesh = Mesh::blob();
        let base = self.quick_scene_options();
        let reference_options = SceneOptions {
            density_scale: base.density_scale * 4.0,
            ..base.clone()
        };
        let (groom, reference_settings) = reference_options.resolve(&mesh)?;
        let (reference, reference_ms, reference_hairs) =
            self.render_once(&mesh, &groom, &reference_settings)?;
        (self.progress)("render reference");
        let mut points = Vec::new();
        for &scale in scales {
            let options = SceneOptions {
                density_scale: base.density_scale * scale,
                ..base.clone()
            };
            let (_, settings) = options.resolve(&mesh)?;
            let (image, ms, hairs) = self.render_once(&mesh, &groom, &settings)?;
            let error = rmse(&image, &reference);
            let case = format!("density x{scale}");
            self.row("render_accuracy", case.clone(), "rmse", error, "0..1");
            self.row("render_accuracy", case.clone(), "fur_pass_ms", ms, "ms");
            self.row(
                "render_accuracy",
                case.clone(),
                "hairs_drawn",
                hairs as f64,
                "count",
            );
            self.row(
                "render_scaling",
                case.clone(),
                "ns_per_hair",
                ms * 1e6 / hairs.max(1) as f64,
                "ns",
            );
            points.push((scale, ms, error, hairs));
            (self.progress)(&case);
        }
        let front = pareto_front(&points.iter().map(|p| (p.1, p.2)).collect::<Vec<_>>());
        let _ = writeln!(
            self.md,
            "## Rendering: image error against cost\n\nRMSE (0..1, RGB) against a render at 4× the \
             density ({reference_hairs} hairs, fur pass {reference_ms:.2} ms), same camera, {}×{}.\n\n\
             | density | hairs drawn | fur pass ms | ns per hair | RMSE | Pareto |\n| --- | --- | --- | --- | --- | --- |",
            self.extent().width,
            self.extent().height
        );
        for (p, on_front) in points.iter().zip(&front) {
            self.row(
                "render_accuracy",
                format!("density x{}", p.0),
                "pareto",
                f64::from(u8::from(*on_front)),
                "bool",
            );
            let _ = writeln!(
                self.md,
                "| ×{}{} | {} | {:.2} | {:.0} | {:.4} | {} |",
                p.0,
                if p.0 == 1.0 { " (default)" } else { "" },
                p.3,
                p.1,
                p.1 * 1e6 / p.3.max(1) as f64,
                p.2,
                if *on_front { "yes" } else { "" }
            );
        }
        self.md.push('\n');
        self.plots.push((
            "render_pareto.png",
            Plot {
                title: "RENDERING: IMAGE ERROR VS FUR PASS COST".into(),
                x_label: "FUR PASS GPU MS".into(),
                y_label: "RMSE VS 4X DENSITY".into(),
                log_x: true,
                log_y: false,
                series: vec![Series {
                    name: "DENSITY SCALES".into(),
                    points: points.iter().map(|p| (p.1, p.2)).collect(),
                    color: PALETTE[0],
                    line: true,
                }],
                highlight: points
                    .iter()
                    .find(|p| p.0 == 1.0)
                    .map(|p| (p.1, p.2, "DEFAULT".into())),
            },
        ));
        self.plots.push((
            "render_scaling.png",
            Plot {
                title: "RENDERING: COST PER HAIR".into(),
                x_label: "HAIRS DRAWN".into(),
                y_label: "NS PER HAIR".into(),
                log_x: true,
                log_y: false,
                series: vec![Series {
                    name: "FUR PASS".into(),
                    points: points
                        .iter()
                        .map(|p| (p.3 as f64, p.1 * 1e6 / p.3.max(1) as f64))
                        .collect(),
                    color: PALETTE[1],
                    line: true,
                }],
                highlight: None,
            },
        ));
        Ok(())
    }

    /// Simulation cost against the number of master strands (flat grids of fur).
    fn simulation_scaling(&mut self) -> Result<()> {
        let counts: &[u32] = if self.quick {
            &[1_000, 4_000]
        } else {
            &[1_000, 10_000, 50_000, 100_000]
        };
        let params = SimParams {
            wind: Vec3::new(6.0, 0.0, 2.0),
            ..SimParams::default()
        };
        let groom = GroomParams::default();
        let mut points = Vec::new();
        let _ = writeln!(
            self.md,
            "## Simulation: cost against strands\n\n{} vertices per strand, default parameters with wind.\n\n\
             | master strands | GPU ms/frame | ns per strand |\n| --- | --- | --- |",
            groom.vertices_per_strand()
        );
        for &n in counts {
            let side = (f64::from(n).sqrt().round() as u32).max(2) - 1;
            let mesh = Mesh::grid(side, side, 2.0);
            let strands = Strands::grow(&mesh, &groom)?;
            let ms = self.sim_ms_per_frame(&strands, &params)?;
            let count = strands.count();
            let ns = ms * 1e6 / count as f64;
            let case = format!("{count} strands");
            self.row("sim_scaling", case.clone(), "gpu_ms_per_frame", ms, "ms");
            self.row("sim_scaling", case.clone(), "ns_per_strand", ns, "ns");
            let _ = writeln!(self.md, "| {count} | {ms:.3} | {ns:.1} |");
            points.push((count as f64, ns));
            (self.progress)(&case);
        }
        self.md.push('\n');
        self.plots.push((
            "sim_scaling.png",
            Plot {
                title: "SIMULATION: COST PER STRAND".into(),
                x_label: "MASTER STRANDS".into(),
                y_label: "NS PER STRAND PER FRAME".into(),
                log_x: true,
                log_y: false,
                series: vec![Series {
                    name: "ALL STEPS".into(),
                    points,
                    color: PALETTE[2],
                    line: true,
                }],
                highlight: None,
            },
        ));
        Ok(())
    }

    /// What skipping unneeded work saves: before/after ratios.
    fn savings(&mut self) -> Result<()> {
        let _ = writeln!(
            self.md,
            "## Work the scene does not need\n\n| saving | with the work | without | ratio |\n| --- | --- | --- | --- |"
        );
        let blob = Mesh::blob();
        let options = self.quick_scene_options();
        let (groom, settings) = options.resolve(&blob)?;
        let strands = Strands::grow(&blob, &groom)?;
        let full = SimParams {
            wind: Vec3::new(6.0, 0.0, 2.0),
            ..SimParams::default()
        };
        let sim_cases = [
            (
                "wind off: no wind dispatch",
                SimParams {
                    wind: Vec3::ZERO,
                    ..full.clone()
                },
            ),
            (
                "S_G = 0: no global-shape dispatch",
                SimParams {
                    global_stiffness: 0.0,
                    ..full.clone()
                },
            ),
        ];
        let with_all = self.sim_ms_per_frame(&strands, &full)?;
        for (name, params) in sim_cases {
            let without = self.sim_ms_per_frame(&strands, &params)?;
            self.saving(name, with_all, without, "simulation ms/frame");
            (self.progress)(name);
        }
        let (_, culled_ms, culled_hairs) = self.render_once(&blob, &groom, &settings)?;
        let mut no_cull = settings.clone();
        no_cull.style.cull = false;
        let (_, all_ms, all_hairs) = self.render_once(&blob, &groom, &no_cull)?;
        self.saving(
            "culling back-facing and off-screen triangles",
            all_ms,
            culled_ms,
            "fur pass ms",
        );
        self.saving(
            "culling: hairs drawn",
            all_hairs as f64,
            culled_hairs as f64,
            "hairs",
        );
        (self.progress)("culling");
        let mut far = settings.clone();
        far.camera.distance *= 4.0;
        let (_, lod_ms, lod_hairs) = self.render_once(&blob, &groom, &far)?;
        far.style.lod_distance = 1e9;
        let (_, full_ms, full_hairs) = self.render_once(&blob, &groom, &far)?;
        self.saving(
            "distance LOD at 4× the distance",
            full_ms,
            lod_ms,
            "fur pass ms",
        );
        self.saving(
            "distance LOD: hairs drawn",
            full_hairs as f64,
            lod_hairs as f64,
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
