//! `fur`: renders and simulates fur on any Vulkan device with tessellation and geometry
//! shaders. `fur` with no subcommand renders the default scene to `fur.png`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context as _};
use ash::vk;
use clap::{Args, Parser, Subcommand};
use fur::scene::Mesh;
use fur::session::{FurSession, SceneOptions};
use fur::sim::{Motion, MotionKind, SimParams};
use glam::Vec3;

/// Real-time fur rendering and simulation on Vulkan: master hairs grown from a mesh,
/// simulated in compute shaders (Han & Harada 2012), interpolated by tessellation,
/// drawn by a geometry shader and lit with Kajiya–Kay.
///
/// With no subcommand, `fur` runs `fur render` with the given options.
#[derive(Parser)]
#[command(version, about, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    render: RenderArgs,
}

#[derive(Subcommand)]
enum Command {
    /// Render the scene to a PNG, or simulate it and render a PNG sequence.
    Render(RenderArgs),
    /// Open a window: live simulation, orbit camera, parameter panel, stage timings.
    View(ViewArgs),
    /// Measure stage costs, the speed/accuracy trade, scaling and savings on this device;
    /// writes results.csv, results.md and PNG charts.
    Bench {
        /// A small suite that finishes in seconds (for CI).
        #[arg(long)]
        quick: bool,
        /// Output folder.
        #[arg(long, default_value = "bench")]
        out_dir: PathBuf,
        /// Enable the Khronos validation layer (slows everything down).
        #[arg(long)]
        validate: bool,
    },
    /// Write the built-in default model as an OBJ file.
    ExportModel {
        /// Where to write it.
        #[arg(default_value = "assets/blob.obj")]
        out: PathBuf,
    },
}

#[derive(Args, Clone)]
struct ViewArgs {
    /// OBJ model to grow fur on (default: the built-in blob).
    #[arg(long)]
    model: Option<PathBuf>,
    /// Initial window width in pixels.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Initial window height in pixels.
    #[arg(long, default_value_t = 720)]
    height: u32,
    #[command(flatten)]
    groom: GroomArgs,
    #[command(flatten)]
    sim: SimArgs,
    /// Present without waiting for vertical blank (mailbox or immediate when available).
    #[arg(long)]
    no_vsync: bool,
    /// Close after this many frames.
    #[arg(long)]
    frames: Option<u64>,
    /// Scripted input, e.g. "10:resize=320x240; 30:orbit=40,-10; 50:wind=on; 90:screenshot=shot.png".
    #[arg(long, default_value = "")]
    script: String,
    /// Folder for screenshots taken with F12 or P.
    #[arg(long, default_value = ".")]
    screenshot_dir: PathBuf,
    /// Enable the Khronos validation layer; any validation message fails the run.
    #[arg(long)]
    validate: bool,
}

#[derive(Args, Clone)]
struct RenderArgs {
    /// OBJ model to grow fur on (default: the built-in blob, see `fur export-model`).
    #[arg(long)]
    model: Option<PathBuf>,
    /// Output PNG of a single frame.
    #[arg(long, default_value = "fur.png")]
    out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Camera orbit angle around the vertical axis, degrees.
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true)]
    yaw: f32,
    /// Camera elevation, degrees.
    #[arg(long, default_value_t = 15.0, allow_negative_numbers = true)]
    pitch: f32,
    /// Camera distance as a multiple of the model's bounding radius.
    #[arg(long, default_value_t = 2.6)]
    distance: f32,

    #[command(flatten)]
    groom: GroomArgs,
    #[command(flatten)]
    sim: SimArgs,

    /// Simulate and render this many frames (1/60 s each) into --out-dir.
    #[arg(long, default_value_t = 1)]
    frames: u32,
    /// Folder for the PNG sequence (frame_0000.png, …); implies simulation.
    #[arg(long)]
    out_dir: Option<PathBuf>,
    /// Scripted head motion: still, shake, spin or nod.
    #[arg(long, default_value = "shake")]
    motion: MotionKind,
    /// Motion amplitude: fraction of the model radius for shake, degrees for nod.
    #[arg(long, default_value_t = 0.25)]
    amplitude: f64,
    /// Motion rate: Hz for shake and nod, turns per second for spin.
    #[arg(long, default_value_t = 1.0)]
    rate: f64,

    /// Enable the Khronos validation layer; any validation message fails the run.
    #[arg(long)]
    validate: bool,
}

