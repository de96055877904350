//! Straight hairs standing on a plane under the Marschner model, drawn on the device:
//! the scene, camera and measures that `tests/marschner.rs` and `tests/coat.rs` share.
#![allow(dead_code)]

use fur_core::colour::srgb8_to_linear as linear;
use fur_core::render::marschner::Lobes;
use fur_core::render::{Fibre, FrameSettings, FurStyle, Lighting, LightingModel, Raster, Shading};
use fur_core::scene::Camera;
use glam::Vec3;

pub const COLOR: Vec3 = Vec3::new(0.8, 0.45, 0.2);
pub const INTENSITY: f32 = 0.6;
pub const FIBRE: Fibre = Fibre {
    longitudinal_roughness: 0.2,
    azimuthal_roughness: 0.3,
    cuticle_tilt_deg: 6.0,
    ior: 1.55,
    direction_spread: fur_core::render::DIRECTION_SPREAD,
};

/// Every term but the coat's light: the tests of the lobes light the hairs from below
/// their plane too, which the coat (the skin) would stop.
pub const NO_COAT: Lobes = Lobes {
    coat: false,
    ..Lobes::ALL
};

/// The standing hairs' length (6 segments of 0.06: `crate::common::standing_hairs_scene`).
pub const HAIR_LENGTH: f32 = 0.36;

/// Far away with a narrow field of view: every hair is seen from almost the same
/// direction, so the image's light is the model's at that direction.
pub fn camera() -> Camera {
    Camera {
        target: Vec3::new(0.0, 0.2, 0.0),
        yaw_deg: 0.0,
        pitch_deg: 20.0,
        distance: 20.0,
        fov_y_deg: 4.0,
    }
}

pub const WIDTH: u32 = 128;
pub const HEIGHT: u32 = 96;

/// [`camera`] level with the hairs' mid-height, for the coat's test: each row of the
/// image sees the hairs at one height, all lit alike, so the row's light over its
/// coverage (the unlit image's) is their radiance however they hide one another.
pub fn side_on() -> Camera {
    Camera {
        pitch_deg: 0.0,
        target: Vec3::new(0.0, 0.5 * HAIR_LENGTH, 0.0),
        ..camera()
    }
}

/// The height on the hairs that row `row` of a [`side_on`] image sees (at the plane's
/// centre; ±0.5 off it the perspective moves it by 2.5 % of its distance from the
/// middle row, under a third of a row).
pub fn height_of_row(row: u32) -> f32 {
    let c = side_on();
    let half = c.distance * (0.5 * c.fov_y_deg).to_radians().tan();
    c.target.y + half * (1.0 - 2.0 * (row as f32 + 0.5) / HEIGHT as f32)
}

/// Each row's linear light over the background, summed.
pub fn row_sums(image: &fur_core::render::RgbaImage) -> Vec<Vec3> {
    let background = linear_at(image, 0, 0);
    (0..image.height)
        .map(|y| {
            (0..image.width)
                .map(|x| linear_at(image, x, y) - background)
                .sum()
        })
        .collect()
}

/// The light `angle` degrees off the hair (+Y), in the x–y plane.
pub fn light_at(angle: f32) -> Vec3 {
    let a = angle.to_radians();
    Vec3::new(a.sin(), a.cos(), 0.0)
}

/// Straight hairs standing up (+Y) on a plane seen from the side, lit by the fibre
/// model's terms `lobes` from `light` (None: unlit, each hair its colour: drawn by
/// Kajiya–Kay with ambient 1 and no light, whose hairs are then exactly their colour, so
/// the image measures their coverage). Returns the linear
/// light over the background per channel summed over `mask`, the covered pixels and
/// the background.
pub fn standing_hairs(
    device: &std::sync::Arc<fur_gpu::gpu::Device>,
    light: Option<Vec3>,
    lobes: Lobes,
    mask: Option<&[bool]>,
) -> (Vec3, Vec<bool>, Vec3) {
    let image = render_standing(device, light, lobes, None);
    let covered = crate::common::covered(&image);
    let mask = mask.unwrap_or(&covered);
    let background = linear_at(&image, 0, 0);
    let mut sum = Vec3::ZERO;
    for (i, _) in mask.iter().enumerate().filter(|(_, c)| **c) {
        sum += linear_at(&image, i as u32 % image.width, i as u32 / image.width) - background;
    }
    (sum, covered, background)
}

pub fn linear_at(image: &fur_core::render::RgbaImage, x: u32, y: u32) -> Vec3 {
    let p = image.pixel(x, y);
    Vec3::new(linear(p[0]), linear(p[1]), linear(p[2]))
}

/// The hair layers' opacity the standing hairs are drawn with (the shadow map's, which
/// the coat's count takes).
pub fn opacity() -> f32 {
    fur_core::render::Shadows::default().opacity
}

/// The image of [`standing_hairs`] or, given the shadow map's layer spacing (which the
/// coat's count takes; shadows stay off), of the hairs seen [`side_on`], every hair as
/// long (no length jitter).
pub fn render_standing(
    device: &std::sync::Arc<fur_gpu::gpu::Device>,
    light: Option<Vec3>,
    lobes: Lobes,
    spacing: Option<f32>,
) -> fur_core::render::RgbaImage {
    let (plane, groom) = crate::common::standing_hairs_scene();
    let (light, intensity, ambient, model) = match light {
        Some(l) => (l.normalize(), INTENSITY, 0.0, LightingModel::Marschner),
        None => (Vec3::Y, 0.0, 1.0, LightingModel::KajiyaKay),
    };
    let default = FurStyle::default();
    let settings = FrameSettings {
        camera: if spacing.is_some() {
            side_on()
        } else {
            camera()
        },
        lighting: Lighting {
            model,
            fibre: FIBRE,
            light_direction: light,
            intensity,
            ambient,
            root_occlusion: 0.0,
            root_color: COLOR,
            tip_color: COLOR,
            lobes,
            shadows: fur_core::render::Shadows {
                spacing: spacing.unwrap_or(0.0),
                ..Default::default()
            },
            ..Default::default()
        },
        draw_mesh: false,
        // Lit per fragment through the fixed-function rasteriser: the model's terms are
        // measured along the hair, finer than its vertices (the compute strands are lit
        // per vertex).
        style: FurStyle {
            jitter: 0.0,
            shading: Shading::Fragment,
            raster: Raster::Hardware,
            length_jitter: if spacing.is_some() {
                0.0
            } else {
                default.length_jitter
            },
            ..default
        },
        ..Default::default()
    };
    let (image, _, _) = crate::common::render(device, &plane, &groom, &settings, (WIDTH, HEIGHT));
    crate::common::keep(
        &image,
        &format!("marschner_{light:?}_{lobes:?}_{spacing:?}"),
    );
    image
}
