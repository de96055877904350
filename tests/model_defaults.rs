//! The defaults fit any model (lavapipe, validation on): generated models nobody tuned
//! for, drawn with no options, are centred and whole in the frame, and thin parts keep
//! their shape under the fur.

mod common;

use fur_core::render::RgbaImage;
use fur_core::scene::{Mesh, Strands};
use fur_core::scene_file::SceneOptions;
use glam::Vec3;

const SIZE: (u32, u32) = (192, 108);

/// A capsule `length` long and `2 × radius` thick along x.
fn capsule(length: f32, radius: f32) -> Mesh {
    let mut mesh = Mesh::uv_sphere(1.0, 24, 48);
    for p in &mut mesh.positions {
        let shift = (0.5 * length - radius) * p.x.signum();
        *p = *p * radius + Vec3::X * shift;
    }
    mesh.normals = mesh.face_weighted_normals();
    mesh
}

/// A round body with two thin spikes (legs, ears, a tail) along ±x, each
/// `reach` beyond the body and about `thin` across.
fn spiky(reach: f32, thin: f32) -> Mesh {
    let mut mesh = Mesh::icosphere(5);
    let sharpness = (2.0 / (thin * thin)).max(8.0);
    for p in &mut mesh.positions {
        let d = p.normalize();
        let spike = d.x.abs().powf(sharpness) * reach;
        *p = d * (1.0 + spike);
    }
    mesh.normals = mesh.face_weighted_normals();
    mesh
}

/// The bounding box of the pixels that are not background, as (x0, y0, x1, y1).
fn covered_box(image: &RgbaImage) -> (u32, u32, u32, u32) {
    let covered = common::covered(image);
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for y in 0..image.height {
        for x in 0..image.width {
            if covered[(y * image.width + x) as usize] {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
        }
    }
    (x0, y0, x1, y1)
}

/// Renders `mesh` with the default scene (no options), seen from `yaw`, `pitch`.
fn render_default(mesh: &Mesh, yaw: f32, pitch: f32, options: SceneOptions) -> RgbaImage {
    let device = common::device();
    let options = SceneOptions {
        yaw_deg: yaw,
        pitch_deg: pitch,
        ..options
    };
    let (groom, settings) = options.resolve(mesh).unwrap();
    let (image, _, counts) = common::render(&device, mesh, &groom, &settings, SIZE);
    assert!(counts.hairs > 1000, "{} hairs", counts.hairs);
    common::assert_clean(&device);
    image
}

fn assert_centred_and_whole(image: &RgbaImage, name: &str) {
    let (x0, y0, x1, y1) = covered_box(image);
    let (w, h) = (image.width, image.height);
    assert!(
        x0 >= 2 && y0 >= 2 && x1 + 3 <= w && y1 + 3 <= h,
        "{name} is cut by the frame: covers {x0}..{x1} × {y0}..{y1} of {w}×{h}"
    );
    let (cx, cy) = ((x0 + x1) as f32 / 2.0, (y0 + y1) as f32 / 2.0);
    assert!(
        (cx - w as f32 / 2.0).abs() < 0.08 * w as f32
            && (cy - h as f32 / 2.0).abs() < 0.08 * h as f32,
        "{name} is off centre: its middle is at ({cx}, {cy}) of {w}×{h}"
    );
}

#[test]
fn an_elongated_capsule_is_centred_whole_and_thinly_furred() {
    let mesh = capsule(10.0, 0.5);
    let options = SceneOptions::default();
    for (yaw, pitch) in [(25.0, 15.0), (90.0, 0.0), (0.0, 60.0)] {
        let image = render_default(&mesh, yaw, pitch, options.clone());
        common::keep(&image, &format!("capsule_{yaw}_{pitch}"));
        assert_centred_and_whole(&image, "the capsule");
    }
    // Its hair follows its thickness (a radius of 0.5), not its length.
    let (groom, _) = options.resolve(&mesh).unwrap();
    let strands = Strands::grow(&mesh, &groom).unwrap();
    assert!(
        strands.hair_length() <= 0.6 * 0.5 * 1.05,
        "{}",
        strands.hair_length()
    );
}

#[test]
fn thin_protrusions_keep_their_shape_under_the_fur() {
    let mesh = spiky(1.2, 0.12);
    // Seen from the front, the spikes run left and right through the image's middle.
    let furred = render_default(&mesh, 0.0, 0.0, SceneOptions::default());
    let buried = render_default(
        &mesh,
        0.0,
        0.0,
        // Hair as long as asked everywhere, standing as the constant comb leaves it (the
        // body's flow lays thin parts flat, which hides the spikes' burial).
        SceneOptions {
            thickness_limit: 0.0,
            flow: fur_core::scene::Flow::Direction,
            ..SceneOptions::default()
        },
    );
    common::keep(&furred, "spiky_default");
    common::keep(&buried, "spiky_without_thickness_limit");
    assert_centred_and_whole(&furred, "the spiky body");
    // Halfway along each spike, a little above and below it: background with the
    // defaults (the spike stands out of its fur), fur without the thickness limit.
    let (x0, _, x1, _) = covered_box(&furred);
    let (w, h) = (furred.width as f32, furred.height as f32);
    let body_half = 0.25 * (x1 - x0) as f32; // the body is about half the width
    let mid = h / 2.0;
    let covered_at = |image: &RgbaImage, x: f32, y: f32| {
        common::covered(image)[(y as u32 * image.width + x as u32) as usize]
    };
    let mut clear = 0;
    let mut filled_without = 0;
    for side in [-1.0f32, 1.0] {
        let x = w / 2.0 + side * (body_half + 0.5 * (0.5 * (x1 - x0) as f32 - body_half));
        for dy in [-6.0f32, 6.0] {
            clear += usize::from(!covered_at(&furred, x, mid + dy));
            filled_without += usize::from(covered_at(&buried, x, mid + dy));
        }
        // The spike itself is drawn (its fur covers its axis).
        assert!(covered_at(&furred, x, mid), "no spike at x = {x}");
    }
    assert_eq!(clear, 4, "the spikes are buried in fur with the defaults");
    assert!(
        filled_without >= 2,
        "the test does not see buried spikes ({filled_without})"
    );
}

#[test]
fn a_detailed_mesh_of_over_100k_vertices_renders_centred_and_whole() {
    let mut mesh = Mesh::icosphere(7);
    for p in &mut mesh.positions {
        let d = p.normalize();
        *p = d * (1.0 + 0.1 * (9.0 * d.x).sin() * (7.0 * d.y).cos());
    }
    mesh.normals = mesh.face_weighted_normals();
    assert!(mesh.vertex_count() > 100_000);
    let image = render_default(&mesh, 25.0, 15.0, SceneOptions::default());
    common::keep(&image, "detailed");
    assert_centred_and_whole(&image, "the detailed mesh");
}
