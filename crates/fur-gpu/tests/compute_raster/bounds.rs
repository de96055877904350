//! The compute passes' loops under lavapipe's loop limit: each counts its turns and
//! stops, counted, before the driver would end it.

use std::sync::Arc;

use super::{assert_clean, blob_renderer, blob_settings, device};
use fur_core::render::{Raster, RgbaImage};
use fur_gpu::gpu::Device;
use fur_gpu::render::ComputeCounts;

/// The blob drawn in compute at 96×72 with the shaders compiled with `defines`, and what
/// the passes counted.
fn blob_in_compute(device: &Arc<Device>, defines: &[(&str, &str)]) -> (RgbaImage, ComputeCounts) {
    let settings = blob_settings(Raster::Compute, 1);
    fur_gpu::gpu::shader::with_test_defines(defines, || {
        let (mut renderer, textures) = blob_renderer(device, &settings, (96, 72));
        let (image, report) = renderer.render(&textures, &settings).unwrap();
        (image, report.raster.unwrap())
    })
}

/// The fine pass's walk stays under lavapipe's loop limit by counting its turns: a
/// pixel that would take more stops, counted with the pixels that stopped. With the
/// bound lowered to a few turns (`FUR_TEST_MAX_TURNS`), the frame still finishes,
/// validation-clean, many more pixels stop, and the image changes (what those pixels
/// did not meet); a guard that did not stop the walk, or stopped it uncounted, fails.
#[test]
fn a_pixel_past_the_loop_bound_stops_and_is_counted() {
    let device = device();
    let draw = |defines: &[(&str, &str)]| blob_in_compute(&device, defines);
    let (whole, whole_counts) = draw(&[]);
    let (cut, cut_counts) = draw(&[("FUR_TEST_MAX_TURNS", "4u")]);
    eprintln!("{whole_counts:?}\n{cut_counts:?}");
    assert!(
        cut_counts.pixels_stopped > whole_counts.pixels_stopped + 500,
        "{whole_counts:?}\n{cut_counts:?}"
    );
    assert_ne!(
        whole.data, cut.data,
        "the stopped pixels' fragments were drawn"
    );
    assert_clean(&device);
}

/// On a CPU driver the scatter is a workgroup for each half of the segments (the same
/// list order every run), whose invocations each walk many segments, so each counts its
/// turns under lavapipe's loop limit. With the bound lowered to a few turns
/// (`FUR_TEST_BIN_TURNS`), the frame finishes validation-clean, the entries the stopped invocations never wrote are
/// counted lost, and the lists end where the written entries do: the entries kept and
/// lost add up to the whole frame's entries, and the image loses hair. Seen failing
/// with the sort taking each tile's whole count (nothing counted lost, and stale
/// entries drawn).
#[test]
fn a_scatter_past_the_loop_bound_stops_and_counts_what_it_left() {
    let device = device();
    if !device.info().is_cpu() {
        return;
    }
    let draw = |defines: &[(&str, &str)]| blob_in_compute(&device, defines);
    let (whole, whole_counts) = draw(&[]);
    let (cut, cut_counts) = draw(&[("FUR_TEST_BIN_TURNS", "6u")]);
    eprintln!("{whole_counts:?}\n{cut_counts:?}");
    assert_eq!(whole_counts.entries_lost, 0, "{whole_counts:?}");
    assert!(cut_counts.entries_lost > 0, "{cut_counts:?}");
    assert!(cut_counts.entries > 0, "{cut_counts:?}");
    assert_eq!(
        cut_counts.entries + cut_counts.entries_lost,
        whole_counts.entries,
        "{whole_counts:?}\n{cut_counts:?}"
    );
    let covered = |image: &fur_core::render::RgbaImage| {
        let background = image.pixel(0, 0);
        (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .filter(|&(x, y)| image.pixel(x, y) != background)
            .count()
    };
    assert!(
        covered(&cut) < covered(&whole),
        "the lost entries were drawn: {} pixels against {}",
        covered(&cut),
        covered(&whole)
    );
    assert_clean(&device);
}

/// A frame slot's first frame sizes the pools by what the slot asked for before it:
/// nothing, whatever its counts' memory held. Host-visible buffers of the counts' size
/// filled with ones and freed come first, so the counts may take their memory; a second
/// slot prepared after the first slot's frame (as the viewer's second frame in flight
/// is) then keeps the pools. Seen failing without the counts zeroed when made: the
/// second slot's stale words asked for pools of 193.8 GiB, and they were refused.
#[test]
fn a_slots_first_frame_asks_the_pools_for_nothing() {
    use ash::vk;
    use gpu_allocator::MemoryLocation;
    let device = device();
    let size = ComputeCounts::BUFFER_BYTES;
    let stale: Vec<fur_gpu::gpu::Buffer> = (0..256)
        .map(|i| {
            let mut b = fur_gpu::gpu::Buffer::new(
                &device,
                &format!("stale[{i}]"),
                size,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::GpuToCpu,
            )
            .unwrap();
            b.write(0, &vec![0xff; size as usize]);
            b
        })
        .collect();
    drop(stale);
    let settings = blob_settings(Raster::Compute, 1);
    let mesh = fur_core::scene::Mesh::blob();
    let strands = fur_core::scene::Strands::grow(&mesh, &super::groom()).unwrap();
    let textures =
        fur_gpu::strand_textures::StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: 96,
        height: 72,
    };
    let mut renderer =
        fur_gpu::render::Renderer::new(&device, &mesh, &textures, extent, 2, 1).unwrap();
    renderer.render(&textures, &settings).unwrap();
    if let Err(e) = renderer.update(1, &settings) {
        panic!("the second slot's first frame: {e}");
    }
    assert_clean(&device);
}

/// The fragment counts are 64-bit: a frame of 16384×16384 pixels takes more than 2³²
/// fragments, and an add that wraps a count's low word carries into its high word.
/// With each pixel's counts added 2²⁰ times over (`FUR_TEST_FRAGMENT_SCALE`) the small
/// frame's counts pass 2³² several times: they come back exactly 2²⁰ times the plain
/// frame's, and the image is the same. Seen failing with the fragments' high word never
/// carried into: 1,035,993,088 fragments (wrapped) against 258,734,030,848.
#[test]
fn fragment_counts_carry_past_two_to_the_thirty_second() {
    const SCALE: u64 = 1 << 20;
    let device = device();
    let draw = |defines: &[(&str, &str)]| blob_in_compute(&device, defines);
    let (plain, plain_counts) = draw(&[]);
    let (scaled, scaled_counts) = draw(&[("FUR_TEST_FRAGMENT_SCALE", "1048576u")]);
    eprintln!("{plain_counts:?}\n{scaled_counts:?}");
    assert!(
        plain_counts.fragments * SCALE > 4 << 32 && plain_counts.tail_fragments * SCALE > 1 << 32,
        "the frame is too small to carry: {plain_counts:?}"
    );
    assert_eq!(scaled_counts.fragments, plain_counts.fragments * SCALE);
    assert_eq!(
        scaled_counts.tail_fragments,
        plain_counts.tail_fragments * SCALE
    );
    assert_eq!(plain.data, scaled.data, "counting changed the image");
    assert_clean(&device);
}