/// Groom and density.
#[derive(Args, Clone)]
struct GroomArgs {
    /// Hair length as a fraction of the model's bounding radius.
    #[arg(long, default_value_t = 0.2)]
    hair_length: f32,
    /// Segments per master hair (1..=63).
    #[arg(long, default_value_t = 16)]
    segments: u32,
    /// Multiplies the interpolated-hair density.
    #[arg(long, default_value_t = 1.0)]
    density_scale: f32,
    /// Comb strength (0 = hairs stand along the normals).
    #[arg(long, default_value_t = 0.9)]
    comb: f32,
    /// Curl radius as a fraction of the segment length.
    #[arg(long, default_value_t = 0.0)]
    curl: f32,
}

/// Simulation parameters (see `SimParams` for units and ranges).
#[derive(Args, Clone)]
struct SimArgs {
    /// Substeps per frame (1..=64).
    #[arg(long, default_value_t = 1)]
    substeps: u32,
    /// Gravity in m/s², pointing down.
    #[arg(long, default_value_t = 9.82, allow_negative_numbers = true)]
    gravity: f32,
    /// Fraction of velocity lost per 1/60 s (0..1).
    #[arg(long, default_value_t = 0.08)]
    damping: f32,
    /// Global shape stiffness S_G (0..1).
    #[arg(long, default_value_t = 0.2)]
    global_stiffness: f32,
    /// Fraction of each strand the global constraint covers (0..1).
    #[arg(long, default_value_t = 1.0)]
    global_range: f32,
    /// Local shape stiffness S_L (0..1).
    #[arg(long, default_value_t = 0.9)]
    local_stiffness: f32,
    /// Local shape passes per substep (0..=64).
    #[arg(long, default_value_t = 2)]
    local_iterations: u32,
    /// Edge-length passes per substep (0..=64).
    #[arg(long, default_value_t = 2)]
    length_iterations: u32,
    /// Wind vector "x,y,z" in m/s² (0,0,0 = no wind).
    #[arg(long, default_value = "6,0,2", value_parser = parse_vec3)]
    wind: Vec3,
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let parts: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected x,y,z: {e}"))?;
    match parts[..] {
        [x, y, z] => Ok(Vec3::new(x, y, z)),
        _ => Err(format!(
            "expected three comma-separated numbers, got {}",
            parts.len()
        )),
    }
}

