//! `fur render`: one frame, or a sequence of frames, of a scene to image files, with
//! the scene's report.

use super::*;

/// What a frame without any hair means.
const NO_FUR: &str = "no hair was drawn: every furred triangle is off-screen, facing away \
    (culled) or too small for the density; move the camera (--yaw, --pitch, --distance) or \
    raise --density-scale";

/// Frames measured before this many are warm-up (lazy shader compilation, caches).
const WARM_UP_FRAMES: usize = 2;

/// The largest frame budget `--budget-ms` takes: a minute a frame. Beyond it no rung
/// would ever be left, and the number is more likely a mistake (seconds for ms).
const MAX_BUDGET_MS: f64 = 60_000.0;

pub(super) fn render(args: &RenderArgs) -> anyhow::Result<()> {
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if let Some(ms) = args.budget_ms {
        if !(ms.is_finite() && ms > 0.0 && ms <= MAX_BUDGET_MS) {
            bail!(
                "--budget-ms must be a positive number of milliseconds up to {MAX_BUDGET_MS} \
                 (a minute a frame), got {ms}"
            );
        }
        if args.frames < 2 {
            bail!("--budget-ms needs a sequence (--frames 2 or more) to observe frame times");
        }
    }
    let simulate = args.frames > 1 || args.out_dir.is_some();
    // Every output path is checked before any work starts.
    let frames_dir = args
        .out_dir
        .clone()
        .unwrap_or_else(|| PathBuf::from("frames"));
    if simulate {
        fur_core::files::check_output_dir(&frames_dir)?;
    } else {
        fur_core::files::check_output_file(&args.out)?;
    }
    let Opened {
        device,
        mut session,
        width,
        height,
    } = open(args, simulate)?;
    let masters = session.strands.count();
    if simulate {
        let ladder = device.info().ladder(session.settings.style.raster);
        render_sequence(args, &frames_dir, &mut session, ladder)?;
    } else {
        let start = Instant::now();
        let (image, report) = session
            .render()
            .with_context(|| format!("drawing the frame ({width}×{height})"))?;
        let elapsed = start.elapsed();
        let image = with_legend(image, &session, &flow_points(&session))?;
        image.write_png(&args.out)?;
        warn_without_fur(&session, report.counts);
        let points = report
            .statistics
            .map(|s| format!(", {} tessellated points", s.tess_eval_invocations))
            .unwrap_or_default();
        let hairs = report
            .counts
            .map(|c| {
                if !session.settings.show.draws_fur() {
                    return format!(", {} triangles culled", c.triangles_culled);
                }
                format!(
                    ", {} hairs drawn in {} segments (points shared by two triangles are drawn \
                     once), {} triangles culled",
                    c.hairs, c.segments, c.triangles_culled
                )
            })
            .unwrap_or_default();
        // The model that lights the view, where its colours come from one.
        let lighting = if session.settings.show.shows_lighting() {
            format!(", {} lighting", session.settings.lighting.model.label())
        } else {
            String::new()
        };
        // With the image on standard output (`--out -`), the summary goes to stderr.
        let summary = format!(
            "wrote {} ({}×{}{lighting}): {masters} master hairs{points}{hairs}; one cold \
             frame {:.1} ms (use --frames N for warm timings)",
            args.out.display(),
            width,
            height,
            elapsed.as_secs_f64() * 1e3,
        );
        if args.out.as_os_str() == fur_core::files::STDOUT {
            eprintln!("{summary}");
        } else {
            println!("{summary}");
        }
    }
    drop(session);
    fur_gpu::gpu::shut_down(device)?;
    Ok(())
}

/// Warns when a view that draws fur drew none.
fn warn_without_fur(session: &FurSession, counts: Option<fur_gpu::render::HairCounts>) {
    if session.settings.show.draws_fur() && counts.is_some_and(|c| c.hairs == 0) {
        eprintln!("warning: {NO_FUR}");
    }
}

/// Where the `masters` view marks the fur's flow turning: the singular points of the
/// master hairs as grown (found once a run; they move only with the posed body); none
/// for the other views.
fn flow_points(session: &FurSession) -> Vec<fur_core::scene::Singularity> {
    if session.settings.show == fur_core::render::Stage::Masters {
        fur::flow_marks::of_masters(&session.mesh, &session.strands)
    } else {
        Vec::new()
    }
}

/// `image` with the colour key of the stage it shows in its corner, when that stage
/// has one (`fur::legend`), and the flow's singular `points` ([`flow_points`]) marked
/// where the body is posed (`fur::flow_marks`).
fn with_legend(
    mut image: fur_core::render::RgbaImage,
    session: &FurSession,
    points: &[fur_core::scene::Singularity],
) -> anyhow::Result<fur_core::render::RgbaImage> {
    let max_level = session.renderer.max_level();
    if let Some(legend) = fur::legend::Legend::of(&session.settings, max_level) {
        legend.draw(&mut image);
    }
    if !points.is_empty() {
        let mesh = &session.mesh;
        let posed = session.posed_body()?;
        let (positions, normals) = posed
            .as_ref()
            .map_or((&mesh.positions, &mesh.normals), |(p, n)| (p, n));
        let marks = fur::flow_marks::placed(points, positions, normals);
        let camera = &session.settings.camera;
        let aspect = image.width as f32 / image.height.max(1) as f32;
        let view_projection = camera.view_projection(aspect);
        fur::flow_marks::draw(
            &mut image,
            &marks,
            session.settings.head,
            view_projection,
            camera.eye(),
        );
    }
    Ok(image)
}

/// A scene built and ready to draw.
pub(super) struct Opened {
    pub device: std::sync::Arc<fur_gpu::gpu::Device>,
    pub session: FurSession,
    pub width: u32,
    pub height: u32,
}

