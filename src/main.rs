//! `fur`: renders (and simulates) fur headless on any Vulkan device.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use ash::vk;
use clap::{Args, Parser, Subcommand};
use fur::render::{FrameSettings, Renderer};
use fur::scene::{Camera, GroomParams, Mesh, Strands};
use fur::strand_textures::StrandTextures;

/// Real-time fur rendering and simulation on Vulkan: master hairs grown from a mesh,
/// interpolated by tessellation, drawn by a geometry shader, lit with Kajiya–Kay.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render the scene to a PNG (the default model unless --model is given).
    Render(RenderArgs),
    /// Write the built-in default model as an OBJ file.
    ExportModel {
        /// Where to write it.
        #[arg(default_value = "assets/blob.obj")]
        out: PathBuf,
    },
}

#[derive(Args, Clone)]
struct RenderArgs {
    /// OBJ model to grow fur on (default: the built-in blob).
    #[arg(long)]
    model: Option<PathBuf>,
    /// Output PNG.
    #[arg(long, default_value = "fur.png")]
    out: PathBuf,
    #[arg(long, default_value_t = 1280)]
    width: u32,
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
    /// Enable the Khronos validation layer; any validation message fails the run.
    #[arg(long)]
    validate: bool,
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::ExportModel { out }) => Mesh::blob()
            .write_obj(&out)
            .map(|_| println!("wrote {}", out.display()))
            .map_err(Into::into),
        None => {
            use clap::CommandFactory;
            let _ = Cli::command().print_help();
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn load_mesh(model: Option<&PathBuf>) -> anyhow::Result<Mesh> {
    Ok(match model {
        Some(path) => Mesh::load_obj(path)?,
        None => Mesh::blob(),
    })
}

fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let mesh = load_mesh(args.model.as_ref())?;
    let (center, radius) = mesh.bounds();
    if !(args.hair_length.is_finite() && args.hair_length > 0.0) {
        anyhow::bail!("--hair-length must be positive, got {}", args.hair_length);
    }
    if !(args.distance.is_finite() && args.distance > 0.0) {
        anyhow::bail!("--distance must be positive, got {}", args.distance);
    }
    if !(args.density_scale.is_finite() && args.density_scale > 0.0) {
        anyhow::bail!(
            "--density-scale must be positive, got {}",
            args.density_scale
        );
    }
    let groom = GroomParams {
        segments: args.segments,
        segment_length: args.hair_length * radius / args.segments.max(1) as f32,
        comb_strength: args.comb,
        curl: args.curl,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom)?;
    let mut settings = FrameSettings {
        camera: Camera {
            target: center,
            yaw_deg: args.yaw,
            pitch_deg: args.pitch,
            distance: args.distance * radius,
            ..Default::default()
        },
        ..Default::default()
    };
    // Density and widths are per scene unit; scale them with the model.
    settings.style.density *= args.density_scale / (radius * radius);
    settings.style.hair_width *= radius;
    settings.style.jitter *= radius;
    settings.style.lod_distance *= radius;
    settings.style.validate()?;

    let device = fur::gpu::headless(args.validate)?;
    let textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY)?;
    let mut renderer = Renderer::new(
        &device,
        &mesh,
        &textures,
        vk::Extent2D {
            width: args.width,
            height: args.height,
        },
    )?;
    let start = Instant::now();
    let (image, report) = renderer.render(&textures, &settings)?;
    let elapsed = start.elapsed();
    image.write_png(&args.out)?;
    let hairs = report
        .statistics
        .map(|s| format!(", {} interpolated hairs drawn", s.geometry_invocations))
        .unwrap_or_default();
    println!(
        "wrote {} ({}×{}): {} master hairs{hairs}; frame {:.1} ms (GPU: mesh {:.2} ms, fur {:.2} ms)",
        args.out.display(),
        args.width,
        args.height,
        strands.count(),
        elapsed.as_secs_f64() * 1e3,
        report.mesh_ms,
        report.fur_ms,
    );
    drop(renderer);
    drop(textures);
    let messages = device.instance().validation_messages();
    if !messages.is_empty() {
        anyhow::bail!(
            "{} validation message(s); the first: {}",
            messages.len(),
            messages[0]
        );
    }
    Ok(())
}
