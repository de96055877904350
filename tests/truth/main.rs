//! Ground truth (lavapipe, validation on): the capture holds exactly the hairs a frame
//! draws, `fur export-frame` writes them so that Pixar's usd-core reads the same counts,
//! and the path tracer agrees with fur's drawing on every convention (the calibration),
//! which a deliberately wrong convention fails.
//!
//! The tests that run the reference renderer need `tools/reference/setup.sh` (or
//! `FUR_REFERENCE_PYTHON`); without it they say so loudly and stop, unless
//! `FUR_REFERENCE_REQUIRED` is set (CI sets it), when they fail.

#[path = "../common/mod.rs"]
mod common;

mod calibration;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use ash::vk;
use fur::export::reference::read_pfm;
use fur_core::render::direction_spread::direction_spread;
use fur_core::render::{FrameSettings, RgbaImage};
use fur_core::scene::{ModelSpec, Strands};
use fur_core::scene_file::Scene;
use fur_gpu::render::Renderer;
use fur_gpu::strand_textures::StrandTextures;
use glam::Vec3;

fn fur(args: &[&str]) -> Output {
    common::fur(args)
}

fn scratch(name: &str) -> PathBuf {
    common::scratch("truth", name)
}

/// The blob's default scene, small, drawn and captured by the library.
fn captured(
    device: &std::sync::Arc<fur_gpu::gpu::Device>,
    mesh: Option<fur_core::scene::Mesh>,
    edit: impl FnOnce(&mut FrameSettings),
    size: impl Into<fur_core::colour::Size>,
) -> (
    RgbaImage,
    fur_gpu::render::CapturedHairs,
    FrameSettings,
    u64,
) {
    let fur_core::colour::Size { width, height } = size.into();
    let scene = Scene::defaults(ModelSpec::Blob);
    let mesh = mesh.unwrap_or_else(|| scene.model.load_body().unwrap().0);
    let (groom, mut settings) = scene.options.resolve(&mesh).unwrap();
    edit(&mut settings);
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let textures = StrandTextures::new(device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D { width, height };
    let mut renderer =
        Renderer::new(device, &mesh, &textures, extent, 1, settings.style.samples).unwrap();
    let counting = FrameSettings {
        count_hairs: true,
        ..settings.clone()
    };
    let (_, report) = renderer.render(&textures, &counting).unwrap();
    let (image, hairs) = renderer.capture(&textures, &settings).unwrap();
    (image, hairs, settings, report.counts.unwrap().hairs)
}

#[test]
fn the_capture_holds_the_hairs_as_drawn() {
    let device = common::device();
    let (_, hairs, settings, drawn) = captured(&device, None, |_| {}, (160, 90));
    let v = hairs.vertices_per_strand;
    assert!(drawn > 1000, "the frame draws {drawn} hairs");
    assert_eq!(
        hairs.count() as u64,
        drawn,
        "one captured hair per hair drawn"
    );
    assert_eq!(hairs.points.len(), hairs.count() * v);
    let style = &settings.style;
    let eye = settings.camera.eye();
    let lighting = &settings.lighting;
    for h in 0..hairs.count() {
        let at = h * v;
        let root = hairs.points[at];
        // The width the geometry stage gives the root: the style's, widened by the
        // density LOD's thinning (thickness compensation).
        let lod = (style.lod_distance / root.distance(eye)).powi(2).min(1.0);
        let expected = if style.thickness_compensation {
            style.hair_width / lod
        } else {
            style.hair_width
        };
        let (w_root, w_tip) = (hairs.widths[at], hairs.widths[at + v - 1]);
        assert!(
            (w_root - expected).abs() <= 1e-5 * expected,
            "hair {h}: root width {w_root}, drawn at {expected}"
        );
        assert!(
            (w_tip - 0.2 * w_root).abs() <= 1e-5 * w_root,
            "hair {h}: tip {w_tip}"
        );
        for k in 0..v {
            assert!(hairs.drawn_widths[at + k] >= hairs.widths[at + k] * (1.0 - 1e-6));
        }
        let (c_root, c_tip) = (hairs.colors[at], hairs.colors[at + v - 1]);
        assert!(
            c_root.abs_diff_eq(lighting.root_color, 1e-6),
            "hair {h}: {c_root}"
        );
        assert!(
            c_tip.abs_diff_eq(lighting.tip_color, 1e-6),
            "hair {h}: {c_tip}"
        );
    }
    // A fixed order: each hair's seed, ascending (the device hands out places as it runs).
    common::assert_clean(&device);
}

/// The Marschner model's default direction spread is the default blob's: its drawn
/// hairs' neighbours differ in direction by a mean squared angle within a fifth of the
/// default (the blob's hairs at rest; simulated, the truth benchmark reports them per
/// scene). Seen failing against the default of parallel hairs, 0.
#[test]
fn the_default_direction_spread_is_the_default_blobs() {
    let device = common::device();
    let (_, hairs, settings, _) = captured(&device, None, |_| {}, (160, 90));
    let measured = direction_spread(&hairs.points, hairs.vertices_per_strand).unwrap();
    let default = f64::from(settings.lighting.fibre.direction_spread);
    eprintln!("the blob's drawn hairs' direction spread: {measured:.4} rad²");
    assert!(
        (measured - default).abs() <= 0.2 * default,
        "the default blob's hairs spread by {measured:.4} rad², the default is {default}"
    );
    common::assert_clean(&device);
}

/// Each interpolated hair's random tip offset is at most `JITTER_SHARE` of its own
/// reach from root to tip: with a jitter far longer than the hair, every captured tip
/// lies that share of the hair's reach from where it lies without jitter (the same hair
/// found by its root, which jitter does not move). Seen failing with the offset
/// uncapped (the blob's short ear hair scattered into tufts).
#[test]
fn a_hairs_jitter_is_at_most_a_share_of_its_own_reach() {
    let device = common::device();
    let run = |jitter: f32| {
        let (_, hairs, _, _) = captured(
            &device,
            None,
            |s| {
                s.style.jitter = jitter;
                s.style.length_jitter = 0.0;
            },
            (160, 90),
        );
        let v = hairs.vertices_per_strand;
        (0..hairs.count())
            .map(|h| {
                let (root, tip) = (hairs.points[h * v], hairs.points[h * v + v - 1]);
                (root.to_array().map(f32::to_bits), (root, tip))
            })
            .collect::<std::collections::HashMap<_, _>>()
    };
    let still = run(0.0);
    let scattered = run(100.0);
    assert!(still.len() > 1000, "{} hairs", still.len());
    assert_eq!(still.len(), scattered.len());
    let share = fur_core::render::uniforms::JITTER_SHARE;
    for (key, (root, tip)) in &still {
        let (_, moved) = scattered[key];
        let (offset, reach) = (moved.distance(*tip), tip.distance(*root));
        assert!(
            (offset - share * reach).abs() <= 1e-3 * reach + 1e-6,
            "a hair of reach {reach} moved {offset}"
        );
    }
}

#[test]
fn captured_hairs_project_onto_the_pixels_drawn() {
    let device = common::device();
    let (width, height) = (160u32, 90u32);
    // A few hairs on a coarse sphere: a wrong projection lands on empty pixels.
    let (image, hairs, settings, _) = captured(
        &device,
        Some(fur_core::scene::Mesh::icosphere(1)),
        |s| {
            // The hair alone, opaque: every pixel a hair crosses differs from the clear colour.
            // Through the fixed-function rasteriser, whose one sample covers a pixel
            // whole or not at all: the compute passes' exact coverage leaves a faint
            // share in the pixels around, so a mirrored projection lands on drawn pixels
            // too and the check could not fail (measured: 397 of 714).
            s.style.raster = fur_core::render::Raster::Hardware;
            s.draw_mesh = false;
            s.style.thin_hair_aa = false;
            s.style.samples = 1;
            s.style.fixed_level = 1; // the master hairs only: sparse
            s.style.min_pixel_width = 2.0; // a hair seen end-on still covers a pixel
            s.style.cull = false;
            // Bright and unlit, so that no hair is as dark as the background.
            s.lighting.root_occlusion = 0.0;
            s.lighting.root_color = Vec3::ONE;
            s.lighting.tip_color = Vec3::ONE;
            s.lighting.ambient = 1.0;
        },
        (width, height),
    );
    let covered = common::covered(&image);
    let view_proj = settings
        .camera
        .view_projection(width as f32 / height as f32);
    let hits = |mirror: bool| {
        let (mut hit, mut total) = (0, 0);
        for p in &hairs.points {
            let c = view_proj * p.extend(1.0);
            let ndc = c.truncate() / c.w;
            let mut x = ((ndc.x * 0.5 + 0.5) * width as f32).floor() as i64;
            let y = ((ndc.y * 0.5 + 0.5) * height as f32).floor() as i64;
            if mirror {
                x = i64::from(width) - 1 - x;
            }
            if x < 1 || y < 1 || x >= i64::from(width) - 1 || y >= i64::from(height) - 1 {
                continue;
            }
            total += 1;
            let near = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| covered[((y + dy) * i64::from(width) + x + dx) as usize])
            });
            hit += usize::from(near);
        }
        (hit, total)
    };
    let (hit, total) = hits(false);
    assert!(total > 300, "{total} vertices on screen");
    assert!(
        hit as f64 >= 0.99 * total as f64,
        "{hit} of {total} captured vertices land on drawn pixels"
    );
    // The same check with the image mirrored fails: it can tell a wrong projection.
    let (mirrored, _) = hits(true);
    assert!(
        (mirrored as f64) < 0.5 * total as f64,
        "a mirrored projection also lands on drawn pixels ({mirrored} of {total}): the check \
         cannot fail"
    );
    common::assert_clean(&device);
}

