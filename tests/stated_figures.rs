//! The limits, targets and defaults the documents state are the code's. Each phrase
//! below is built from the constant it states and must stand in its document word for
//! word, so changing either the constant or the document fails here (seen failing with
//! the model limit changed to 3 GiB, and with the README's Rust version one behind).
//!
//! Figures measured by a run are bound elsewhere: the README's against the generated
//! tables (`docs.rs`), the ratios it derives from them below, and every figure inside a
//! `<!-- BEGIN … -->` region is a benchmark figure, written by the run the region names.

#[path = "common/mod.rs"]
mod common;

use common::{flat, read_doc as read};

use fur::files::{self, size_text};

/// A whole number with thousands separated by commas, as the documents write counts.
fn count_text(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Each document and the phrases it must hold, built from the code.
fn stated() -> Vec<(&'static str, Vec<String>)> {
    let calibration = fur::export::compare::Calibration::MAX_SHIFT_PX;
    let radiance = fur::export::compare::Calibration::MAX_RATIO_ERROR;
    let (low, high) = fur::scene::Mesh::SCALE_RANGE;
    let cargo = read("Cargo.toml");
    let rust = cargo
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = \""))
        .and_then(|v| v.strip_suffix('"'))
        .expect("Cargo.toml states its rust-version");
    let idle = fur::render::budget::Budget::IDLE_SECONDS;
    let near = fur::sim::collide::NEAR_CAPSULES;
    // The goal's body (`dense-sphere`), whose vertices the README's groom and the GPU
    // goal's masters are.
    let dense: fur::scene::ModelSpec = "dense-sphere".parse().unwrap();
    let dense = dense.load().unwrap().positions.len() as u64;
    vec![
        (
            "docs/robustness.md",
            vec![
                format!(
                    "a model over {}, a texture over {}, a material library over {}, a scene file over {}",
                    size_text(files::MAX_MODEL_BYTES),
                    size_text(files::MAX_TEXTURE_BYTES),
                    size_text(files::MAX_MATERIAL_BYTES),
                    size_text(files::MAX_SCENE_BYTES)
                ),
                format!("over {} on a side", fur::scene::Texture::MAX_SIDE),
                format!(
                    "over {}, of an unknown extension",
                    size_text(fur::groom_file::MAX_GROOM_BYTES)
                ),
                format!(
                    "over {} bounding radii from the body",
                    fur::scene::BIND_LIMIT
                ),
                format!("over {}, a warning", fur::scene::BIND_TOLERANCE),
                format!(
                    "would pass {}",
                    size_text(fur::skinning::blend::MAX_BYTES as u64)
                ),
                format!(
                    "more than {} strand vertices",
                    count_text(fur::session::MAX_STRAND_VERTICES)
                ),
                format!(
                    "more than {} hair segments a frame",
                    count_text(fur::session::MAX_SEGMENTS_PER_FRAME)
                ),
                format!(
                    "a render target over {}",
                    size_text(fur::session::MAX_TARGET_BYTES)
                ),
                format!(
                    "over {} to capture, or whose file would pass {}",
                    size_text(fur::render::MAX_CAPTURE_BYTES),
                    size_text(fur::export::MAX_EXPORT_BYTES)
                ),
                format!(
                    "big-endian or over {}",
                    size_text(fur::export::reference::MAX_PFM_BYTES)
                ),
                format!("outside {low:e}…{high:e} units"),
            ],
        ),
        (
            "README.md",
            vec![
                format!("Rust {rust} or newer is needed"),
                format!("an imported groom of {} curly strands", count_text(dense)),
                format!("the performance goal's {}K-vertex body", (dense + 500) / 1000),
                // The idle time in words: the phrase exists only for the value it names.
                (if idle == 0.5 {
                    "half a second after input stops"
                } else {
                    "(IDLE_SECONDS changed: say it in the README)"
                })
                .to_string(),
                format!(
                    "(`--target-fps`, default {})",
                    fur::viewer::DEFAULT_TARGET_FPS
                ),
                format!(
                    "the target of {} % of the hair length",
                    100.0 * fur::bench::DEPTH_TARGET
                ),
            ],
        ),
        (
            "docs/gpu.md",
            vec![format!("{} masters on the built-in `dense-sphere`", count_text(dense))],
        ),
        (
            "docs/grooms.md",
            vec![
                format!("such a groom: {} curly strands", count_text(dense)),
                format!(
                    "A curve may have at most {} vertices after evaluation",
                    count_text(fur::groom_file::MAX_CURVE_VERTICES as u64)
                ),
                format!(
                    "A root farther than **{} bounding radii** from the surface is reported",
                    fur::scene::BIND_TOLERANCE
                ),
                format!(
                    "A root farther than **{} bounding radii** refuses the groom",
                    fur::scene::BIND_LIMIT
                ),
            ],
        ),
        (
            "docs/ground-truth.md",
            vec![format!(
                "lie within {calibration} px, and the mean linear radiance over the pixels both cover agrees within {} %",
                100.0 * radiance
            )],
        ),
        (
            "docs/design.md",
            vec![
                format!(
                    "(`--shadow-opacity {}` = α",
                    fur::render::Shadows::default().opacity
                ),
                format!(
                    "(at least `--min-pixel-width`, {} px)",
                    fur::render::uniforms::FurStyle::default().min_pixel_width
                ),
                format!(
                    "with the {} bone capsules nearest its root",
                    ["no", "one", "two", "three", "four", "five", "six"][near.min(6)]
                ),
            ],
        ),
    ]
}

#[test]
fn the_limits_targets_and_defaults_the_documents_state_are_the_codes() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for (doc, phrases) in stated() {
        let text = flat(&read(doc));
        for phrase in phrases {
            checked += 1;
            if !text.contains(&phrase) {
                missing.push(format!("{doc}: \"{phrase}\""));
            }
        }
    }
    assert!(checked >= 20, "only {checked} phrases checked");
    assert!(
        missing.is_empty(),
        "the documents do not state what the code does:\n{}",
        missing.join("\n")
    );
}

#[test]
fn counts_are_written_with_commas() {
    assert_eq!(count_text(8_000_000), "8,000,000");
    assert_eq!(count_text(999), "999");
    assert_eq!(count_text(1000), "1,000");
    assert_eq!(size_text(2 << 30), "2 GiB");
}
