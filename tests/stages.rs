//! The stage views (`--show`): each a view of the running pipeline, checked on
//! lavapipe with validation on against what the stage holds.

mod common;

use ash::vk;
use fur_core::colour::linear_to_srgb8;
use fur_core::render::{FrameSettings, FurStyle, Lighting, Primitive, RgbaImage, Stage};
use fur_core::scene::{Camera, GroomParams, Mesh, Strands};
use fur_gpu::render::{FrameReport, Renderer};
use fur_gpu::strand_textures::StrandTextures;
use glam::{Vec3, Vec4Swizzles};

const SIZE: (u32, u32) = (256, 192);

/// Draws `strands` on `mesh` once, at `SIZE` and one frame in flight.
fn draw(
    device: &std::sync::Arc<fur_gpu::gpu::Device>,
    mesh: &Mesh,
    strands: &Strands,
    settings: &FrameSettings,
) -> (RgbaImage, FrameReport) {
    let textures = StrandTextures::new(device, strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: SIZE.0,
        height: SIZE.1,
    };
    let samples = settings.style.samples;
    let mut renderer = Renderer::new(device, mesh, &textures, extent, 1, samples).unwrap();
    renderer.render(&textures, settings).unwrap()
}

/// The colour `shaders/masters.vert` gives master `index`, as the sRGB target stores it.
fn master_colour(index: usize) -> [u8; 3] {
    let h = (index as f64 * 0.6180339887).fract() as f32;
    let channel = |offset: f32| {
        let x = (h * 6.0 + offset).rem_euclid(6.0);
        ((x - 3.0).abs() - 1.0).clamp(0.0, 1.0)
    };
    [channel(0.0), channel(4.0), channel(2.0)].map(linear_to_srgb8)
}

/// The masters view draws each master hair where the simulation's state has it, in
/// its own colour, and no interpolated hair: a master's tip segment is found at its
/// projected pixel in its colour far more often than in the next master's (a view
/// that indexed the strands wrongly, or drew interpolated hairs over them, would not
/// tell them apart), and the frame runs no tessellation.
#[test]
fn the_masters_view_draws_each_master_hair_where_it_is_and_nothing_else() {
    let device = common::device();
    let mesh = Mesh::blob();
    let groom = GroomParams {
        segments: 8,
        segment_length: 0.03,
        ..Default::default()
    };
    let (centre, radius) = mesh.bounds();
    let settings = FrameSettings {
        camera: Camera {
            target: centre,
            distance: 2.6 * radius,
            ..Default::default()
        },
        show: Stage::Masters,
        count_hairs: true,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let (image, report) = draw(&device, &mesh, &strands, &settings);
    let statistics = common::statistics(report.statistics);
    assert_eq!(
        statistics.tess_eval_invocations, 0,
        "the masters view tessellates nothing"
    );
    assert_eq!(report.counts, None, "and counts no interpolated hair");

    let view_proj = settings
        .camera
        .view_projection(SIZE.0 as f32 / SIZE.1 as f32);
    let eye = settings.camera.eye();
    // `found`: tips showing their own master's colour; `control`: tips showing the
    // colour of the next master, which a correct view shows only by coincidence.
    let (mut facing, mut found, mut control) = (0, 0, 0);
    for s in 0..strands.count() {
        let strand = strands.strand(s);
        let (root, tip) = (strand[0], strand[strand.len() - 1]);
        // Masters on the body's far side are hidden by it.
        if (tip - root).dot(eye - root) <= 0.0 {
            continue;
        }
        facing += 1;
        let mid = 0.5 * (strand[strand.len() - 2] + tip);
        let clip = view_proj * mid.extend(1.0);
        let ndc: Vec3 = clip.xyz() / clip.w;
        let (x, y) = (
            (ndc.x * 0.5 + 0.5) * SIZE.0 as f32,
            (ndc.y * 0.5 + 0.5) * SIZE.1 as f32,
        );
        let shows = |want: [u8; 3]| {
            let near = (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)));
            near.into_iter().any(|(dx, dy)| {
                let (px, py) = (x as i32 + dx, y as i32 + dy);
                if px < 0 || py < 0 || px >= SIZE.0 as i32 || py >= SIZE.1 as i32 {
                    return false;
                }
                let p = image.pixel(px as u32, py as u32);
                (0..3).all(|c| p[c].abs_diff(want[c]) <= 2)
            })
        };
        found += usize::from(shows(master_colour(s)));
        control += usize::from(shows(master_colour(s + 1)));
    }
    assert!(facing > 100, "{facing} masters face the camera");
    // Other masters in front hide some tips; most show.
    let ok = found * 3 >= facing && found >= 5 * control.max(1);
    if !ok {
        common::keep(&image, "masters_view");
    }
    assert!(
        ok,
        "{found} of {facing} facing masters found at their tips in their colour \
         ({control} in the next master's colour)"
    );
    common::assert_clean(&device);
}

