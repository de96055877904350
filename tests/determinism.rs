//! The same frame drawn twice is the same image: in one renderer frame after frame, and
//! in a new renderer after others were made and dropped (the driver then hands out
//! memory that held other frames). A frame that reads anything before writing it (an
//! output a shader stage leaves undefined, an attachment not cleared, a buffer not filled)
//! draws from whatever that memory held, and fails here on a driver that recycles it
//! (Mesa 25's lavapipe did, for the ribbons' second side before the geometry stage wrote
//! every output before each vertex it emits). On lavapipe with validation on.

mod common;

use ash::vk;
use fur_core::render::{FrameSettings, FurStyle, Lighting, Primitive, Raster, Shading, Shadows};
use fur_core::scene::{Camera, GroomParams, Mesh, Strands};
use fur_gpu::render::Renderer;
use fur_gpu::strand_textures::StrandTextures;

/// The drawings whose frames are compared: the default (strands drawn in compute), and
/// through the fixed-function rasteriser each primitive, shading and sample count, the
/// vertex LOD, thin-hair AA, shadows and the supersampled reference's settings.
fn drawings() -> Vec<(&'static str, FrameSettings)> {
    let base = FrameSettings {
        camera: Camera {
            distance: 4.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let with = |style: FurStyle| FrameSettings {
        style,
        ..base.clone()
    };
    let style = FurStyle {
        raster: Raster::Hardware,
        ..base.style.clone()
    };
    let shadowed = |style: FurStyle| FrameSettings {
        lighting: Lighting {
            shadows: Shadows {
                enabled: true,
                ..Shadows::default()
            },
            ..Lighting::default()
        },
        style,
        ..base.clone()
    };
    vec![
        ("default, in compute", base.clone()),
        ("4x ribbons", with(style.clone())),
        (
            "1x lines",
            with(FurStyle {
                samples: 1,
                primitive: Primitive::Lines,
                ..style.clone()
            }),
        ),
        (
            "4x ribbons per fragment, thin-hair AA",
            with(FurStyle {
                samples: 4,
                primitive: Primitive::Ribbons,
                shading: Shading::Fragment,
                thin_hair_aa: true,
                ..style.clone()
            }),
        ),
        (
            "1x ribbons, vertex LOD",
            with(FurStyle {
                samples: 1,
                primitive: Primitive::Ribbons,
                vertex_lod_px: 0.5,
                ..style.clone()
            }),
        ),
        (
            "Marschner, in compute (per vertex)",
            FrameSettings {
                lighting: Lighting {
                    model: fur_core::render::LightingModel::Marschner,
                    ..Lighting::default()
                },
                ..base.clone()
            },
        ),
        (
            "Marschner, per fragment",
            FrameSettings {
                lighting: Lighting {
                    model: fur_core::render::LightingModel::Marschner,
                    ..Lighting::default()
                },
                style: FurStyle {
                    shading: Shading::Fragment,
                    ..style.clone()
                },
                ..base.clone()
            },
        ),
        ("shadows, in compute", shadowed(base.style.clone())),
        ("shadows", shadowed(style.clone())),
    ]
}

#[test]
fn the_same_frame_drawn_twice_is_the_same_image() {
    let device = common::device();
    let mesh = Mesh::icosphere(2);
    let groom = GroomParams {
        segments: 4,
        segment_length: 0.05,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let extent = vk::Extent2D {
        width: 64,
        height: 48,
    };
    let draw = |settings: &FrameSettings, frames: usize| {
        let mut renderer =
            Renderer::new(&device, &mesh, &textures, extent, 1, settings.style.samples).unwrap();
        (0..frames)
            .map(|_| renderer.render(&textures, settings).unwrap().0)
            .collect::<Vec<_>>()
    };
    let drawings = drawings();
    let first: Vec<_> = drawings.iter().map(|(_, s)| draw(s, 3)).collect();
    // Every drawing again, in reverse order, each in a new renderer after the others.
    for ((name, settings), images) in drawings.iter().zip(&first).rev() {
        let covered = common::covered(&images[0]).iter().filter(|&&c| c).count();
        assert!(covered > 100, "{name}: only {covered} pixels drawn");
        for (frame, image) in images.iter().enumerate().skip(1) {
            if *image != images[0] {
                common::keep(&images[0], &format!("determinism-{name}-0"));
                common::keep(image, &format!("determinism-{name}-{frame}"));
            }
            assert!(
                *image == images[0],
                "{name}: frame {frame} differs from frame 0"
            );
        }
        let again = draw(settings, 1).remove(0);
        if again != images[0] {
            common::keep(&images[0], &format!("determinism-{name}-first"));
            common::keep(&again, &format!("determinism-{name}-again"));
        }
        assert!(
            again == images[0],
            "{name}: drawn again in a new renderer, the frame differs"
        );
    }
    drop(textures);
    common::assert_clean(&device);
}

#[test]
fn the_same_mesh_gives_the_same_distance_field_every_time() {
    // The field decides hair lengths under the thickness limit and every collision;
    // built across threads, it once differed from run to run in the last digits, and
    // so did every image.
    let mesh = Mesh::blob();
    let first = mesh.half_thickness().unwrap();
    for _ in 0..4 {
        let again = mesh.half_thickness().unwrap();
        assert!(
            first
                .iter()
                .zip(&again)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "the blob's half-thickness differs between two builds of its distance field"
        );
    }
}
