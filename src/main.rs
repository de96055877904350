//! `fur`: renders and simulates fur on any Vulkan device with tessellation and geometry
//! shaders. `fur` with no subcommand renders the default scene to `fur.png`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

mod args;
mod export_command;
mod groom_command;
mod render_command;

use anyhow::{bail, Context as _};
use args::{DeviceArgs, SceneArgs};
use ash::vk;
use clap::{Args, Parser, Subcommand};
use fur_core::scene::ModelSpec;
use fur_core::sim::MotionKind;
use fur_gpu::session::{FurSession, SessionSetup};

/// Real-time fur rendering and simulation on Vulkan: master hairs grown from a mesh,
/// simulated in compute shaders (Han & Harada 2012), interpolated by tessellation,
/// drawn by a geometry shader (strands rasterised in compute or by the fixed-function
/// rasteriser) and lit with the Marschner model (Kajiya–Kay, the seed's, one flag away).
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
    /// Write one frame exactly as drawn (every hair the geometry stage emits, the posed
    /// body, camera, lights and the fibre's parameters) as USD text for a path tracer
    /// (tools/reference), and the PNG fur draws of it (--out); --frames N exports the
    /// Nth simulated frame.
    ExportFrame(export_command::ExportArgs),
    /// Write the master hairs as guide curves — USD text (.usda) or cyHair (.hair) — at
    /// rest in the model's space (ready for `--groom`), or at the Nth simulated frame
    /// (--frames N) as drawn.
    ExportGroom(groom_command::GroomArgs),
    /// Open a window: live simulation, orbit camera, parameter panel, stage timings.
    View(ViewArgs),
    /// Measure stage costs, the speed/accuracy trade, scaling and savings on this device;
    /// writes results.csv, results.md and SVG charts.
    Bench(BenchArgs),
    /// List every setting of a scene (section and key in a scene file, flag, values,
    /// units, defaults, meaning) as Markdown tables.
    Settings {
        /// Put the tables into this Markdown file between its `<!-- BEGIN fur settings
        /// -->` and `<!-- END fur settings -->` lines instead, e.g. docs/scene-files.md.
        #[arg(long, allow_hyphen_values = true)]
        write_docs: Option<PathBuf>,
    },
    /// List the Vulkan devices (index, type, Vulkan version, name, driver, whether fur
    /// can use it) and mark the one fur uses by default; `--device` chooses another.
    Devices {
        /// Mark the device this choice names instead of the default (or refuse it).
        #[command(flatten)]
        device: DeviceArgs,
    },
    /// Write a built-in model as an OBJ file, or as binary glTF (`.glb`: with its
    /// skeleton, skin and clips for the critter).
    ExportModel {
        /// Where to write it; a name ending in `.glb` writes glTF, anything else OBJ.
        #[arg(default_value = "assets/blob.obj")]
        out: PathBuf,
        /// Which built-in model: blob, sphere or critter.
        #[arg(long, default_value = "blob", allow_hyphen_values = true)]
        model: ModelSpec,
    },
}

#[derive(Args, Clone)]
struct BenchArgs {
    #[command(flatten)]
    device: DeviceArgs,
    /// A small suite that finishes in seconds (for CI).
    #[arg(long)]
    quick: bool,
    /// Run only these sections (comma-separated); `fur bench --list` names them.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    only: Vec<String>,
    /// List the sections and exit.
    #[arg(long)]
    list: bool,
    /// Measure this scene file in the frame and render-quality sections instead of
    /// the blob and the original's sphere.
    #[arg(long, allow_hyphen_values = true)]
    scene: Option<PathBuf>,
    /// Image width of the frame and quality measurements in pixels [1280; quick
    /// suite: 160].
    #[arg(long, allow_negative_numbers = true)]
    width: Option<u32>,
    /// Image height of the frame and quality measurements in pixels [720; quick
    /// suite: 90].
    #[arg(long, allow_negative_numbers = true)]
    height: Option<u32>,
    /// Output folder.
    #[arg(long, default_value = "bench", allow_hyphen_values = true)]
    out_dir: PathBuf,
    /// Enable the Khronos validation layer (slows everything down).
    #[arg(long)]
    validate: bool,
    /// Also put the tables into this Markdown file between its `<!-- BEGIN fur
    /// bench -->` and `<!-- END fur bench -->` lines (a full run only), e.g.
    /// docs/benchmark.md.
    #[arg(long, allow_hyphen_values = true)]
    write_docs: Option<PathBuf>,
}

