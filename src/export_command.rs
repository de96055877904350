//! `fur export-frame`: one frame exactly as drawn (the hairs the geometry stage emits,
//! the posed body, the camera, the lights, the fibre) as USD text for a path tracer,
//! with the PNG fur draws of the same frame beside it.

use super::render_command::{open, Opened};
use super::*;

#[derive(Args, Clone)]
pub(super) struct ExportArgs {
    /// Where to write the frame: USD text (`.usda`) or binary USD (`.usdc`).
    pub usd: PathBuf,
    /// Export and draw the body alone, without hair (the calibration of the path
    /// tracer against fur's mesh pass).
    #[arg(long)]
    pub body_only: bool,
    #[command(flatten)]
    pub render: RenderArgs,
}

pub(super) fn export_frame(args: &ExportArgs) -> anyhow::Result<()> {
    let r = &args.render;
    if r.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if r.out_dir.is_some() || r.budget_ms.is_some() {
        bail!(
            "export-frame writes one frame: --out-dir and --budget-ms are for `fur render`; \
             --frames N exports the Nth simulated frame"
        );
    }
    let binary = check_extension(&args.usd)?;
    fur_core::files::check_output_file(&args.usd)?;
    fur_core::files::check_output_file(&r.out)?;
    let simulate = r.frames > 1;
    let Opened {
        device,
        mut session,
        width,
        height,
    } = open(r, simulate)?;
    let show = session.settings.show;
    if show != fur_core::render::Stage::Lit {
        bail!(
            "export-frame writes the final frame as drawn; --show {} is a study view of \
             `fur render` and `fur view`, not a frame to path-trace",
            show.name()
        );
    }
    session.settings.draw_fur = !args.body_only;
    if simulate {
        let bar = indicatif::ProgressBar::new(u64::from(r.frames)).with_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} frames simulated {elapsed}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        for frame in 0..r.frames {
            fur_core::interrupt::check()?;
            session
                .step_and_render()
                .with_context(|| format!("simulating frame {frame}"))?;
            bar.inc(1);
        }
        bar.finish_and_clear();
    }
    let (image, hairs) = session
        .renderer
        .capture(&session.textures, &session.settings)
        .context("capturing the hairs the frame draws")?;
    let posed = session.posed_body()?;
    // The texture the frame is drawn with, for the body's colours.
    let texture = session
        .mesh
        .texture
        .as_ref()
        .map(|t| t.load())
        .transpose()
        .context("loading the model's texture")?;
    let frame = fur::export::FrameExport::new(
        hairs,
        &session.mesh,
        texture.as_ref(),
        posed,
        &session.settings,
        ash::vk::Extent2D { width, height },
    );
    frame.check_size()?;
    let generator = format!("fur {}", env!("CARGO_PKG_VERSION"));
    let text = fur::export::write_usda(&frame, &generator)?;
    let bytes = if binary {
        fur_core::groom_file::usdc_from_text(&text)
            .map_err(|m| anyhow::anyhow!("writing the frame as binary USD: {m}"))?
    } else {
        text.into_bytes()
    };
    fur_core::files::write_output(&args.usd, &bytes, "write the frame to")?;
    image.write_png(&r.out)?;
    if frame.hairs.count() == 0 {
        eprintln!("warning: no hair was drawn: the export holds the body only");
    }
    let which = if simulate {
        format!("frame {} of the simulation", r.frames)
    } else {
        "the frame at rest".to_string()
    };
    println!(
        "wrote {} ({which}, {width}×{height}): {} hairs of {} vertices, {} body triangles, \
         {}; and {} (the same frame as fur draws it)",
        args.usd.display(),
        frame.hairs.count(),
        frame.hairs.vertices_per_strand,
        frame.body.as_ref().map_or(0, |b| b.indices.len() / 3),
        fur_core::files::size_text(bytes.len() as u64),
        r.out.display()
    );
    drop(session);
    fur_gpu::gpu::shut_down(device)?;
    Ok(())
}

/// Whether the frame is written as binary USD (`.usdc`) rather than text (`.usda`);
/// other extensions are refused, a package (`.usdz`) with the way to one.
fn check_extension(path: &Path) -> anyhow::Result<bool> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("usda") => Ok(false),
        Some("usdc") => Ok(true),
        Some(e @ ("usd" | "usdz")) => bail!(
            "{}: fur writes USD as text (.usda) or binary (.usdc); for .{e} write one of \
             those and convert it with usd-core (`usdcat frame.usda -o frame.usd`, \
             `usdzip frame.usdz frame.usdc`)",
            path.display()
        ),
        _ => bail!(
            "{}: unknown extension; the frame is written as USD, name it *.usda or *.usdc",
            path.display()
        ),
    }
}
