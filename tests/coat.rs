//! The Marschner model's light through the coat on curved skin: tips past the skin's
//! horizon catch the light, as far as a shell around a sphere lets them and no further
//! (lavapipe, validation on). `tests/marschner.rs` checks the coat's count on flat skin
//! height by height.

mod common;

use fur::render::marschner::Lobes;
use fur::render::{FrameSettings, FurStyle, Lighting, LightingModel, RgbaImage, Shading, Shadows};
use fur::scene::{Camera, GroomParams, Mesh};
use glam::Vec3;

/// The hairs' length: they stand along the unit sphere's normals (no comb).
const HAIR: f32 = 0.5;
/// Half the view's height and width, world units at the sphere's centre.
const HALF_VIEW: f32 = 1.7;
const DISTANCE: f32 = 40.0;
const PIXELS: u32 = 160;

/// The unit sphere's hairs seen from +z, far away (almost orthographic), lit from +x
/// (the terminator is the image's middle column) by the Marschner model alone: no
/// ambient, no body drawn, one hair layer per unit so that the coat's depth dims the
/// light little and where the skin stops it shows.
fn lit_sphere(device: &std::sync::Arc<fur::gpu::Device>) -> RgbaImage {
    let sphere = Mesh::icosphere(3);
    let groom = GroomParams {
        segments: 5,
        segment_length: HAIR / 5.0,
        comb_strength: 0.0,
        ..Default::default()
    };
    let settings = FrameSettings {
        camera: Camera {
            target: Vec3::ZERO,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            distance: DISTANCE,
            fov_y_deg: 2.0 * (HALF_VIEW / DISTANCE).atan().to_degrees(),
        },
        lighting: Lighting {
            model: LightingModel::Marschner,
            light_direction: Vec3::X,
            intensity: 1.0,
            ambient: 0.0,
            root_occlusion: 0.0,
            root_color: Vec3::splat(0.8),
            tip_color: Vec3::splat(0.8),
            lobes: Lobes::ALL,
            shadows: Shadows {
                spacing: 1.0,
                ..Default::default()
            },
            ..Default::default()
        },
        draw_mesh: false,
        style: FurStyle {
            jitter: 0.0,
            length_jitter: 0.0,
            shading: Shading::Vertex,
            ..FurStyle::default()
        },
        ..Default::default()
    };
    let (image, _, _) = common::render(device, &sphere, &groom, &settings, (PIXELS, PIXELS));
    image
}

/// The world x (at the sphere's centre's depth) of the left edge of the leftmost column
/// holding a pixel brighter than the background.
fn leftmost_lit(image: &RgbaImage) -> f32 {
    let background = image.pixel(0, 0);
    let column = (0..image.width)
        .find(|&x| {
            (0..image.height).any(|y| {
                let p = image.pixel(x, y);
                (0..3).all(|c| p[c] > background[c].saturating_add(6))
            })
        })
        .expect("some hair is lit");
    (column as f32 / PIXELS as f32 * 2.0 - 1.0) * HALF_VIEW
}

/// A point at distance ρ from the centre of a unit sphere, lit from +x, sees the light
/// past the sphere when its distance from the x axis is at least 1; hair tips reach
/// ρ = 1 + HAIR, so light reaches x = −√((1 + HAIR)² − 1) at most past the terminator
/// (−1.118), and on flat skin (no curvature) none passes it. The image is taken from
/// 40 units away: a tip 1.5 nearer the eye looks 4 % further out; and three pixels: the
/// column's own width (its left edge is reported), half a drawn hair's width (at least
/// 0.75 px) and the icosphere's flat faces, on which interpolated roots lie inside the
/// sphere the estimate assumes. Light that the skin did not stop would reach −1.56.
#[test]
fn tips_past_the_skins_horizon_catch_the_light_as_a_shell_lets_them() {
    let device = common::device();
    let pixel = 2.0 * HALF_VIEW / PIXELS as f32;
    let horizon = ((1.0 + HAIR).powi(2) - 1.0).sqrt();
    let furthest = horizon * DISTANCE / (DISTANCE - 1.0 - HAIR) + 3.0 * pixel;
    let image = lit_sphere(&device);
    common::keep(&image, "coat_sphere");
    let left = leftmost_lit(&image);
    println!("lit from x = {left:.3}; the shell allows {:.3}", -furthest);
    assert!(
        left > -furthest,
        "light reaches x = {left}, past the sphere's shadow ({})",
        -furthest
    );
    // Well past the terminator: half way to the shell's horizon.
    assert!(
        left < -0.5 * horizon,
        "the tips past the skin's horizon are dark: light stops at x = {left}"
    );
    // The same coat on flat skin (the curvature estimate taken out) keeps the far side
    // dark: the check above tells the two apart.
    let flat =
        fur::gpu::shader::with_test_defines(&[("FUR_TEST_FLAT_COAT", "1")], || lit_sphere(&device));
    common::keep(&flat, "coat_sphere_flat");
    let flat_left = leftmost_lit(&flat);
    println!("flat skin: lit from x = {flat_left:.3}");
    assert!(
        flat_left > -0.5 * horizon,
        "a coat on flat skin lights the far side too (from x = {flat_left}): the test cannot tell"
    );
    common::assert_clean(&device);
}
