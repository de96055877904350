//! Thin-hair anti-aliasing: coverage by true width, steady under sub-pixel motion.

use super::*;

/// Sparse hairs combed flat on a plane, seen from above, white on the dark background.
fn flat_hairs(hair_px: f32, style: FurStyle, yaw_deg: f32) -> (Mesh, GroomParams, FrameSettings) {
    let groom = GroomParams {
        segments: 4,
        segment_length: 0.03,
        comb_direction: Vec3::X,
        comb_strength: 20.0,
        ..Default::default()
    };
    let camera = Camera {
        target: Vec3::ZERO,
        yaw_deg,
        pitch_deg: 75.0,
        distance: 2.0,
        fov_y_deg: 40.0,
    };
    let mut settings = FrameSettings {
        camera,
        lighting: unlit_white(),
        draw_mesh: false,
        style: FurStyle {
            density: 400.0,
            jitter: 0.0,
            length_jitter: 0.0,
            vertex_lod_px: 0.0,
            ..style
        },
        ..Default::default()
    };
    let pixel = settings.pixel_at_unit_distance(TARGET) * camera.distance;
    settings.style.hair_width = hair_px * pixel;
    (Mesh::grid(4, 4, 1.2), groom, settings)
}

const TARGET: u32 = 128;

/// Linear light the fur adds over the background, summed over the image (pixels).
fn ink(image: &RgbaImage) -> f32 {
    let luma = |p: [u8; 4]| 0.2126 * linear(p[0]) + 0.7152 * linear(p[1]) + 0.0722 * linear(p[2]);
    let background = luma(image.pixel(0, 0));
    (0..image.height)
        .flat_map(|y| (0..image.width).map(move |x| (x, y)))
        .map(|(x, y)| (luma(image.pixel(x, y)) - background).max(0.0))
        .sum()
}

#[test]
fn thin_hairs_cover_their_pixels_by_their_width_and_hold_still() {
    let device = common::device();
    let draw = |hair_px: f32, style: FurStyle, yaw: f32| {
        let (mesh, groom, settings) = flat_hairs(hair_px, style, yaw);
        common::render(&device, &mesh, &groom, &settings, (TARGET, TARGET)).0
    };
    // Thin-hair AA is the fixed-function rasteriser's (the compute passes' coverage is
    // exact whatever the width: held to the same steadiness below).
    let fixed = FurStyle {
        raster: fur_core::render::Raster::Hardware,
        ..FurStyle::default()
    };
    let aa = FurStyle {
        thin_hair_aa: true,
        min_pixel_width: 1.0,
        ..fixed.clone()
    };
    let off = FurStyle {
        thin_hair_aa: false,
        min_pixel_width: 1.0,
        ..fixed.clone()
    };
    // Coverage follows the true width, whatever width the hair is drawn at.
    let (thin, thick) = (draw(0.2, aa.clone(), 0.0), draw(0.4, aa.clone(), 0.0));
    common::keep(&thin, "thin_hair_aa_0.2px");
    let ratio = ink(&thick) / ink(&thin);
    assert!(
        (1.6..2.4).contains(&ratio),
        "twice the width gives {ratio}× the ink with thin-hair AA"
    );
    let wide_footprint = draw(
        0.2,
        FurStyle {
            min_pixel_width: 2.0,
            ..aa.clone()
        },
        0.0,
    );
    let footprint = ink(&wide_footprint) / ink(&thin);
    assert!(
        (0.85..1.18).contains(&footprint),
        "the ink of 0.2-px hairs changes {footprint}× when drawn 2 px instead of 1 px wide"
    );
    // Without it both are drawn a whole pixel wide (the property above fails).
    let ratio_off = ink(&draw(0.4, off.clone(), 0.0)) / ink(&draw(0.2, off, 0.0));
    assert!(ratio_off < 1.2, "without AA: {ratio_off}");

    // Sub-pixel camera motion: frame-to-frame change of every pixel, relative to the
    // ink, against hairs drawn at their true width with nothing to hold them.
    let naive = FurStyle {
        thin_hair_aa: false,
        min_pixel_width: 0.0,
        ..fixed
    };
    let flicker = |style: &FurStyle| {
        let frames: Vec<RgbaImage> = (0..6)
            .map(|i| draw(0.2, style.clone(), 0.02 * i as f32))
            .collect();
        let mut change = 0.0;
        for pair in frames.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            for y in 0..a.height {
                for x in 0..a.width {
                    let (p, q) = (a.pixel(x, y), b.pixel(x, y));
                    change += (linear(p[1]) - linear(q[1])).abs();
                }
            }
        }
        let inks: Vec<f32> = frames.iter().map(ink).collect();
        let mean = inks.iter().sum::<f32>() / inks.len() as f32;
        let spread = inks.iter().fold(0.0f32, |m, i| m.max((i - mean).abs())) / mean;
        (change / (frames.len() - 1) as f32 / mean, spread, mean)
    };
    let (aa_change, aa_spread, aa_ink) = flicker(&aa);
    let (naive_change, naive_spread, naive_ink) = flicker(&naive);
    eprintln!(
        "flicker: AA {aa_change:.3} (ink {aa_ink:.0} ± {aa_spread:.3}), \
         true width {naive_change:.3} (ink {naive_ink:.0} ± {naive_spread:.3})"
    );
    assert!(
        aa_spread < 0.03,
        "the ink of AA hairs varies by {aa_spread} as the camera moves"
    );
    assert!(
        aa_change < 0.6 * naive_change,
        "AA hairs flicker {aa_change}, true-width hairs {naive_change}"
    );
    // The strands drawn in compute (the default) hold as still as the AA hairs.
    let (compute_change, compute_spread, _) = flicker(&FurStyle {
        raster: fur_core::render::Raster::Compute,
        ..FurStyle::default()
    });
    eprintln!("compute: {compute_change:.3} (± {compute_spread:.3})");
    assert!(
        compute_spread < 0.03 && compute_change < 0.6 * naive_change,
        "compute strands flicker {compute_change} (ink ± {compute_spread}), true-width \
         hairs {naive_change}"
    );
    common::assert_clean(&device);
}
