//! The strand textures hold any number of master hairs: fifty thousand, more than the
//! widest image holds in a row, tile into rows exactly as laid out, and are drawn
//! (lavapipe, validation on).

mod common;

use fur_core::render::{FrameSettings, FurStyle};
use fur_core::scene::{Camera, GroomParams, Mesh};

#[test]
fn fifty_thousand_master_hairs_tile_the_strand_textures() {
    let device = common::device();
    let mesh = Mesh::grid(250, 200, 4.0); // 50,451 vertices
    assert!(mesh.vertex_count() >= 50_000);
    let groom = GroomParams {
        segments: 4,
        segment_length: 0.02,
        ..Default::default()
    };
    let strands = fur_core::scene::Strands::grow(&mesh, &groom).unwrap();
    let textures =
        fur_gpu::strand_textures::StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY)
            .unwrap();
    // 50,451 strands of 5 vertices in one row would need 252,255 texels: more than any
    // device's widest image, so they must tile into rows. The layout, worked out by
    // hand: ⌊max / 5⌋ strands a row, rows stacked downwards.
    let max = device.info().limits.max_image_dimension2_d;
    assert!(strands.count() * 5 > max as usize);
    let per_row = (max / 5) as usize;
    let rows = strands.count().div_ceil(per_row);
    assert!(rows > 1);
    assert_eq!(
        (textures.layout.width, textures.layout.height),
        (per_row as u32 * 5, rows as u32)
    );
    // Every strand vertex is at that texel of the image as stored (read back raw, not
    // through the layout's own mapping).
    let texels = textures.read_texels(textures.current).unwrap();
    let width = per_row * 5;
    assert_eq!(texels.len(), width * rows);
    for (i, p) in strands.positions.iter().enumerate() {
        let (strand, vertex) = (i / 5, i % 5);
        let (x, y) = ((strand % per_row) * 5 + vertex, strand / per_row);
        assert_eq!(
            texels[y * width + x].truncate(),
            *p,
            "strand {strand} vertex {vertex} is not at texel ({x}, {y})"
        );
    }
    // And the layout's own round trip agrees.
    let back = textures.read_positions(textures.current).unwrap();
    assert_eq!(back, strands.positions);
    drop(textures);
    let settings = FrameSettings {
        camera: Camera {
            pitch_deg: 50.0,
            distance: 4.0,
            ..Default::default()
        },
        style: FurStyle {
            density: 50.0,
            ..FurStyle::default()
        },
        ..Default::default()
    };
    let (image, stats, _) = common::render(&device, &mesh, &groom, &settings, (96, 72));
    let stats = common::statistics(stats);
    common::keep(&image, "fifty_thousand");
    assert!(stats.geometry_invocations > 10_000, "{stats:?}");
    assert!(common::covered(&image).iter().filter(|c| **c).count() > 1000);
    common::assert_clean(&device);
}
