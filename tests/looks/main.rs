//! Looks on lavapipe with validation: the secondary highlight against the CPU model,
//! thin-hair anti-aliasing (coverage by true width, steady under sub-pixel motion) and
//! self-shadowing (depth into the fur darkens, off costs nothing), and the colour
//! texture: each in a file of its own.

#[path = "../common/mod.rs"]
mod common;

mod coverage;
mod highlight;
mod shadows;
mod texture;

use glam::Vec3;

use fur_core::render::{
    kajiya_kay, FrameSettings, FurStyle, Highlights, Lighting, RgbaImage, Shadows,
};
use fur_core::scene::{Camera, GroomParams, Mesh};

/// The linear value of an sRGB-encoded channel.
fn linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Mean linear colour the fur adds over the background in the pixels that differ
/// from it.
fn mean_covered(image: &RgbaImage) -> (Vec3, usize) {
    let covered = common::covered(image);
    let rgb = |p: [u8; 4]| Vec3::new(linear(p[0]), linear(p[1]), linear(p[2]));
    let background = rgb(image.pixel(0, 0));
    let mut sum = Vec3::ZERO;
    let mut n = 0;
    for y in 0..image.height {
        for x in 0..image.width {
            if covered[(y * image.width + x) as usize] {
                sum += rgb(image.pixel(x, y)) - background;
                n += 1;
            }
        }
    }
    (sum / n.max(1) as f32, n)
}

/// White hair and skin at ambient 1 and nothing else: the image shows coverage and
/// colour only.
fn unlit_white() -> Lighting {
    Lighting {
        kd: 0.0,
        ks: 0.0,
        ambient: 1.0,
        root_occlusion: 0.0,
        root_color: Vec3::ONE,
        tip_color: Vec3::ONE,
        skin_color: Vec3::ONE,
        highlights: Highlights {
            secondary: false,
            ..Default::default()
        },
        // Kajiya–Kay's ambient term: the colour itself (the Marschner model has none).
        model: fur_core::render::LightingModel::KajiyaKay,
        ..Default::default()
    }
}