impl SimArgs {
    fn params(&self) -> SimParams {
        SimParams {
            substeps: self.substeps,
            gravity: Vec3::new(0.0, -self.gravity, 0.0),
            damping: self.damping,
            global_stiffness: self.global_stiffness,
            global_range: self.global_range,
            local_stiffness: self.local_stiffness,
            local_iterations: self.local_iterations,
            length_iterations: self.length_iterations,
            wind: self.wind,
            ..SimParams::default()
        }
    }
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::View(args)) => view(args),
        Some(Command::ExportModel { out }) => export_model(&out),
        Some(Command::Bench {
            quick,
            out_dir,
            validate,
        }) => bench(quick, &out_dir, validate),
        None => render(&cli.render),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn bench(quick: bool, out_dir: &Path, validate: bool) -> anyhow::Result<()> {
    let device = fur::gpu::headless(validate)?;
    let options = fur::bench::BenchOptions { quick };
    let bar = indicatif::ProgressBar::new(fur::bench::task_count(&options)).with_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let report = fur::bench::run(&device, &options, &mut |task| {
        bar.set_message(task.to_string());
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    report.write(out_dir)?;
    println!("{}", report.markdown);
    println!(
        "wrote {} measurements to {}",
        report.rows.len(),
        out_dir.display()
    );
    device.instance().check_validation()?;
    Ok(())
}

fn view(args: ViewArgs) -> anyhow::Result<()> {
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    let options = fur::viewer::ViewerOptions {
        model: args.model,
        scene: SceneOptions {
            hair_length: args.groom.hair_length,
            segments: args.groom.segments,
            comb: args.groom.comb,
            curl: args.groom.curl,
            density_scale: args.groom.density_scale,
            ..SceneOptions::default()
        },
        sim: args.sim.params(),
        vsync: !args.no_vsync,
        frames: args.frames,
        validate: args.validate,
        width: args.width,
        height: args.height,
        script: fur::viewer::Script::parse(&args.script)?,
        screenshot_dir: args.screenshot_dir,
    };
    options.sim.validate()?;
    fur::viewer::run(options)?;
    Ok(())
}

fn export_model(out: &Path) -> anyhow::Result<()> {
    Mesh::blob().write_obj(out)?;
    println!("wrote {}", out.display());
    Ok(())
}

fn render(args: &RenderArgs) -> anyhow::Result<()> {
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    let mesh = match &args.model {
        Some(path) => Mesh::load_obj(path)?,
        None => Mesh::blob(),
    };
    let (_, radius) = mesh.bounds();
    let scene = SceneOptions {
        hair_length: args.groom.hair_length,
        segments: args.groom.segments,
        comb: args.groom.comb,
        curl: args.groom.curl,
        density_scale: args.groom.density_scale,
        yaw_deg: args.yaw,
        pitch_deg: args.pitch,
        distance: args.distance,
    };
    let (groom, settings) = scene.resolve(&mesh)?;
    let simulate = args.frames > 1 || args.out_dir.is_some();
    let motion = Motion {
        kind: if simulate {
            args.motion
        } else {
            MotionKind::Still
        },
        amplitude: match args.motion {
            MotionKind::Shake => args.amplitude * f64::from(radius),
            _ => args.amplitude,
        },
        rate: args.rate,
    };
    let extent = vk::Extent2D {
        width: args.width,
        height: args.height,
    };

    let device = fur::gpu::headless(args.validate)?;
    let mut session = FurSession::new(
        &device,
        mesh,
        &groom,
        args.sim.params(),
        motion,
        settings,
        extent,
        1,
    )?;
    let masters = session.strands.count();
    let groom_segments = session.strands.vertices_per_strand - 1;
    if simulate {
        let dir = args
            .out_dir
            .clone()
            .unwrap_or_else(|| PathBuf::from("frames"));
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        let bar = indicatif::ProgressBar::new(u64::from(args.frames)).with_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} frames {elapsed} (eta {eta}) {msg}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        let mut sim_ms = Vec::new();
        for frame in 0..args.frames {
            let (image, timings) = session.step_and_render()?;
            image.write_png(&dir.join(format!("frame_{frame:04}.png")))?;
            sim_ms.push(timings.simulation_ms);
            bar.set_message(format!(
                "sim {:.2} ms, fur {:.1} ms",
                timings.simulation_ms, timings.render.fur_ms
            ));
            bar.inc(1);
        }
        bar.finish();
        sim_ms.sort_by(f64::total_cmp);
        println!(
            "wrote {} frames to {}: {masters} master hairs; GPU simulation median {:.3} ms per frame",
            args.frames,
            dir.display(),
            sim_ms[sim_ms.len() / 2]
        );
    } else {
        let start = Instant::now();
        let (image, report) = session.render()?;
        let elapsed = start.elapsed();
        image.write_png(&args.out)?;
        let hairs = report
            .statistics
            .map(|s| {
                let segments = u64::from(groom_segments);
                format!(
                    ", {} tessellated points, {} hairs drawn (corner and edge points shared by two \
                     triangles are drawn once)",
                    s.tess_eval_invocations,
                    s.geometry_primitives / (2 * segments)
                )
            })
            .unwrap_or_default();
        println!(
            "wrote {} ({}×{}): {masters} master hairs{hairs}; frame {:.1} ms (GPU: mesh {:.2} ms, fur {:.2} ms)",
            args.out.display(),
            args.width,
            args.height,
            elapsed.as_secs_f64() * 1e3,
            report.mesh_ms,
            report.fur_ms,
        );
    }
    drop(session);
    device.instance().check_validation()?;
    Ok(())
}
