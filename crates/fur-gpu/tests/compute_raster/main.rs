//! Strands drawn in compute (`--raster compute`) on lavapipe, validation on: the same
//! hairs as the hardware backend, drawn, nothing lost, validation-clean.

use std::sync::Arc;

use ash::vk;
use fur_core::render::{FrameSettings, FurStyle, Raster, RgbaImage, MAX_NEAREST, TILE_SIZES};
use fur_core::scene::{Camera, GroomParams, Mesh, Strands};
use fur_gpu::gpu::Device;
use fur_gpu::render::{FrameReport, Renderer};
use fur_gpu::strand_textures::StrandTextures;

mod bounds;
mod empty_tiles;
mod lighting;

fn device() -> Arc<Device> {
    let device = fur_gpu::gpu::headless(true).expect("a Vulkan device with the validation layer");
    assert!(device.instance().has_debug_messenger());
    device
}

fn assert_clean(device: &Arc<Device>) {
    let messages = device.instance().validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation message(s):\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// The blob at a quarter of the default density (small images of full-density fur put
/// hundreds of fragments in a pixel: slow on lavapipe, and no more telling).
fn blob_settings(raster: Raster, samples: u32) -> FrameSettings {
    let mesh = Mesh::blob();
    let (center, radius) = mesh.bounds();
    let style = FurStyle::default();
    FrameSettings {
        camera: Camera {
            target: center,
            distance: 2.6 * radius,
            ..Default::default()
        },
        style: FurStyle {
            raster,
            samples,
            density: 0.25 * style.density,
            ..style
        },
        count_hairs: true,
        ..Default::default()
    }
}

fn groom() -> GroomParams {
    GroomParams {
        segments: 8,
        segment_length: 0.03,
        ..Default::default()
    }
}

/// A renderer of the blob's fur at `size` for `settings`, and its strands.
fn blob_renderer(
    device: &Arc<Device>,
    settings: &FrameSettings,
    size: (u32, u32),
) -> (Renderer, StrandTextures) {
    let mesh = Mesh::blob();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let textures = StrandTextures::new(device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: size.0,
        height: size.1,
    };
    let renderer =
        Renderer::new(device, &mesh, &textures, extent, 1, settings.style.samples).unwrap();
    (renderer, textures)
}

fn render(
    device: &Arc<Device>,
    settings: &FrameSettings,
    size: (u32, u32),
) -> (RgbaImage, FrameReport) {
    let (mut renderer, textures) = blob_renderer(device, settings, size);
    renderer.render(&textures, settings).unwrap()
}

fn keep(image: &RgbaImage, name: &str) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("images");
    let path = dir.join(format!("{name}.png"));
    if image.write_png(&path).is_ok() {
        eprintln!("image: {}", path.display());
    }
}

#[test]
fn the_compute_backend_draws_the_hardware_backends_hairs() {
    let device = device();
    let size = (160, 120);
    for samples in [1, 4] {
        let (hardware, hw) = render(&device, &blob_settings(Raster::Hardware, samples), size);
        let (compute, cr) = render(&device, &blob_settings(Raster::Compute, samples), size);
        keep(&hardware, &format!("hardware_{samples}x"));
        keep(&compute, &format!("compute_{samples}x"));
        let (hw_counts, cr_counts) = (hw.counts.unwrap(), cr.counts.unwrap());
        assert_eq!(hw_counts, cr_counts, "{samples}×");
        let raster = cr.raster.expect("the compute backend reports its counts");
        eprintln!("{samples}×: {hw_counts:?} {raster:?}");
        assert_eq!(u64::from(raster.segments), cr_counts.segments, "{raster:?}");
        assert_eq!(
            (raster.hairs_lost, raster.entries_lost),
            (0, 0),
            "{raster:?}"
        );
        let flip = fur_core::render::flip(&hardware, &compute);
        eprintln!("{samples}×: ꟻLIP hardware against compute {flip:?}");
        // The same hair, drawn: the two images within 0.15 of each other against the
        // hardware's default 4× MSAA (0.094 measured). One sample aliases the
        // hardware's image itself (0.21 measured), so it is not held to it.
        if samples == 4 {
            assert!(flip < 0.15, "ꟻLIP {flip} between the backends at 4×");
        }
    }
    assert_clean(&device);
}

