//! `fur export-groom`: the master hairs as guide curves (USD or cyHair), at rest
//! in the model's space — ready to come back as `--groom` — or at the Nth simulated
//! frame as drawn (world space, a skinned body's pose).

use super::render_command::{open, Opened};
use super::*;
use fur_core::scene::DrawnGroom;

#[derive(Args, Clone)]
pub(super) struct GroomArgs {
    /// Where to write the master hairs: USD text (`.usda`), binary USD (`.usdc`) or
    /// cyHair (`.hair`).
    #[arg(value_name = "OUT")]
    pub out: PathBuf,
    /// A TOML scene file (see assets/scenes/); options given here override it.
    #[arg(long)]
    pub scene_file: Option<PathBuf>,
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Simulate this many frames (1/60 s each) and write the hairs of the last one as
    /// drawn; 1 writes them at rest in the model's space.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub frames: u32,
    /// Enable the Khronos validation layer (with --frames above 1).
    #[arg(long)]
    pub validate: bool,
    #[command(flatten)]
    pub device: DeviceArgs,
}

pub(super) fn export_groom(args: &GroomArgs) -> anyhow::Result<()> {
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    fur_core::groom_file::GroomFormat::of(&args.out)?;
    fur_core::files::check_output_file(&args.out)?;
    let generator = format!("fur {}", env!("CARGO_PKG_VERSION"));
    let (guides, which) = if args.frames == 1 {
        (at_rest(args)?, "at rest, in the model's space".to_string())
    } else {
        (
            simulated(args)?,
            format!("frame {} of the simulation, in world space", args.frames),
        )
    };
    fur_core::groom_file::write_groom(&args.out, &guides, &generator)?;
    println!(
        "wrote {} ({which}): {} master hairs of {} vertices",
        args.out.display(),
        guides.count(),
        guides.counts.first().copied().unwrap_or(0)
    );
    Ok(())
}

/// The master hairs as the session grows them, without a device.
fn at_rest(args: &GroomArgs) -> anyhow::Result<fur_core::groom_file::Guides> {
    let scene = args::scene(args.scene_file.as_deref(), &args.scene)?;
    let (mesh, rig, warnings) = scene.model.prepare_body(scene.options.texture.as_ref())?;
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    let rig = scene.animation.resolve(rig, &scene.model.name())?;
    let (mut groom, settings) = scene.options.resolve(&mesh)?;
    if let Some((rig, _)) = &rig {
        // As the session does: a skinned body's fur flows along its bones.
        groom.comb_field = Some(fur_core::skinning::fur_flow(rig));
    }
    let (strands, warnings) = match groom.drawn_source() {
        // A drawn groom: its guides' master hairs, not the body's stubs.
        Some(source) => {
            let drawn = DrawnGroom::from_file(mesh, rig.map(|(r, _)| r), &groom, source)?;
            (drawn.guide_strands(), drawn.warnings())
        }
        None => fur_core::scene::Strands::grow_reported(&mesh, &groom)?,
    };
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    Ok(strands.to_guides(Some(settings.style.hair_width)))
}

/// The master hairs at the last of `args.frames` simulated frames, read back.
fn simulated(args: &GroomArgs) -> anyhow::Result<fur_core::groom_file::Guides> {
    let render = RenderArgs {
        scene_file: args.scene_file.clone(),
        scene: args.scene.clone(),
        out: PathBuf::from("fur.png"),
        frames: args.frames,
        out_dir: None,
        budget_ms: None,
        validate: args.validate,
        device: args.device.clone(),
    };
    let Opened {
        device,
        mut session,
        ..
    } = open(&render, true)?;
    for frame in 0..args.frames {
        fur_core::interrupt::check()?;
        session
            .step_and_render()
            .with_context(|| format!("simulating frame {frame}"))?;
    }
    let textures = &session.textures;
    let mut vertices = textures.read_vertices(textures.current)?;
    let per_strand = textures.layout.vertices_per_strand;
    if let Some(first) = session.first_guide {
        // A drawn groom: its guides' master hairs, not the body's stubs.
        vertices.drain(..first * per_strand as usize);
    }
    let guides = fur_core::groom_file::Guides {
        counts: vec![per_strand; vertices.len() / per_strand.max(1) as usize],
        points: vertices.iter().map(|v| v.truncate()).collect(),
        widths: Some(vec![session.settings.style.hair_width; vertices.len()]),
        colors: None,
        notes: Vec::new(),
    };
    drop(session);
    fur_gpu::gpu::shut_down(device)?;
    Ok(guides)
}