/// The GLSL `hash_u32` (`shaders/common.glsl`).
fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The GLSL `hue` (linear RGB).
fn hue(h: f32) -> [f32; 3] {
    let channel = |offset: f32| {
        let x = (h * 6.0 + offset).rem_euclid(6.0);
        ((x - 3.0).abs() - 1.0).clamp(0.0, 1.0)
    };
    [channel(0.0), channel(4.0), channel(2.0)]
}

fn srgb(linear: [f32; 3]) -> [u8; 3] {
    linear.map(linear_to_srgb8)
}

/// Draws the standing hairs (no skin) as opaque ribbons at one sample per pixel, so
/// every fur pixel is exactly one hair's colour, in stage view `show` with `style`.
fn standing_hairs(show: Stage, style: FurStyle, camera: Camera) -> (RgbaImage, Vec<u32>, u64) {
    standing_hairs_lit(show, style, camera, Lighting::default())
}

/// [`standing_hairs`] under `lighting`.
fn standing_hairs_lit(
    show: Stage,
    style: FurStyle,
    camera: Camera,
    lighting: Lighting,
) -> (RgbaImage, Vec<u32>, u64) {
    let device = common::device();
    let (mesh, groom) = common::standing_hairs_scene();
    let settings = FrameSettings {
        camera,
        // Opaque ribbons at one sample through the fixed-function rasteriser: each pixel
        // holds one hair's colour, which the views' tests read back exactly (the compute
        // passes' exact coverage blends the hairs a pixel holds; the tiles view draws in
        // compute whatever this says).
        style: FurStyle {
            primitive: Primitive::Ribbons,
            thin_hair_aa: false,
            samples: 1,
            raster: fur_core::render::Raster::Hardware,
            ..style
        },
        lighting,
        show,
        draw_mesh: false,
        count_hairs: true,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let (image, report) = draw(&device, &mesh, &strands, &settings);
    common::assert_clean(&device);
    let counts = report.counts.expect("lavapipe counts hairs");
    (image, mesh.indices, counts.hairs)
}

fn side_camera(distance: f32) -> Camera {
    Camera {
        target: Vec3::new(0.0, 0.2, 0.0),
        pitch_deg: 20.0,
        distance,
        ..Default::default()
    }
}

/// The colours of the pixels the fur covers.
fn fur_pixels(image: &RgbaImage) -> Vec<[u8; 3]> {
    let covered = common::covered(image);
    (0..image.height)
        .flat_map(|y| (0..image.width).map(move |x| (x, y)))
        .zip(covered)
        .filter(|(_, c)| *c)
        .map(|((x, y), _)| {
            let p = image.pixel(x, y);
            [p[0], p[1], p[2]]
        })
        .collect()
}

fn near(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
    (0..3).all(|c| a[c].abs_diff(b[c]) <= tolerance)
}

/// The interpolated view paints every hair in its source triangle's colour (the GLSL
/// hash of the triangle's three master hairs, worked out here on the CPU): nearly every
/// fur pixel is one of those colours, and many triangles' colours show. The lit image
/// has none of them, and both draw the same hairs.
#[test]
fn the_interpolated_view_paints_each_hair_in_its_triangles_colour() {
    let (image, indices, hairs) =
        standing_hairs(Stage::Interpolated, FurStyle::default(), side_camera(2.0));
    let colours: Vec<[u8; 3]> = indices
        .chunks_exact(3)
        .map(|t| {
            // hash_unit(hash_u32(a ^ hash_u32(b ^ hash_u32(c)))), as fur.geom has it.
            let seed = hash_u32(t[0] ^ hash_u32(t[1] ^ hash_u32(t[2])));
            srgb(hue((hash_u32(seed) >> 8) as f32 / 16_777_216.0))
        })
        .collect();
    let pixels = fur_pixels(&image);
    assert!(pixels.len() > 1000, "{} fur pixels", pixels.len());
    let mut seen = vec![false; colours.len()];
    let mut matched = 0;
    for p in &pixels {
        if let Some(t) = colours.iter().position(|c| near(*p, *c, 2)) {
            seen[t] = true;
            matched += 1;
        }
    }
    let share = matched as f64 / pixels.len() as f64;
    let triangles = seen.iter().filter(|s| **s).count();
    if share < 0.98 {
        common::keep(&image, "interpolated_view");
    }
    assert!(
        share >= 0.98,
        "{matched} of {} fur pixels in a triangle's colour",
        pixels.len()
    );
    assert!(
        triangles * 2 >= colours.len(),
        "{triangles} of {} triangles' colours seen",
        colours.len()
    );
    let (lit, _, lit_hairs) = standing_hairs(Stage::Lit, FurStyle::default(), side_camera(2.0));
    assert_eq!(
        hairs, lit_hairs,
        "the interpolated view draws the lit image's hairs"
    );
    let lit_matched = fur_pixels(&lit)
        .iter()
        .filter(|p| colours.iter().any(|c| near(**p, *c, 2)))
        .count();
    assert!(
        lit_matched * 20 < matched,
        "the lit image matches {lit_matched}"
    );
}

/// The ownership view paints each hair in the colour of the triangle that draws it,
/// dimmed inside the triangle, bright on an edge, white at a corner: nearly every fur
/// pixel is one of those, and all three kinds of point show.
#[test]
fn the_ownership_view_tells_interior_edge_and_corner_points_apart() {
    let (image, indices, _) =
        standing_hairs(Stage::Ownership, FurStyle::default(), side_camera(2.0));
    let bright: Vec<[f32; 3]> = indices
        .chunks_exact(3)
        .map(|t| {
            let seed = hash_u32(t[0] ^ hash_u32(t[1] ^ hash_u32(t[2])));
            hue((hash_u32(seed) >> 8) as f32 / 16_777_216.0)
        })
        .collect();
    let edge: Vec<[u8; 3]> = bright.iter().map(|c| srgb(*c)).collect();
    let inside: Vec<[u8; 3]> = bright.iter().map(|c| srgb(c.map(|v| 0.3 * v))).collect();
    let pixels = fur_pixels(&image);
    let (mut corners, mut edges, mut interiors) = (0, 0, 0);
    for p in &pixels {
        if p.iter().all(|c| *c >= 253) {
            corners += 1;
        } else if edge.iter().any(|c| near(*p, *c, 2)) {
            edges += 1;
        } else if inside.iter().any(|c| near(*p, *c, 2)) {
            interiors += 1;
        }
    }
    let classified = corners + edges + interiors;
    if classified * 100 < pixels.len() * 98 {
        common::keep(&image, "ownership_view");
    }
    assert!(
        classified * 100 >= pixels.len() * 98,
        "{classified} of {} pixels classified ({corners} corner, {edges} edge, {interiors} interior)",
        pixels.len()
    );
    assert!(
        corners > 0 && edges > corners && interiors > edges,
        "{corners} corner, {edges} edge, {interiors} interior pixels"
    );
}

/// The LOD view: with every segment kept and every hair drawn, the fur is pure red;
/// when the vertex LOD leaves the straight hairs one segment each, blue; and where the
/// density LOD draws a quarter of the hairs, red at the brightness
/// `0.25 + 0.75 · lod` the view gives (lod = (D / d)², worked out from the camera).
#[test]
fn the_lod_view_colours_hairs_by_segments_kept_and_density_thinned() {
    let full = FurStyle {
        vertex_lod_px: 0.0,
        lod_distance: 100.0,
        ..Default::default()
    };
    let (image, _, _) = standing_hairs(Stage::Lod, full.clone(), side_camera(2.0));
    let pixels = fur_pixels(&image);
    let red = srgb(hue(0.0));
    let reds = pixels.iter().filter(|p| near(**p, red, 2)).count();
    assert!(
        reds * 100 >= pixels.len() * 98,
        "{reds} of {} pixels red with every segment kept",
        pixels.len()
    );

    let one_segment = FurStyle {
        vertex_lod_px: 2.0,
        ..full.clone()
    };
    let (image, _, _) = standing_hairs(Stage::Lod, one_segment, side_camera(2.0));
    let pixels = fur_pixels(&image);
    let blue = srgb(hue(0.66));
    let blues = pixels.iter().filter(|p| near(**p, blue, 2)).count();
    assert!(
        blues * 100 >= pixels.len() * 95,
        "{blues} of {} pixels blue with straight hairs at one segment",
        pixels.len()
    );

    // A camera 6 units out with the full-density distance at 3: lod ≈ (3 / 6)² = 1/4
    // at the plane (its hairs are within 0.7 of the target).
    let camera = side_camera(6.0);
    let thinned = FurStyle {
        lod_distance: 3.0,
        ..full
    };
    let (image, _, _) = standing_hairs(Stage::Lod, thinned, camera);
    let mut reds: Vec<u8> = fur_pixels(&image)
        .iter()
        .filter(|p| p[1] < 8 && p[2] < 8)
        .map(|p| p[0])
        .collect();
    assert!(reds.len() > 50, "{} thinned red pixels", reds.len());
    reds.sort_unstable();
    let median = reds[reds.len() / 2];
    let d = camera.eye().distance(Vec3::ZERO);
    let lod = (3.0 / d).powi(2);
    let want = linear_to_srgb8(0.25 + 0.75 * lod);
    assert!(
        median.abs_diff(want) <= 12,
        "median red {median}, want {want} (lod {lod:.3})"
    );
}

/// The shadow view shows the self-shadowing term alone, in grey: with the light above
/// standing hairs, the light reaching the hairs falls from their tips (the top of the
/// fur in the image) to their roots; with hair that stops no light, every hair is
/// white. The scene's shadows are off: the view draws them anyway.
#[test]
fn the_shadow_view_shows_the_light_falling_into_the_fur() {
    let lighting = |opacity: f32| {
        // Kajiya–Kay's shadow view is grey (the Marschner model's is in the fibres'
        // colour: tests/looks/shadows.rs).
        let mut l = Lighting {
            light_direction: Vec3::Y,
            model: fur_core::render::LightingModel::KajiyaKay,
            ..Default::default()
        };
        l.shadows.enabled = false;
        l.shadows.opacity = opacity;
        l
    };
    let (image, _, _) = standing_hairs_lit(
        Stage::Shadow,
        FurStyle::default(),
        side_camera(2.0),
        lighting(0.8),
    );
    let covered = common::covered(&image);
    let mut rows: Vec<(u32, f64)> = Vec::new();
    for y in 0..image.height {
        let (mut sum, mut n) = (0.0, 0);
        for x in 0..image.width {
            if !covered[(y * image.width + x) as usize] {
                continue;
            }
            let p = image.pixel(x, y);
            let spread = p[0].max(p[1]).max(p[2]) - p[0].min(p[1]).min(p[2]);
            assert!(spread <= 2, "pixel ({x}, {y}) is {p:?}, not grey");
            sum += f64::from(p[0]);
            n += 1;
        }
        if n > 0 {
            rows.push((y, sum / f64::from(n)));
        }
    }
    assert!(rows.len() > 30, "{} rows of fur", rows.len());
    let third = rows.len() / 3;
    let mean = |r: &[(u32, f64)]| r.iter().map(|(_, v)| v).sum::<f64>() / r.len() as f64;
    let (top, bottom) = (mean(&rows[..third]), mean(&rows[rows.len() - third..]));
    if top < bottom + 40.0 {
        common::keep(&image, "shadow_view");
    }
    assert!(
        top >= bottom + 40.0,
        "the tips' rows average {top:.0}, the roots' {bottom:.0}"
    );
    let (clear, _, _) = standing_hairs_lit(
        Stage::Shadow,
        FurStyle::default(),
        side_camera(2.0),
        lighting(0.0),
    );
    let pixels = fur_pixels(&clear);
    let white = pixels
        .iter()
        .filter(|p| p.iter().all(|c| *c >= 253))
        .count();
    assert!(
        white * 100 >= pixels.len() * 99,
        "{white} of {} pixels white where hair stops no light",
        pixels.len()
    );
}

/// `--show` on the command line: the masters view names what it drew, an unknown
/// stage is refused naming the flag and the choices.
#[test]
fn the_command_line_shows_a_stage_and_refuses_an_unknown_one() {
    let dir = common::scratch("stages", "cli");
    let out = dir.join("masters.png");
    let o = common::fur(&[
        "render",
        "--validate",
        "--show",
        "masters",
        "--width",
        "96",
        "--height",
        "72",
        "--out",
        out.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(text.contains("0 tessellated points"), "{text}");
    assert!(out.exists());
    let o = common::fur(&["render", "--show", "everything"]);
    let error = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        error.contains("--show") && error.contains("masters"),
        "{error}"
    );
}