/// The GPU's binning and hair layer against the CPU twin's, on the very segments the
/// geometry stage wrote over the very depth the mesh pass left: every tile lists the
/// same segments, and drawing the GPU's lists (in the GPU's order, which the tail's
/// blending and merging depend on) gives each pixel's colour and transmittance to float rounding
/// over the hundreds of fragments of a dense pixel: within 10⁻³ (the GPU's division and
/// fused arithmetic differ from the CPU's by up to 3·10⁻⁴ here), but for at most one
/// pixel in a thousand, within 10⁻², where two fragments nearer to each other than that
/// rounding sort either way (two of 6,912 with 8 or 16 kept in order, none with 2 or 4).
/// With lists of 2 (most fragments in the tail), the default and the most fragments in
/// order, on the device's tiles; and the smallest and largest tile sides and 4×4 (a
/// pixel a bit of the entries' masks up to 4×4, blocks of 2×4 at 16×16).
/// Seen failing against the fine pass walking a dense tile's list in one loop (lavapipe
/// ends an invocation's loops after 65,535 turns: whole tiles drawn empty), and against
/// the fine pass blending the lit colour unclamped where the twin holds it to white
/// (the lit blob's highlights are brighter than white), and against an opaque pixel
/// stopping at the start of the bin it is in rather than where that bin ends (its
/// fragments fell short of the twin's), and against a sort that leaves each list in
/// the order the scatter wrote it (the stops found from its entries' bins differ).
#[test]
fn the_gpu_draws_what_its_cpu_twin_draws() {
    let default = FurStyle::default().nearest;
    for (nearest, tile) in [
        (2, 0),
        (default, 0),
        (MAX_NEAREST, 0),
        (default, TILE_SIZES[0]),
        (default, 4),
        (default, TILE_SIZES[TILE_SIZES.len() - 1]),
    ] {
        draws_what_its_twin_draws(nearest, tile);
    }
}

fn draws_what_its_twin_draws(nearest: u32, tile: u32) {
    use fur_core::render::strand_raster::{bin, draw, Backdrop, RasterBudget};
    let device = device();
    let size = (96, 72);
    let mut settings = blob_settings(Raster::Compute, 1);
    settings.style.nearest = nearest;
    settings.style.tile = tile;
    // Kajiya–Kay's highlights are brighter than white, which the check below needs.
    settings.lighting.model = fur_core::render::LightingModel::KajiyaKay;
    let mesh = Mesh::blob();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let textures = StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: size.0,
        height: size.1,
    };
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    let (_, report) = renderer.render(&textures, &settings).unwrap();
    let gpu_counts = report.raster.expect("the compute passes' counts");
    let capture = renderer.capture_raster(0).unwrap();
    assert!(
        capture.segments.len() > 1000,
        "{} segments",
        capture.segments.len()
    );
    // Highlights brighter than white, which both must hold to white.
    let bright = capture
        .segments
        .iter()
        .filter(|s| s.a.color.iter().any(|c| *c > 1.0))
        .count();
    eprintln!(
        "{bright} of {} segments brighter than white",
        capture.segments.len()
    );
    assert!(bright > 100, "{bright} segments brighter than white");
    let budget = RasterBudget {
        tile: capture.tile,
        nearest: nearest as usize,
        entries: 1 << 24,
    };
    let backdrop = |background: [f32; 3]| Backdrop {
        width: capture.width,
        height: capture.height,
        color: vec![background; capture.depth.len()],
        depth: capture.depth.clone(),
    };
    let (twin_bins, counts) = bin(&capture.segments, &backdrop([0.0; 3]), &budget);
    let sorted = |lists: &[Vec<u32>]| -> Vec<Vec<u32>> {
        lists
            .iter()
            .map(|l| {
                let mut l = l.clone();
                l.sort_unstable();
                l
            })
            .collect()
    };
    assert_eq!(
        sorted(&capture.bins.lists),
        sorted(&twin_bins.lists),
        "the tiles list different segments"
    );
    // Sorted alike: each depth bin that holds an entry ends where the twin's does, and
    // the GPU's lists hold the twin's bins in order (within a bin, in any order).
    assert_eq!(
        capture.bins.stops, twin_bins.stops,
        "the tiles' depth bins differ"
    );
    for (tile, stops) in twin_bins.stops.iter().enumerate() {
        let mut start = 0;
        for &end in stops {
            let range = start as usize..end as usize;
            let gpu = sorted(&[capture.bins.lists[tile][range.clone()].to_vec()]);
            let twin = sorted(&[twin_bins.lists[tile][range].to_vec()]);
            assert_eq!(gpu, twin, "tile {tile}: the bin ending at {end} differs");
            start = end;
        }
    }
    let drawn = |background| {
        draw(
            &capture.segments,
            &capture.bins,
            &backdrop(background),
            &budget,
            counts.clone(),
        )
    };
    let on_black = drawn([0.0; 3]);
    let (black, white) = (on_black.color, drawn([1.0; 3]).color);
    // The pixels took the twin's fragments: a pass that counted every entry it
    // searched, or each pixel's kept fragments only, is far off (fragments nearer to the
    // body or to the least coverage than the two's rounding may go either way).
    let (gpu, twin) = (gpu_counts.fragments, on_black.counts.fragments);
    eprintln!("{nearest} in order, tile {tile}: fragments {gpu} on the GPU, {twin} in the twin");
    assert!(
        twin > 10_000 && gpu.abs_diff(twin) * 1000 <= twin,
        "the GPU's pixels took {gpu} fragments, the twin's {twin}"
    );
    let mut worst = (0.0f32, 0usize);
    let mut off = 0;
    for (i, gpu) in capture.layer.iter().enumerate() {
        let transmit = white[i][0] - black[i][0];
        let error = (0..3)
            .map(|c| (gpu[c] - black[i][c]).abs())
            .fold((gpu[3] - transmit).abs(), f32::max);
        off += usize::from(error >= 1e-3);
        if error > worst.0 {
            worst = (error, i);
        }
    }
    let (x, y) = (
        worst.1 as u32 % capture.width,
        worst.1 as u32 / capture.width,
    );
    // Fragments nearer to each other than the two's rounding may sort either way.
    assert!(
        off <= capture.layer.len() / 1000 && worst.0 < 1e-2,
        "{nearest} in order, tile {}: {off} pixels off by 1e-3 or more; the worst, ({x}, {y}): \
         {:?} on the GPU, {:?} + {} transmitted in the twin",
        capture.tile,
        capture.layer[worst.1],
        black[worst.1],
        white[worst.1][0] - black[worst.1][0]
    );
    let covered = capture.layer.iter().filter(|p| p[3] < 0.5).count();
    assert!(covered > 500, "only {covered} pixels are mostly hair");
    assert_clean(&device);
}

