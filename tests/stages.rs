//! The stage views (`--show`): each a view of the running pipeline, checked on
//! lavapipe with validation on against what the stage holds.

mod common;

use ash::vk;
use fur::colour::linear_to_srgb8;
use fur::render::{FrameSettings, Renderer, Stage};
use fur::scene::{Camera, GroomParams, Mesh, Strands};
use fur::strand_textures::StrandTextures;
use glam::{Vec3, Vec4Swizzles};

const SIZE: (u32, u32) = (256, 192);

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
    let textures = StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: SIZE.0,
        height: SIZE.1,
    };
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    let (image, report) = renderer.render(&textures, &settings).unwrap();
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
