//! The lighting pass (`strand_shade.comp`): under the Marschner model the geometry
//! stage leaves each strand vertex with what lights it, and a compute pass lights it.

use super::{assert_clean, blob_settings, device, groom};
use ash::vk;
use fur_core::render::strand_raster::Segment;
use fur_core::render::{LightingModel, Raster};
use fur_core::scene::{Mesh, Strands};
use fur_gpu::render::Renderer;
use fur_gpu::strand_textures::StrandTextures;

/// The segments the geometry stage wrote in a Marschner-lit frame of the blob, lit
/// (with `shadows`).
fn lit_segments(device: &std::sync::Arc<fur_gpu::gpu::Device>, shadows: bool) -> Vec<Segment> {
    let mut settings = blob_settings(Raster::Compute, 1);
    settings.lighting.model = LightingModel::Marschner;
    settings.lighting.shadows.enabled = shadows;
    let mesh = Mesh::blob();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let textures = StrandTextures::new(device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: 96,
        height: 72,
    };
    let mut renderer = Renderer::new(device, &mesh, &textures, extent, 1, 1).unwrap();
    renderer.render(&textures, &settings).unwrap();
    renderer.capture_raster(0).unwrap().segments
}

/// Every vertex the lighting pass lit has the colour the geometry stage gives it when
/// it lights the vertex itself (the test-only `FUR_TEST_LIGHT_IN_GEOMETRY`), to the
/// rounding of what the pass's input packs (half floats: base colour and coat, two
/// 16-bit coordinates: the tangent), without and with the shadow map. With the map, at
/// most one channel in 5,000 may be off, by at most 0.02: the pass finds a vertex's
/// world point from its place on the screen, whose depth (NDC z, a float) holds it to
/// about 10⁻⁵ of the camera's distance (frame_block's
/// `the_inverse_projection_finds_each_strand_vertex_again`), and where the map's hair layers change
/// abruptly between texels that moves the lookup (seen: 52 of 781,440, by up to
/// 0.0085). The frames write the same segments in the same slots (the positions are
/// compared too).
/// Seen failing against a pass that ignored the shadow map (with shadows: 416,180 of
/// the 781,440 channels of the segments' ends off, by up to 0.26), one that read the
/// coat's two counts swapped (465,389 off, by up to 0.29) and one that lit each vertex
/// at the world point of the pixel to its right (without shadows: 62,366 of 781,440
/// off), and one whose every colour was not a number (as a zero inverse projection
/// makes it: every channel off).
#[test]
fn the_lighting_pass_lights_each_vertex_as_the_geometry_stage_would() {
    let device = device();
    for shadows in [false, true] {
        let in_pass = lit_segments(&device, shadows);
        let in_geometry =
            fur_gpu::gpu::shader::with_test_defines(&[("FUR_TEST_LIGHT_IN_GEOMETRY", "1")], || {
                lit_segments(&device, shadows)
            });
        assert_eq!(in_pass.len(), in_geometry.len());
        assert!(in_pass.len() > 1000, "{} segments", in_pass.len());
        let (mut off, mut worst, mut lit) = (0, 0.0f32, 0);
        for (p, g) in in_pass.iter().zip(&in_geometry) {
            for (a, b) in [(&p.a, &g.a), (&p.b, &g.b)] {
                assert_eq!((a.position, a.depth), (b.position, b.depth));
                lit += usize::from(b.color.iter().any(|c| *c > 0.05));
                for (x, y) in a.color.iter().zip(&b.color) {
                    // A colour that is not a number is off by any measure.
                    let err = if x.is_finite() {
                        (x - y).abs()
                    } else {
                        f32::INFINITY
                    };
                    worst = worst.max(err);
                    off += usize::from(err.is_nan() || err > 2e-3 + 2e-3 * y.abs());
                }
            }
        }
        eprintln!(
            "shadows {shadows}: {} segment ends, {lit} brighter than 0.05, {off} channels off, worst {worst}",
            2 * in_pass.len()
        );
        assert!(lit > in_pass.len(), "{lit} lit ends");
        let (most, largest) = if shadows {
            (6 * in_pass.len() / 5_000, 0.02)
        } else {
            (0, f32::INFINITY)
        };
        assert!(
            off <= most && worst <= largest,
            "shadows {shadows}: {off} channels off, worst {worst}"
        );
    }
    assert_clean(&device);
}

/// One renderer switching between the lighting models, as the viewer's panel does,
/// draws each frame as a renderer made for it does: the lighting pass comes and goes
/// with the Marschner model, and the geometry stage leaves what lights a vertex, or
/// its colour, as the frame's model asks. Seen failing with the pipelines kept when
/// the model changes (the Marschner frame after Kajiya–Kay's was not the fresh
/// renderer's), and, when the lighting had a pool of its own, with that pool kept.
#[test]
fn switching_the_lighting_model_draws_each_frame_as_a_new_renderer_does() {
    let device = device();
    let mesh = Mesh::blob();
    let strands = Strands::grow(&mesh, &groom()).unwrap();
    let settings = |model: LightingModel| {
        let mut s = blob_settings(Raster::Compute, 1);
        s.lighting.model = model;
        s
    };
    let textures =
        StrandTextures::new(&device, &strands, settings(LightingModel::Marschner).head).unwrap();
    let extent = vk::Extent2D {
        width: 96,
        height: 72,
    };
    let fresh = |model: LightingModel| {
        let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
        renderer.render(&textures, &settings(model)).unwrap().0
    };
    let (kajiya_kay, marschner) = (
        fresh(LightingModel::KajiyaKay),
        fresh(LightingModel::Marschner),
    );
    assert_ne!(kajiya_kay.data, marschner.data);
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    for model in [
        LightingModel::KajiyaKay,
        LightingModel::Marschner,
        LightingModel::KajiyaKay,
        LightingModel::Marschner,
    ] {
        let (image, _) = renderer.render(&textures, &settings(model)).unwrap();
        let expected = match model {
            LightingModel::KajiyaKay => &kajiya_kay,
            LightingModel::Marschner => &marschner,
        };
        assert!(image.data == expected.data, "{model:?} after a switch");
    }
    assert_clean(&device);
}