/// Exports `args` with the binary (validation on); returns the file's text and stdout.
fn export(dir: &Path, args: &[&str]) -> (PathBuf, String) {
    let usda = dir.join("frame.usda");
    let png = dir.join("fur.png");
    let mut all = vec![
        "export-frame",
        usda.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
        "--validate",
    ];
    all.extend_from_slice(args);
    let out = fur(&all);
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "export-frame {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (usda, stdout)
}

/// The number before `what` in `text` ("1234 hairs").
fn number_before(text: &str, what: &str) -> u64 {
    let end = text
        .find(what)
        .unwrap_or_else(|| panic!("no `{what}` in {text}"));
    let digits: String = text[..end]
        .trim_end()
        .chars()
        .rev()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.chars().rev().collect::<String>().parse().unwrap()
}

#[test]
fn the_export_holds_what_render_draws_and_usd_core_reads_it() {
    let dir = scratch("counts");
    let size = ["--width", "96", "--height", "54", "--density-scale", "0.5"];
    let (usda, stdout) = export(&dir, &size);
    let exported = number_before(&stdout, " hairs of");
    let png = dir.join("render.png");
    let mut render = vec!["render", "--validate", "--out", png.to_str().unwrap()];
    render.extend_from_slice(&size);
    let out = fur(&render);
    assert!(out.status.success());
    let drawn = number_before(&String::from_utf8_lossy(&out.stdout), " hairs drawn");
    assert_eq!(
        exported, drawn,
        "export-frame exports the hairs `fur render` draws"
    );
    // The same frame: the export's image is the render's, byte for byte.
    let (a, b) = (
        image::open(dir.join("fur.png")).unwrap().to_rgba8(),
        image::open(&png).unwrap().to_rgba8(),
    );
    let differ = a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
    assert_eq!(
        differ, 0,
        "the export's image differs from the render's in {differ} pixels"
    );
    let text = std::fs::read_to_string(&usda).unwrap();
    let counts = text
        .lines()
        .find(|l| l.trim_start().starts_with("int[] curveVertexCounts"))
        .unwrap();
    assert_eq!(counts.matches(',').count() as u64 + 1, exported);
    let Some(reference) = common::reference() else {
        return;
    };
    let read = Command::new(reference.python())
        .args([
            "-c",
            "import sys\nfrom pxr import Usd, UsdGeom\ns = Usd.Stage.Open(sys.argv[1])\n\
             c = UsdGeom.BasisCurves(s.GetPrimAtPath('/World/Hair'))\n\
             m = UsdGeom.Mesh(s.GetPrimAtPath('/World/Body'))\n\
             cam = UsdGeom.Camera(s.GetPrimAtPath('/World/Camera')).GetCamera()\n\
             print(len(c.GetCurveVertexCountsAttr().Get()), len(c.GetPointsAttr().Get()), \
             len(c.GetWidthsAttr().Get()), len(m.GetFaceVertexCountsAttr().Get()), \
             round(cam.GetFieldOfView(cam.FOVVertical), 4))",
        ])
        .arg(&usda)
        .output()
        .unwrap();
    let line = String::from_utf8_lossy(&read.stdout).trim().to_string();
    assert!(
        read.status.success(),
        "{}",
        String::from_utf8_lossy(&read.stderr)
    );
    let v = 17; // the default 16 segments
    let blob_triangles = fur_core::scene::Mesh::blob().triangle_count();
    assert_eq!(
        line,
        format!(
            "{exported} {} {} {blob_triangles} 40.0",
            exported * v,
            exported * v
        )
    );
    // The same frame as binary USD: usd-core reads every prim and every attribute's
    // value of the text file there, equal.
    let usdc = dir.join("frame.usdc");
    let mut binary = vec!["export-frame", usdc.to_str().unwrap(), "--out"];
    let png = dir.join("binary.png");
    binary.push(png.to_str().unwrap());
    binary.extend_from_slice(&size);
    let out = fur(&binary);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let compare = "import sys\nfrom pxr import Usd\n\
        a, b = Usd.Stage.Open(sys.argv[1]), Usd.Stage.Open(sys.argv[2])\n\
        prims = attrs = 0\n\
        for p in a.Traverse():\n\
        \x20   q = b.GetPrimAtPath(p.GetPath())\n\
        \x20   assert q and q.GetTypeName() == p.GetTypeName(), p.GetPath()\n\
        \x20   prims += 1\n\
        \x20   for attr in p.GetAttributes():\n\
        \x20       other = q.GetAttribute(attr.GetName())\n\
        \x20       assert other and bool(other.Get() == attr.Get()), attr.GetPath()\n\
        \x20       attrs += 1\n\
        assert len(list(b.Traverse())) == prims\n\
        print(prims, attrs)\n";
    let read = Command::new(reference.python())
        .args(["-c", compare])
        .arg(&usda)
        .arg(&usdc)
        .output()
        .unwrap();
    assert!(
        read.status.success(),
        "the .usdc frame differs from the .usda one: {}",
        String::from_utf8_lossy(&read.stderr)
    );
    let counts: Vec<u64> = String::from_utf8_lossy(&read.stdout)
        .split_whitespace()
        .map(|n| n.parse().unwrap())
        .collect();
    assert!(counts[0] >= 5 && counts[1] >= 30, "compared {counts:?}");
}

