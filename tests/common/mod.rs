//! Shared helpers for the GPU tests: a validated headless device and checks.
#![allow(dead_code)]

use std::sync::Arc;

use fur_gpu::gpu::Device;

// The CPU-side helpers live with the core's tests, shared here.
#[path = "../../crates/fur-core/tests/common/mod.rs"]
mod core_common;
#[allow(unused_imports)]
pub use core_common::{field_error, rounding, seed};

/// A small, quick drawing of the blob for the `fur` command line: its size, density
/// and segments.
pub const SMALL: [&str; 8] = [
    "--width",
    "96",
    "--height",
    "64",
    "--density-scale",
    "0.2",
    "--segments",
    "6",
];

/// A lavapipe-friendly headless device with the Khronos validation layer on, and a debug
/// messenger that hears it: without `VK_EXT_debug_utils` no messenger exists, every
/// [`assert_clean`] would pass on zero messages whatever the layer found, so the test
/// refuses to run.
pub fn device() -> Arc<Device> {
    let device = fur_gpu::gpu::headless(true)
        .expect("a Vulkan device with the validation layer (see README)");
    assert!(
        device.instance().has_debug_messenger(),
        "the validation layer is on but no debug messenger could be created \
         (VK_EXT_debug_utils is missing): its messages would go unheard and every \
         validation check would pass on zero messages; install a Vulkan loader and \
         validation layer that provide VK_EXT_debug_utils"
    );
    device
}

/// The path-traced reference renderer, or None (loudly) where it is not set up and
/// not required; with `FUR_REFERENCE_REQUIRED` set (CI, the README's test command) its
/// absence fails the test.
pub fn reference() -> Option<fur::export::reference::Reference> {
    match fur::export::reference::Reference::find(std::path::Path::new(env!("CARGO_MANIFEST_DIR")))
    {
        Ok(r) => Some(r),
        Err(e) if std::env::var_os("FUR_REFERENCE_REQUIRED").is_some() => {
            panic!("FUR_REFERENCE_REQUIRED is set: {e}")
        }
        Err(e) => {
            eprintln!("NOT RUN: {e}");
            None
        }
    }
}

/// Runs the `fur` binary with `args` (no backtraces: a panic shows as `panicked`).
pub fn fur(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the fur binary runs")
}

/// The standard output of a `fur` run that must have succeeded (its standard error in
/// the failure).
pub fn succeeded(out: &std::process::Output) -> String {
    assert!(
        out.status.success(),
        "fur failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The number before "hairs drawn" in `fur render`'s report ("… 12345 hairs drawn in …").
pub fn hairs_drawn(report: &str) -> u64 {
    let words: Vec<&str> = report.split_whitespace().collect();
    let i = words
        .windows(3)
        .position(|w| w[1] == "hairs" && w[2] == "drawn")
        .unwrap_or_else(|| panic!("no hair count in: {report}"));
    words[i].parse().unwrap()
}

/// An empty scratch folder `group/name` under the target's temporary folder.
pub fn scratch(group: &str, name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Straight hairs standing up (+Y) on a 1 × 1 plane: six segments of 0.06, uncombed.
pub fn standing_hairs_scene() -> (Mesh, GroomParams) {
    let plane = Mesh::grid(6, 6, 1.0);
    let groom = GroomParams {
        segments: 6,
        segment_length: 0.06,
        comb_strength: 0.0,
        ..Default::default()
    };
    (plane, groom)
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
use fur_core::render::{FrameSettings, RgbaImage};
use fur_core::scene::{GroomParams, Mesh, Strands};
use fur_gpu::gpu::FurStatistics;
use fur_gpu::render::{HairCounts, Renderer};
use fur_gpu::strand_textures::StrandTextures;

/// Renders `mesh` with `groom` once and returns the image, the fur pass's pipeline
/// statistics (none when no fur is drawn; read them through [`statistics`]) and the
/// hairs and segments the fur pass counted.
pub fn render(
    device: &Arc<Device>,
    mesh: &Mesh,
    groom: &GroomParams,
    settings: &FrameSettings,
    size: impl Into<fur_core::colour::Size>,
) -> (RgbaImage, Option<FurStatistics>, HairCounts) {
    let fur_core::colour::Size { width, height } = size.into();
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
    (image, report.statistics, counts)
}

/// The fur pass's pipeline statistics of a frame that drew fur: a test that reads them
/// fails when they are missing rather than comparing zeros.
pub fn statistics(statistics: Option<FurStatistics>) -> FurStatistics {
    statistics.expect(
        "no pipeline statistics for a frame that drew fur (the device lacks \
         pipelineStatisticsQuery, or the frame drew no fur)",
    )
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

/// Puts the device's current and previous positions into the CPU twin, so the next
/// frame on each starts from the same state and one frame's arithmetic is compared.
pub fn take_device_state(cpu: &mut fur_core::sim::CpuSim<f32>, textures: &StrandTextures) {
    let state = |which: usize| -> Vec<fur_core::sim::V3<f32>> {
        textures
            .read_positions(which)
            .unwrap()
            .into_iter()
            .map(fur_core::sim::V3::from_vec3)
            .collect()
    };
    cpu.current = state(textures.current);
    cpu.previous = state(1 - textures.current);
}

/// A file of the repository (a document, Cargo.toml) as text.
pub fn read_doc(path: &str) -> String {
    let full = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// Text as the documents write it: runs of spaces and line breaks read as one space.
pub fn flat(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The numbers in `text` (digits with an optional decimal part), as written. Digits
/// that continue a name (`f32`, `rgba32ui`, `F12`) are not numbers.
pub fn numbers(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    let mut previous = ' ';
    for c in text.chars().chain(std::iter::once(' ')) {
        let in_name = previous.is_alphabetic() || previous == '_';
        if (c.is_ascii_digit() && !(current.is_empty() && in_name))
            || (c == '.' && !current.is_empty())
            || (c == ',' && !current.is_empty())
        {
            current.push(c);
        } else if c.is_ascii_digit() {
            // a digit inside a name: skipped with the name
        } else if !current.is_empty() {
            let n = current.trim_end_matches(['.', ',']).to_string();
            out.push(n);
            current.clear();
        }
        if !(c.is_ascii_digit() && current.is_empty()) {
            previous = c;
        }
    }
    out
}

/// `line` without its code spans and link targets (paths, commands: not figures).
pub fn without_code_and_links(line: &str) -> String {
    let mut out = String::new();
    let mut in_code = false;
    let mut in_target = false;
    let mut previous = ' ';
    for c in line.chars() {
        match c {
            '`' => in_code = !in_code,
            '(' if previous == ']' => in_target = true,
            ')' if in_target => in_target = false,
            _ if !in_code && !in_target => out.push(c),
            _ => {}
        }
        previous = c;
    }
    out
}

/// `text` without its generated regions (`<!-- BEGIN x -->` to `<!-- END x -->`, each
/// written by the run it names) and fenced blocks.
pub fn prose(text: &str) -> String {
    let mut out = Vec::new();
    let (mut generated, mut fenced) = (false, false);
    for line in text.lines() {
        if line.starts_with("<!-- BEGIN ") {
            generated = true;
        } else if line.starts_with("<!-- END ") {
            generated = false;
        } else if line.starts_with("```") {
            fenced = !fenced;
        } else if !generated && !fenced {
            out.push(line);
        }
    }
    out.join("\n")
}