/// Pools far too small for the frame: the hairs and entries that did not fit are
/// counted, the frame still draws what did, validation-clean; each next frame's pools
/// grow to what the last asked for (the entries are known once every hair fits), so
/// the loss falls to nothing within three frames, and `render` (which draws a frame
/// again while its pools overflow) returns a whole frame from the same small pools.
/// Seen failing against `render` drawing a frame twice at most (its second try still
/// lost 280,995 entries, since the first had lost the hairs that make them).
#[test]
fn overflowing_every_pool_is_counted_and_the_pools_grow_to_the_frame() {
    use fur_core::render::strand_raster::pools::{Demand, PoolBudget};
    let device = device();
    let settings = blob_settings(Raster::Compute, 1);
    let mesh = Mesh::blob();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let textures = StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: 96,
        height: 72,
    };
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    // A few thousand of each, where the frame writes tens of thousands.
    let small = PoolBudget {
        vertices_per_pixel: 0,
        segments_per_pixel: 0,
        entries_per_pixel: 0,
        floor: Demand {
            vertices: 4096,
            segments: 4096,
            entries: 4096,
        },
        ..PoolBudget::default()
    };
    renderer.force_pool_budget(small);
    let mut losses = Vec::new();
    for _ in 0..3 {
        renderer.update(0, &settings).unwrap();
        device
            .submit_once(|cmd| {
                renderer.begin_frame(cmd, 0);
                renderer.record(
                    cmd,
                    &mut fur_gpu::frame::tracker(),
                    0,
                    textures.current,
                    &settings,
                );
                Ok(())
            })
            .unwrap();
        let counts = renderer.report(0, &settings).unwrap().raster.unwrap();
        eprintln!("{counts:?}");
        losses.push((counts.hairs_lost, counts.entries_lost));
    }
    let (first, last) = (losses[0], losses[2]);
    assert!(first.0 > 0 && first.1 > 0, "{losses:?}");
    assert_eq!(last, (0, 0), "{losses:?}");
    // A fresh renderer (the first remembers what its frames asked for).
    drop(renderer);
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    renderer.force_pool_budget(small);
    let (_, report) = renderer.render(&textures, &settings).unwrap();
    let whole = report.raster.unwrap();
    assert_eq!((whole.hairs_lost, whole.entries_lost), (0, 0), "{whole:?}");
    assert!(whole.segments > 50_000, "{whole:?}");
    assert_clean(&device);
}