#[test]
fn export_refuses_bad_input_before_writing() {
    // Run in an empty folder, so that anything written shows.
    let dir = scratch("bad");
    for (args, needle) in [
        (vec!["export-frame", "frame.usdz"], "usdzip"),
        (vec!["export-frame", "frame.obj"], "unknown extension"),
        (
            vec!["export-frame", "x.usda", "--frames", "0"],
            "--frames must be at least 1",
        ),
        (
            vec!["export-frame", "x.usda", "--out-dir", "d"],
            "one frame",
        ),
        (vec!["export-frame", "/dev/null/x.usda"], "x.usda"),
        (
            vec!["export-frame", "x.usda", "--show", "density"],
            "--show density is a study view",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_fur"))
            .args(&args)
            .current_dir(&dir)
            .env("RUST_BACKTRACE", "0")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
        assert!(
            stderr.contains(needle),
            "{args:?}: `{needle}` not in {stderr}"
        );
    }
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "refused exports wrote {left:?}");
}

#[test]
fn read_pfm_refuses_malformed_files() {
    let dir = scratch("pfm");
    let cases: [(&str, &[u8]); 4] = [
        ("short.pfm", b"PF\n2 2\n-1\n\0\0\0\0"),
        ("grey.pfm", b"Pf\n1 1\n-1\n\0\0\0\0"),
        ("big-endian.pfm", b"PF\n1 1\n1\n\0\0\0\0\0\0\0\0\0\0\0\0"),
        ("header.pfm", b"PF\n1 1"),
    ];
    for (name, bytes) in cases {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        assert!(read_pfm(&path).is_err(), "{name} was read");
    }
    let good = dir.join("good.pfm");
    let mut bytes = b"PF\n1 2\n-1\n".to_vec();
    for v in [0.25f32, 0.5, 0.75, 1.0, 2.0, 3.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(&good, bytes).unwrap();
    let image = read_pfm(&good).unwrap();
    // Rows bottom to top in the file: the last row read is the top.
    assert_eq!(
        image.pixels,
        vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.25, 0.5, 0.75)]
    );
}