#[derive(Args, Clone)]
struct ViewArgs {
    /// A TOML scene file (see assets/scenes/); options given here override it.
    scene_file: Option<PathBuf>,
    #[command(flatten)]
    scene: SceneArgs,
    /// Write the panel's state as a scene file when the viewer closes (the panel's
    /// "save scene" button writes it at once).
    #[arg(long, allow_hyphen_values = true)]
    save_scene: Option<PathBuf>,
    /// Hold this frame rate by lowering the drawing quality while the view moves (the
    /// quality ladder); back at full quality within 2 s of the last input; 0 = off,
    /// always the scene's drawing [30].
    #[arg(long, allow_negative_numbers = true)]
    target_fps: Option<f64>,
    /// Present without waiting for vertical blank (mailbox or immediate when available).
    #[arg(long)]
    no_vsync: bool,
    /// Close after this many frames.
    #[arg(long, allow_negative_numbers = true)]
    frames: Option<u64>,
    /// Scripted input, e.g. "10:resize=320x240; 30:orbit=40,-10; 50:wind=on; 60:pause=on;
    /// 70:key=n; 80:set=render.nearest=4; 90:screenshot=shot.png" (`key=` presses a
    /// character key: `n` steps the paused simulation once, `1`…`8` choose a stage view;
    /// `set=SECTION.KEY=VALUE` changes a scene-file setting as the panel does).
    #[arg(long, default_value = "", allow_hyphen_values = true)]
    script: String,
    /// Folder for screenshots taken with F12 or P.
    #[arg(long, default_value = ".", allow_hyphen_values = true)]
    screenshot_dir: PathBuf,
    /// Enable the Khronos validation layer; any validation message fails the run.
    #[arg(long)]
    validate: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

#[derive(Args, Clone)]
struct RenderArgs {
    /// A TOML scene file (see assets/scenes/); options given here override it.
    scene_file: Option<PathBuf>,
    #[command(flatten)]
    scene: SceneArgs,
    /// Output PNG of a single frame.
    #[arg(long, default_value = "fur.png", allow_hyphen_values = true)]
    out: PathBuf,
    /// Simulate and render this many frames (1/60 s each) into --out-dir.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    frames: u32,
    /// Folder for the PNG sequence (frame_0000.png, …); implies simulation.
    #[arg(long, allow_hyphen_values = true)]
    out_dir: Option<PathBuf>,
    /// Hold a sequence's frames under this many milliseconds by lowering the drawing
    /// quality (the viewer's quality ladder), 0 < ms ≤ 60000; the rung chosen is printed
    /// [off].
    #[arg(long, allow_negative_numbers = true)]
    budget_ms: Option<f64>,
    /// Enable the Khronos validation layer; any validation message fails the run.
    #[arg(long)]
    validate: bool,
    #[command(flatten)]
    device: DeviceArgs,
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    // Ctrl-C asks long runs to stop between frames (`fur_core::interrupt`); a second one
    // while the first is being honoured exits at once, with status 130. Failing to
    // install (another handler is set) leaves the default behaviour.
    let _ = ctrlc::set_handler(|| {
        if fur_core::interrupt::request() {
            std::process::exit(130);
        }
    });
    let result = match cli.command {
        Some(Command::Render(args)) => render_command::render(&args),
        Some(Command::View(args)) => view(args),
        Some(Command::ExportFrame(args)) => export_command::export_frame(&args),
        Some(Command::ExportGroom(args)) => groom_command::export_groom(&args),
        Some(Command::ExportModel { out, model }) => export_model(&out, &model),
        Some(Command::Devices { device }) => devices(&device),
        Some(Command::Settings { write_docs }) => settings(write_docs.as_deref()),
        Some(Command::Bench(args)) => bench(&args),
        None => render_command::render(&cli.render),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if interrupted(&e) => {
            // Everything was dropped on the way out: the device is idle.
            eprintln!("interrupted");
            ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            let chosen_by_env = std::env::var(args::DEVICE_ENV).is_ok_and(|v| !v.trim().is_empty());
            if chosen_by_env && matches!(e.downcast_ref(), Some(fur::Error::DeviceChoice(_))) {
                eprintln!(
                    "note: {} chooses the device where --device is not given",
                    args::DEVICE_ENV
                );
            }
            ExitCode::FAILURE
        }
    }
}

fn bench(args: &BenchArgs) -> anyhow::Result<()> {
    let BenchArgs {
        device,
        quick,
        only,
        list,
        scene,
        width,
        height,
        out_dir,
        validate,
        write_docs,
    } = args;
    let (quick, list, validate) = (*quick, *list, *validate);
    let (scene, width, height) = (scene.as_deref(), *width, *height);
    let write_docs = write_docs.as_deref();
    if list {
        for section in fur::bench::Section::ALL {
            println!("{:<16} {}", section.name(), section.about());
        }
        return Ok(());
    }
    let sections = fur::bench::Section::parse_list(only)?;
    if let Some(docs) = write_docs {
        if quick || scene.is_some() || width.or(height).is_some() {
            bail!(
                "--write-docs {} takes a run at the benchmark's own settings (no --quick, \
                 --scene, --width or --height): the document's figures all come from one run",
                docs.display()
            );
        }
        fur::bench::check_docs(docs, &sections)?;
    }
    let size = match (width, height) {
        (None, None) => None,
        (Some(w), Some(h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => Some((w, h)),
        (Some(_), Some(_)) => bail!("--width and --height must be 1..=16384 pixels"),
        _ => bail!("--width and --height go together"),
    };
    fur_core::files::check_output_dir(out_dir)?;
    let device = device.headless(validate)?;
    let scene = match scene {
        Some(path) => {
            let name = path
                .file_stem()
                .map_or("scene".into(), |n| n.to_string_lossy().into_owned());
            Some((name, fur_core::scene_file::Scene::load(Some(path), None)?))
        }
        None => None,
    };
    let root = std::env::current_dir().context("the current folder")?;
    let options = fur::bench::BenchOptions {
        quick,
        sections: sections.clone(),
        scene,
        size,
        work: Some((out_dir.to_path_buf(), root)),
    };
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
    if let Some(docs) = write_docs {
        fur::bench::write_docs(docs, &sections, &report.markdown)?;
        eprintln!("wrote the tables into {}", docs.display());
    }
    println!("{}", report.markdown);
    println!(
        "wrote {} measurements to {}",
        report.rows.len(),
        out_dir.display()
    );
    fur_gpu::gpu::shut_down(device)?;
    Ok(())
}

fn view(args: ViewArgs) -> anyhow::Result<()> {
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    let script = fur::viewer::Script::parse(&args.script)?;
    if let Some(frames) = args.frames {
        script.check_within(frames)?;
    }
    let scene = args::scene(args.scene_file.as_deref(), &args.scene)?;
    scene.sim.validate()?;
    let target_fps = args.target_fps.unwrap_or(fur::viewer::DEFAULT_TARGET_FPS);
    if !(target_fps.is_finite() && (0.0..=1000.0).contains(&target_fps)) {
        bail!("--target-fps must be 0 (off) to 1000 frames per second, got {target_fps}");
    }
    if let Some(path) = &args.save_scene {
        fur_core::files::check_output_file(path)?;
    }
    fur_core::files::check_output_dir(&args.screenshot_dir)?;
    let options = fur::viewer::ViewerOptions {
        model: scene.model.clone(),
        scene: scene.options.clone(),
        sim: scene.sim.clone(),
        motion: scene.motion,
        animation: scene.animation.clone(),
        target_fps,
        vsync: !args.no_vsync,
        frames: args.frames,
        validate: args.validate,
        device: args.device.choice(),
        width: scene.width,
        height: scene.height,
        script,
        screenshot_dir: args.screenshot_dir,
        save_scene: args.save_scene,
    };
    fur::viewer::run(options)?;
    Ok(())
}

fn settings(write_docs: Option<&Path>) -> anyhow::Result<()> {
    use fur_core::scene_file::docs;
    let tables = docs::markdown();
    match write_docs {
        Some(path) => {
            fur_core::files::write_region(path, docs::BEGIN, docs::END, &tables)?;
            eprintln!("wrote the settings into {}", path.display());
        }
        None => println!("{tables}"),
    }
    Ok(())
}

fn devices(device: &DeviceArgs) -> anyhow::Result<()> {
    let list = fur_gpu::gpu::list_devices()?
        .with_choice(device.choice().as_deref())
        .map_err(fur::Error::DeviceChoice)?;
    println!("{list}");
    Ok(())
}

fn export_model(out: &Path, model: &ModelSpec) -> anyhow::Result<()> {
    if let ModelSpec::File(path) = model {
        bail!(
            "--model names a built-in model ({}), not a file: {}",
            ModelSpec::BUILT_IN.join(", "),
            path.display()
        );
    }
    fur_core::files::check_output_file(out)?;
    let glb = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (mesh, rig, _) = model.load_body()?;
    if glb {
        let bytes = fur_core::scene::write_glb(&mesh, rig.as_ref())?;
        fur_core::files::write_output(out, &bytes, "write the model to")?;
    } else {
        if rig.is_some() {
            eprintln!(
                "warning: OBJ keeps the rest pose only; write `.glb` to keep the skeleton, \
                 skin and clips"
            );
        }
        mesh.write_obj(out)?;
    }
    let summary = format!("wrote {}", out.display());
    if out.as_os_str() == fur_core::files::STDOUT {
        eprintln!("{summary}");
    } else {
        println!("{summary}");
    }
    Ok(())
}

/// Whether the run stopped because the user asked it to: the core's or the GPU layer's
/// `Interrupted`, anywhere in the error's chain.
fn interrupted(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        matches!(
            cause.downcast_ref(),
            Some(fur_gpu::error::CoreError::Interrupted)
        ) || cause.downcast_ref().is_some_and(fur::Error::is_interrupted)
    })
}