/// `--show tiles` on a scene drawn with the fixed-function rasteriser: the strands are
/// binned anyway, and each tile is in the colour of the segments it lists
/// (`render::stage::tile_colour`), read at its centre against the twin's colour of the
/// count the GPU's own lists hold; tiles with more than one count appear.
/// Seen failing against the composite indexing tiles by the image's height (every row
/// of tiles but the first coloured by another's count).
#[test]
fn the_tiles_view_colours_each_tile_by_the_segments_it_lists() {
    use fur_core::colour::linear_to_srgb8;
    use fur_core::render::stage::tile_colour;
    use fur_core::render::Stage;
    let device = device();
    let (width, height) = (96u32, 72u32);
    let mut settings = blob_settings(Raster::Hardware, 1);
    settings.show = Stage::Tiles;
    let mesh = Mesh::blob();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let textures = StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D { width, height };
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    let (image, _) = renderer.render(&textures, &settings).unwrap();
    keep(&image, "tiles_view");
    let capture = renderer.capture_raster(0).unwrap();
    let tile = capture.tile;
    let mut counts = std::collections::BTreeSet::new();
    for row in 0..capture.bins.rows {
        for column in 0..capture.bins.columns {
            let (x, y) = (column * tile + tile / 2, row * tile + tile / 2);
            if x >= width || y >= height {
                continue;
            }
            let listed = capture.bins.lists[(row * capture.bins.columns + column) as usize].len();
            counts.insert(listed);
            let want = tile_colour(listed as u32).to_array().map(linear_to_srgb8);
            let got = image.pixel(x, y);
            for c in 0..3 {
                assert!(
                    got[c].abs_diff(want[c]) <= 1,
                    "tile ({column}, {row}), {listed} segments: {got:?} against {want:?}"
                );
            }
        }
    }
    assert!(counts.len() > 10, "only {} different counts", counts.len());
    assert_clean(&device);
}

/// A simulated sequence drawn in compute: frames after the first (the simulation's
/// kernels then run in the frame's command buffer) are drawn, validation-clean, with
/// the same hairs and segments as the hardware backend's, on the default blob, the
/// original's sphere and the critter walking (skinned on the device).
/// Seen failing against a composite drawn by a graphics pass after the compute passes:
/// Mesa 22.3's lavapipe crashes on the second frame.
#[test]
fn a_simulated_sequence_is_drawn_in_compute() {
    let device = device();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for scene in [
        None,
        Some(root.join("assets/scenes/original.toml")),
        Some(root.join("assets/scenes/critter.toml")),
    ] {
        let name = scene
            .as_ref()
            .map_or("default".into(), |p| p.display().to_string());
        let hardware = sequence(&device, scene.as_deref(), Raster::Hardware);
        let compute = sequence(&device, scene.as_deref(), Raster::Compute);
        for (frame, ((_, h), (image, c))) in hardware.iter().zip(&compute).enumerate() {
            assert_eq!(h, c, "{name}, frame {frame}");
            assert!(c.hairs > 100, "{name}, frame {frame}: {c:?}");
            let drawn = (0..image.height)
                .flat_map(|y| (0..image.width).map(move |x| (x, y)))
                .filter(|&(x, y)| image.pixel(x, y) != image.pixel(0, 0))
                .count();
            assert!(
                drawn > 500,
                "{name}, frame {frame}: {drawn} pixels differ from the corner"
            );
        }
    }
    assert_clean(&device);
}

/// Two simulated frames of the scene file `path` (the default scene for none), its
/// rig and clip played when it has them, at a small fraction of its density.
fn sequence(
    device: &Arc<Device>,
    path: Option<&std::path::Path>,
    raster: Raster,
) -> Vec<(RgbaImage, fur_gpu::render::HairCounts)> {
    use fur_core::scene_file::Scene;
    use fur_gpu::session::{FurSession, SessionSetup};
    let scene = Scene::load(path, None).unwrap();
    let (mesh, rig, _) = scene.model.prepare_body(None).unwrap();
    let rig = scene.animation.resolve(rig, &scene.model.name()).unwrap();
    let mut options = scene.options.clone();
    options.draw.raster = raster;
    options.draw.density *= 0.03;
    let (groom, mut settings) = options.resolve(&mesh).unwrap();
    settings.count_hairs = true;
    let motion = scene.motion.motion(mesh.bounds().1);
    let mut session = FurSession::new(
        device,
        SessionSetup {
            mesh,
            rig,
            groom: &groom,
            sim: scene.sim.clone(),
            motion,
            settings,
            extent: vk::Extent2D {
                width: 96,
                height: 64,
            },
            frames_in_flight: 1,
        },
    )
    .unwrap();
    (0..2)
        .map(|_| {
            let (image, timings) = session.step_and_render().unwrap();
            (image, timings.render.counts.unwrap())
        })
        .collect()
}