/// Builds the scene `args` describe on the device they choose; `simulate`: whether it
/// will be simulated (a single frame is drawn at rest, its head still).
pub(super) fn open(args: &RenderArgs, simulate: bool) -> anyhow::Result<Opened> {
    let mut scene = args::scene(args.scene_file.as_deref(), &args.scene)?;
    let (mesh, rig, warnings) = scene.model.prepare_body(scene.options.texture.as_ref())?;
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    let rig = scene.animation.resolve(rig, &scene.model.name())?;
    if rig.is_some() && !args.scene.settings.gives("motion") && scene.motion == Default::default() {
        // A character moves by its clip; the head stays put unless asked.
        scene.motion.kind = MotionKind::Still;
    }
    let (_, radius) = mesh.bounds();
    let (groom, mut settings) = scene.options.resolve(&mesh)?;
    if let Some((rig, playback)) = &rig {
        if scene.options.distance.is_none() {
            // The camera frames every pose of the clip, not only the rest pose.
            let frames = if simulate { args.frames } else { 1 };
            scene
                .options
                .frame_poses(&mut settings, &mesh, rig, playback, frames);
        }
        if let Some(clip) = playback.clip {
            eprintln!(
                "animation: {} ({:.2} s) at {}×, from {} s{}",
                rig.clips[clip].name,
                rig.clips[clip].duration(),
                playback.speed,
                playback.start,
                if playback.in_place { ", in place" } else { "" }
            );
        }
    }
    settings.count_hairs = !simulate;
    let mut motion = scene.motion.motion(radius);
    if !simulate {
        motion.kind = MotionKind::Still;
    }
    let extent = vk::Extent2D {
        width: scene.width,
        height: scene.height,
    };

    let device = args.device.headless(args.validate)?;
    let masters = mesh.vertex_count();
    if masters > 100_000 {
        eprintln!(
            "building the scene: {masters} master hairs of {} vertices…",
            groom.vertices_per_strand()
        );
    }
    let session = FurSession::new(
        &device,
        SessionSetup {
            mesh,
            rig,
            groom: &groom,
            sim: scene.sim.clone(),
            motion,
            settings,
            extent,
            frames_in_flight: 1,
        },
    )
    .with_context(|| {
        format!(
            "building the scene ({masters} master hairs of {} vertices, {}×{} image)",
            groom.vertices_per_strand(),
            scene.width,
            scene.height
        )
    })?;
    for warning in session.all_warnings(&scene.model.name()) {
        eprintln!("warning: {warning}");
    }
    Ok(Opened {
        device,
        session,
        width: scene.width,
        height: scene.height,
    })
}

/// Simulates and renders `args.frames` frames into PNGs, under `args.budget_ms` along
/// `ladder` if set; ends with the median frame time of the warm frames.
fn render_sequence(
    args: &RenderArgs,
    dir: &Path,
    session: &mut FurSession,
    ladder: fur_core::render::budget::Ladder,
) -> anyhow::Result<()> {
    let bar = indicatif::ProgressBar::new(u64::from(args.frames)).with_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} frames {elapsed} (eta {eta}) {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut frame_ms = Vec::new();
    let mut budget = args
        .budget_ms
        .map(|ms| fur_core::render::budget::Budget::on(ladder, ms));
    let base = session.settings.style.clone();
    let points = flow_points(session);
    for frame in 0..args.frames {
        fur_core::interrupt::check()?;
        let warm = frame as usize > WARM_UP_FRAMES;
        if let (Some(budget), Some(&last), true) = (&mut budget, frame_ms.last(), warm) {
            // A sequence is always in motion: the budget never refines. The warm-up
            // frames (compiling the default's pipelines) are left out, as from the median.
            let before = budget.rung;
            let rung = budget.observe(last, last / 1e3, true);
            if rung != before {
                bar.suspend(|| {
                    eprintln!(
                        "frame {frame}: quality rung {rung} ({})",
                        ladder.rung(rung).name
                    )
                });
            }
            session.settings.style = ladder.rung(rung).apply(&base);
        }
        // The first frame (a warm-up frame, not timed) counts what it draws.
        session.settings.count_hairs = frame == 0;
        let start = Instant::now();
        let (image, timings) = session
            .step_and_render()
            .with_context(|| format!("simulating and drawing frame {frame}"))?;
        warn_without_fur(session, timings.render.counts);
        frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
        let image = with_legend(image, session, &points)?;
        image.write_png(&dir.join(format!("frame_{frame:04}.png")))?;
        bar.set_message(format!("{:.1} ms", frame_ms[frame_ms.len() - 1]));
        bar.inc(1);
    }
    bar.finish();
    println!(
        "wrote {} frames to {}: {} master hairs",
        args.frames,
        dir.display(),
        session.strands.count()
    );
    let warm = if frame_ms.len() > WARM_UP_FRAMES {
        &frame_ms[WARM_UP_FRAMES..]
    } else {
        &frame_ms[..]
    };
    let note = if frame_ms.len() > WARM_UP_FRAMES {
        format!(
            "over {} warm frames: simulation, both passes and the image copy",
            warm.len()
        )
    } else {
        "over cold frames only (use more than 2 frames for warm timings)".to_string()
    };
    println!(
        "median frame {:.1} ms ({note})",
        fur::bench::metrics::median(warm)
    );
    if let Some(budget) = &budget {
        let rung = budget.ladder().rung(budget.rung);
        println!(
            "budget {:.1} ms: the last frame was drawn at quality rung {} ({}){}",
            budget.target_ms,
            budget.rung,
            rung.name,
            if budget.missed {
                "; even the cheapest rung misses the budget"
            } else {
                ""
            }
        );
    }
    Ok(())
}
