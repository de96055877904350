//! The phrases the documents must hold word for word, each built from the constant it
//! states.

use super::common::read_doc as read;
use fur_core::files::{self, size_text};

/// A whole number with thousands separated by commas, as the documents write counts.
pub fn count_text(n: u64) -> String {
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
pub fn stated() -> Vec<(&'static str, Vec<String>)> {
    let mut all = limits();
    all.extend(design());
    all.extend(super::simulation::simulation());
    // The compute rasteriser's pool table, line by line (the documents are read flat).
    let pools = fur_core::render::strand_raster::pools::table(
        &fur_core::render::strand_raster::pools::PoolBudget::default(),
    );
    let mut raster: Vec<String> = pools
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(super::common::flat)
        .collect();
    // The fragments a pixel keeps in order, in words: the phrase exists only for the
    // values it names.
    let nearest = (
        fur_core::render::FurStyle::default().nearest,
        fur_core::render::MAX_NEAREST,
    );
    raster.push(
        (if nearest == (8, 16) {
            "`--nearest`: eight by default, one to sixteen)"
        } else {
            "(the default or the most of `nearest` changed: say it in docs/compute-raster.md)"
        })
        .to_string(),
    );
    // What lights a vertex under the Marschner model, in its colour's place.
    raster.push(format!(
        "the {} bytes of the vertex's colour",
        fur_core::render::strand_raster::pools::VERTEX_TEXEL_BYTES
    ));
    // The depth bins and the opacity a pixel stops at.
    use fur_core::render::strand_raster::order::{DEPTH_BINS, OPAQUE_TRANSMIT, ROW_RUN};
    raster.push(format!("is cut into {DEPTH_BINS} equal depth bins"));
    // The runs of entries whose masks become rows.
    raster.push(format!("turns each whole run of {ROW_RUN} entries' masks"));
    raster.push(format!("reads one word for {ROW_RUN} entries"));
    raster.push(format!("it skips all {ROW_RUN} at once"));
    raster.push(format!("search skips a run of {ROW_RUN} entries a turn"));
    raster.push(format!(
        "let through less than 1/{} of the light",
        (1.0 / OPAQUE_TRANSMIT).round()
    ));
    // The tile sides.
    let sides = fur_core::render::TILE_SIZES.map(|t| t.to_string());
    let (last, first) = sides.split_last().expect("tile sides");
    raster.push(format!("`--tile`: {} or {last} pixels)", first.join(", ")));
    let side = fur_core::render::DEFAULT_TILE;
    raster.push(format!("whose {}-pixel workgroup", side * side));
    all.push(("docs/compute-raster.md", raster));
    // The tiles view's scale.
    let full = count_text(fur_core::render::stage::TILE_ENTRIES_FULL_SCALE as u64);
    all.push(("docs/pipeline.md", vec![format!("red for {full} or more")]));
    all.push((
        "docs/scene-files.md",
        vec![format!("blue one to red {full},")],
    ));
    all
}

/// A power of ten as the documents write it (`10⁻⁶`).
fn power_of_ten(x: f32) -> String {
    let exponent = x.log10().round() as i32;
    assert_eq!(10f32.powi(exponent), x, "{x} is not a power of ten");
    let superscript = |c: char| match c {
        '-' => '⁻',
        d => ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'][d.to_digit(10).unwrap() as usize],
    };
    format!(
        "10{}",
        exponent
            .to_string()
            .chars()
            .map(superscript)
            .collect::<String>()
    )
}

/// A colour channel as design.md writes it: three decimals, or two significant digits
/// under a hundredth.
fn channel(x: f32) -> String {
    if x >= 0.01 {
        format!("{x:.3}")
    } else {
        let digits = (1 - x.log10().floor() as i32) as usize;
        format!("{x:.digits$}")
    }
}

/// The defaults, formats and counts the design documents state.
fn design() -> Vec<(&'static str, Vec<String>)> {
    use fur_core::render::FurPreset;
    let scene = fur_core::scene_file::SceneOptions::default();
    let sim = fur_core::sim::params::SimParams::default();
    let style = fur_core::render::uniforms::FurStyle::default();
    let fibre = fur_core::render::Fibre::default();
    let frame = format!("1/{}", (1.0 / sim.dt).round());
    // The original demo's sphere: its bands from its counts (V = (r − 1)(s + 1) + 2,
    // T = 2s(r − 1)), its radius and segment length from its size.
    let sphere: fur_core::scene::ModelSpec = "sphere".parse().unwrap();
    let sphere = sphere.load().unwrap();
    let (v, t) = (sphere.vertex_count() as u64, sphere.triangle_count() as u64);
    let bands = t / (2 * (v - 2) - t);
    let rings = t / (2 * bands) + 1;
    let radius = sphere
        .positions
        .iter()
        .map(|p| p.length())
        .fold(0.0, f32::max);
    let original = fur_core::scene_file::SceneOptions::original();
    let half_diagonal = radius * 3f32.sqrt();
    let segment =
        (original.hair_length * half_diagonal / original.segments as f32 * 1000.0).round() / 1000.0;
    // The fur presets' melanin, absorption and colours.
    let melanin: Vec<String> = FurPreset::ALL
        .iter()
        .filter_map(|p| p.melanin().map(|m| (p.name(), m)))
        .map(|(name, (eu, pheo))| match (eu, pheo) {
            (0.0, 0.0) => format!("`{name}` (none)"),
            (eu, 0.0) => format!("`{name}` (eumelanin {eu})"),
            (eu, pheo) => format!("`{name}` (eumelanin {eu}, pheomelanin {pheo})"),
        })
        .collect();
    let triple =
        |c: glam::Vec3, f: &dyn Fn(f32) -> String| format!("({}, {}, {})", f(c.x), f(c.y), f(c.z));
    let beta_n = fibre.azimuthal_roughness;
    let colour = |p: FurPreset| p.colour(beta_n).unwrap();
    let srgb = |x: f32| {
        format!(
            "{:.2}",
            f32::from(fur_core::colour::linear_to_srgb8(x)) / 255.0
        )
    };
    let openusd = read("Cargo.lock")
        .split("name = \"openusd\"\nversion = \"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .map(|v| v.trim_end_matches(".0").to_string())
        .expect("Cargo.lock pins openusd");
    let dense: fur_core::scene::ModelSpec = "dense-sphere".parse().unwrap();
    let thousands = (dense.load().unwrap().positions.len() + 500) / 1000;
    vec![
        (
            "docs/design.md",
            vec![
                format!("`segments` (default {})", scene.segments),
                // How grown fur lies (fur_core::scene::flow, fur_core::scene::groom::comb).
                format!(
                    "time is ({} % of the body's size)²",
                    fur_core::scene::HEAT_TIME * 100.0
                ),
                format!(
                    "an axis that leans less than {} towards z",
                    fur_core::scene::AXIS_LEAN
                ),
                format!(
                    "a peak over the last {} % of the body's extent",
                    fur_core::scene::CAP * 100.0
                ),
                format!(
                    "is at most {} of the body's (its {}th percentile",
                    fur_core::scene::THIN,
                    fur_core::scene::BODY_PERCENTILE
                ),
                format!(
                    "each segment rising about {}° from the tangent plane",
                    (1.0 / fur_core::scene::FLAT_LEAN).atan().to_degrees().round()
                ),
                format!("from {} of the body's up", fur_core::scene::THICK),
                format!(
                    "not at all at {} or less",
                    fur_core::scene::ONE_BONE
                ),
                format!(
                    "offset is at most {} of the hair's own reach",
                    fur_core::render::uniforms::JITTER_SHARE
                ),
                format!(
                    "({} × the half-thickness in the default scene)",
                    scene.thickness_limit
                ),
                format!(
                    "each at most {} × the model's local half-thickness long",
                    scene.thickness_limit
                ),
                format!("the tolerance (default {} px)", style.vertex_lod_px),
                format!("never drawn under {} px", style.min_pixel_width),
                format!(
                    "(`--target-fps`, default {};",
                    fur::viewer::DEFAULT_TARGET_FPS
                ),
                format!(
                    "never more than {} × the model's local half-thickness",
                    scene.thickness_limit
                ),
                format!(
                    "a UV sphere of radius {radius} with {rings} × {bands} bands ({} vertices with the seam duplicated, {} triangles",
                    count_text(v),
                    count_text(t)
                ),
                format!(
                    "one master hair of {} vertices and segments of {segment} per vertex",
                    original.segments + 1
                ),
            ],
        ),
        (
            "docs/lighting.md",
            vec![
                format!(
                    "(`[fibre] direction_spread`, the default {} rad²)",
                    fur_core::render::DIRECTION_SPREAD
                ),
                format!(
                    "defaults {}, {}, {}°, {})",
                    fibre.longitudinal_roughness,
                    fibre.azimuthal_roughness,
                    fibre.cuticle_tilt_deg,
                    fibre.ior
                ),
                format!("melanin, the pigments of hair: {};", melanin.join(", ")),
                format!(
                    "σa = eumelanin · {} + pheomelanin · {}",
                    triple(fur_core::render::presets::EUMELANIN_SIGMA_A, &|x| x.to_string()),
                    triple(fur_core::render::presets::PHEOMELANIN_SIGMA_A, &|x| x.to_string())
                ),
                format!(
                    "at β_n = {beta_n} they are white {}, blond {}, ginger {}, brown {} and black (≈ 0)",
                    triple(colour(FurPreset::White), &|x| x.to_string()),
                    triple(colour(FurPreset::Blond), &channel),
                    triple(colour(FurPreset::Ginger), &channel),
                    triple(colour(FurPreset::Brown), &channel)
                ),
                format!(
                    "(blond is {} in sRGB)",
                    triple(colour(FurPreset::Blond), &srgb)
                ),
            ],
        ),
        (
            "docs/pipeline.md",
            vec![format!("step ({frame} s)")],
        ),
        (
            "docs/grooms.md",
            vec![
                format!("(d below {} radii)", power_of_ten(fur_core::scene::EXACT_ROOT)),
                format!(
                    "the {thousands}K-vertex `dense-sphere` reading its own {thousands}K-guide groom"
                ),
                format!("version {openusd} of `openusd`"),
                format!("fur writes the layer with {openusd},"),
            ],
        ),
    ]
}

/// The limits, targets and defaults the other documents state.
fn limits() -> Vec<(&'static str, Vec<String>)> {
    use fur_core::render::dual_scattering as ds;
    // The table's darkest colour node, whose logarithm the code holds.
    let darkest = 1e-4f32;
    assert!((darkest.ln() - ds::LN_MIN_COLOUR).abs() < 1e-6);
    let calibration = fur::export::compare::Calibration::MAX_SHIFT_PX;
    let radiance = fur::export::compare::Calibration::MAX_RATIO_ERROR;
    let (low, high) = fur_core::scene::Mesh::SCALE_RANGE;
    let cargo = read("Cargo.toml");
    let rust = cargo
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = \""))
        .and_then(|v| v.strip_suffix('"'))
        .expect("Cargo.toml states its rust-version");
    let idle = fur_core::render::budget::Budget::IDLE_SECONDS;
    // The goal's body (`dense-sphere`), whose vertices the README's groom and the GPU
    // goal's masters are.
    let dense: fur_core::scene::ModelSpec = "dense-sphere".parse().unwrap();
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
                format!("over {} on a side", fur_core::scene::Texture::MAX_SIDE),
                format!(
                    "over {}, of an unknown extension",
                    size_text(fur_core::groom_file::MAX_GROOM_BYTES)
                ),
                format!(
                    "| a groom file's size | {}, checked before reading; at most {} + 1 byte",
                    size_text(fur_core::groom_file::MAX_GROOM_BYTES),
                    size_text(fur_core::groom_file::MAX_GROOM_BYTES)
                ),
                format!(
                    "| memory of USD's decoding | {} × the file's size + {} of address space",
                    fur_core::groom_file::USD_MEMORY_PER_BYTE,
                    size_text(fur_core::groom_file::USD_MEMORY_BASE)
                ),
                format!(
                    "| CPU time of USD's decoding | {} s + {} s a MiB (`RLIMIT_CPU`), and twice \
                     that + {} s of wall time",
                    fur_core::groom_file::USD_SECONDS_BASE,
                    fur_core::groom_file::USD_SECONDS_PER_MIB,
                    fur_core::groom_file::USD_WALL_SLACK_SECONDS
                ),
                format!(
                    "nested over {} brackets deep",
                    count_text(fur_core::groom_file::MAX_TEXT_NESTING as u64)
                ),
                format!(
                    "| USD text nesting | {} brackets |",
                    count_text(fur_core::groom_file::MAX_TEXT_NESTING as u64)
                ),
                format!(
                    "| prims visited, prim nesting | 2{} prims, {} deep |",
                    if fur_core::groom_file::MAX_PRIMS == 1 << 20 { "²⁰" } else { "(MAX_PRIMS changed)" },
                    fur_core::groom_file::MAX_DEPTH
                ),
                format!(
                    "| notes kept (what reading changed) | {} |",
                    fur_core::groom_file::MAX_NOTES
                ),
                format!(
                    "| a curve's vertices after reading | {} |",
                    count_text(fur_core::groom_file::MAX_CURVE_VERTICES as u64)
                ),
                format!(
                    "over {} bounding radii from the body",
                    fur_core::scene::BIND_LIMIT
                ),
                format!("over {}, a warning", fur_core::scene::BIND_TOLERANCE),
                format!(
                    "would pass {}",
                    size_text(fur_core::skinning::blend::MAX_BYTES as u64)
                ),
                format!(
                    "more than {} strand vertices",
                    count_text(fur_gpu::session::MAX_STRAND_VERTICES)
                ),
                format!(
                    "more than {} hair segments a frame",
                    count_text(fur_gpu::session::MAX_SEGMENTS_PER_FRAME)
                ),
                format!(
                    "a render target over {}",
                    size_text(fur_gpu::session::MAX_TARGET_BYTES)
                ),
                format!(
                    "over {} to capture, or whose file would pass {}",
                    size_text(fur_gpu::render::MAX_CAPTURE_BYTES),
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
                    count_text(fur_core::groom_file::MAX_CURVE_VERTICES as u64)
                ),
                format!(
                    "A root farther than **{} bounding radii** from the surface is reported",
                    fur_core::scene::BIND_TOLERANCE
                ),
                format!(
                    "A root farther than **{} bounding radii** refuses the groom",
                    fur_core::scene::BIND_LIMIT
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
                    fur_core::render::Shadows::default().opacity
                ),
                format!(
                    "(at least `--min-pixel-width`, {} px)",
                    fur_core::render::uniforms::FurStyle::default().min_pixel_width
                ),
            ],
        ),
        (
            "docs/lighting.md",
            vec![
                format!(
                    "The table holds them at {} angles (|sin θ| 0 to 1) and {} colours (evenly in ln c from 1 to {}",
                    ds::ANGLE_NODES,
                    ds::COLOUR_NODES,
                    power_of_ten(darkest)
                ),
                format!(
                    "the table's colour coordinate (ln c / ln {})",
                    power_of_ten(darkest)
                ),
                format!(
                    "d_f = d_b = {} are the paper's density factors",
                    ds::DENSITY_FORWARD
                ),
            ],
        ),
    ]
}
