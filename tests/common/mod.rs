//! Shared helpers for the GPU tests: a validated headless device and checks.
#![allow(dead_code)]

use std::sync::Arc;

use fur::gpu::Device;

/// A lavapipe-friendly headless device with the Khronos validation layer on.
pub fn device() -> Arc<Device> {
    fur::gpu::headless(true).expect("a Vulkan device with the validation layer (see README)")
}

/// Fails the test if the validation layer reported anything.
pub fn assert_clean(device: &Arc<Device>) {
    let messages = device.instance().validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation message(s):\n{}",
        messages.len(),
        messages.join("\n")
    );
}

use ash::vk;
use fur::gpu::FurStatistics;
use fur::render::{FrameSettings, HairCounts, Renderer, RgbaImage};
use fur::scene::{GroomParams, Mesh, Strands};
use fur::strand_textures::StrandTextures;

/// Renders `mesh` with `groom` once and returns the image, the fur statistics and the
/// hairs and segments the fur pass counted.
pub fn render(
    device: &Arc<Device>,
    mesh: &Mesh,
    groom: &GroomParams,
    settings: &FrameSettings,
    (width, height): (u32, u32),
) -> (RgbaImage, FurStatistics, HairCounts) {
    let strands = Strands::grow(mesh, groom).unwrap();
    let textures = StrandTextures::new(device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D { width, height };
    let mut renderer =
        Renderer::new(device, mesh, &textures, extent, 1, settings.style.samples).unwrap();
    let settings = FrameSettings {
        count_hairs: true,
        ..settings.clone()
    };
    let (image, report) = renderer.render(&textures, &settings).unwrap();
    let counts = report
        .counts
        .expect("lavapipe counts hairs (vertexPipelineStoresAndAtomics)");
    (image, report.statistics.unwrap_or_default(), counts)
}

/// Pixels that differ from the clear colour.
pub fn covered(image: &RgbaImage) -> Vec<bool> {
    let background = image.pixel(0, 0);
    (0..image.height)
        .flat_map(|y| (0..image.width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let p = image.pixel(x, y);
            (0..3).any(|c| p[c].abs_diff(background[c]) > 3)
        })
        .collect()
}

/// Writes an image for a person to look at when a test fails.
pub fn keep(image: &RgbaImage, name: &str) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("images");
    let path = dir.join(format!("{name}.png"));
    if image.write_png(&path).is_ok() {
        eprintln!("image: {}", path.display());
    }
}
