//! Tiles that list nothing: the fine pass leaves their pixels of the hair layer as they
//! are and the composite takes the target alone there.

use fur_core::render::{FrameSettings, FurStyle, Raster};

use super::{assert_clean, blob_renderer, blob_settings, device, render};

/// A frame drawn after one full of hair (the same renderer, its hair layer still
/// holding that hair) is the same bytes as a fresh renderer's: with the fur's draw left
/// out (every tile empty) and with the blob drawn smaller (its old tiles empty). With no
/// hair listed, the image is the body's as the fixed-function backend draws it, to a
/// step of 8-bit rounding. Seen failing with the composite reading the layer in every
/// tile (the earlier frame's hair showed through where the later one lists nothing),
/// and with the scan listing one tile of each invocation's run (the tiles left out
/// kept the earlier frame's hair).
#[test]
fn a_tile_that_lists_nothing_shows_the_target_alone() {
    let device = device();
    let size = (96, 72);
    let near = blob_settings(Raster::Compute, 4);
    let bare = FrameSettings {
        draw_fur: false,
        ..near.clone()
    };
    let mut far = near.clone();
    far.camera.distance *= 2.5;
    let (mut renderer, textures) = blob_renderer(&device, &near, size);
    let (full, _) = renderer.render(&textures, &near).unwrap();
    for (name, later) in [("bare", &bare), ("far", &far)] {
        let (after, report) = renderer.render(&textures, later).unwrap();
        let (fresh, _) = render(&device, later, size);
        assert_ne!(
            full.data, after.data,
            "{name}: the frame drew the same image"
        );
        let differ = after
            .data
            .chunks(4)
            .zip(fresh.data.chunks(4))
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(differ, 0, "{name}: {differ} pixels show an earlier frame");
        let entries = report.raster.expect("compute counts").entries;
        assert_eq!(entries == 0, name == "bare", "{name}: {entries} entries");
    }
    let body = FrameSettings {
        style: FurStyle {
            raster: Raster::Hardware,
            ..bare.style.clone()
        },
        ..bare.clone()
    };
    let (hardware, _) = render(&device, &body, size);
    let (compute, _) = render(&device, &bare, size);
    let step = hardware
        .data
        .iter()
        .zip(&compute.data)
        .map(|(a, b)| a.abs_diff(*b))
        .max();
    assert!(
        step <= Some(1),
        "the body alone differs by {step:?} between the backends"
    );
    assert!(
        hardware.data.chunks(4).any(|p| p != &hardware.data[..4]),
        "the body was not drawn"
    );
    assert_clean(&device);
}
