//! The secondary highlight against the CPU model.

use super::*;

/// Straight hairs standing up (+Y) on a plane, seen from the side, far away so the
/// view direction barely changes across the image.
fn standing_hairs() -> (Mesh, GroomParams, Camera) {
    let groom = GroomParams {
        segments: 6,
        segment_length: 0.06,
        comb_strength: 0.0,
        ..Default::default()
    };
    let camera = Camera {
        target: Vec3::new(0.0, 0.2, 0.0),
        yaw_deg: 0.0,
        pitch_deg: 0.0,
        distance: 6.0,
        fov_y_deg: 12.0,
    };
    (Mesh::grid(6, 6, 1.0), groom, camera)
}

#[test]
fn the_secondary_highlight_follows_the_cpu_model_and_takes_the_hair_colour() {
    let device = common::device();
    let (plane, groom, camera) = standing_hairs();
    let red = Vec3::new(0.9, 0.0, 0.0);
    let base = Lighting {
        kd: 0.0,
        ambient: 0.0,
        root_occlusion: 0.0,
        root_color: red,
        tip_color: red,
        // The highlights are Kajiya–Kay's (Scheuermann's shifted lobes).
        model: fur_core::render::LightingModel::KajiyaKay,
        ..Default::default()
    };
    let render = |lighting: &Lighting| {
        let settings = FrameSettings {
            camera,
            lighting: lighting.clone(),
            draw_mesh: false,
            style: FurStyle {
                jitter: 0.0,
                ..FurStyle::default()
            },
            ..Default::default()
        };
        common::render(&device, &plane, &groom, &settings, (96, 96)).0
    };
    let eye_to_hair = (camera.target - camera.eye()).normalize();
    // The eye looks across the hair (θe = 90°); the light comes from behind, `angle`
    // above the horizontal (θl = 90° − angle): a lobe shifted by β peaks at angle = β.
    let mut shift_effects = Vec::new();
    for angle in [10.0f32, 20.0, 30.0] {
        let a = angle.to_radians();
        let light = Vec3::new(0.0, a.sin(), -a.cos());
        let mut row = Vec::new();
        for shift in [-8.0f32, 8.0] {
            let lighting = Lighting {
                light_direction: light,
                ks: 0.0,
                highlights: Highlights {
                    secondary: true,
                    secondary_shift_deg: shift,
                    secondary_shininess: 10.0,
                    secondary_strength: 1.0,
                    ..Default::default()
                },
                ..base.clone()
            };
            let image = render(&lighting);
            common::keep(&image, &format!("secondary_{angle}_{shift}"));
            let (colour, n) = mean_covered(&image);
            assert!(n > 100, "too little fur visible");
            // Tinted: only the hair colour's channel lights up.
            assert!(
                colour.y < 0.02 * colour.x.max(1e-3) + 0.002,
                "the secondary highlight is not tinted by the red hair: {colour}"
            );
            let shade = kajiya_kay(Vec3::Y, light.normalize(), eye_to_hair, &lighting);
            row.push((colour.x, shade.tinted * red.x));
        }
        shift_effects.push(row);
    }
    // Against the CPU model: brightness proportional to the predicted tinted term, and
    // the shift's sign moves it the same way on both.
    let ratios: Vec<f32> = shift_effects
        .iter()
        .flatten()
        .filter(|(_, predicted)| *predicted > 0.02)
        .map(|(measured, predicted)| measured / predicted)
        .collect();
    assert!(ratios.len() >= 5, "too few lit cases: {shift_effects:?}");
    let (lo, hi) = ratios
        .iter()
        .fold((f32::MAX, 0.0f32), |(lo, hi), r| (lo.min(*r), hi.max(*r)));
    assert!(
        hi < 1.35 * lo,
        "rendered / predicted varies from {lo} to {hi}: {shift_effects:?}"
    );
    for row in &shift_effects {
        let (rendered, predicted) = ((row[0].0 > row[1].0), (row[0].1 > row[1].1));
        assert_eq!(
            rendered, predicted,
            "the shift moves the highlight the other way than the CPU model: {shift_effects:?}"
        );
    }

    // The primary lobe is white: green appears with it (the light where its default
    // 5° shift puts the peak).
    let a = 5f32.to_radians();
    let white = Lighting {
        light_direction: Vec3::new(0.0, a.sin(), -a.cos()),
        ks: 1.0,
        highlights: Highlights {
            secondary_strength: 0.0,
            ..Default::default()
        },
        ..base.clone()
    };
    let (colour, _) = mean_covered(&render(&white));
    assert!(
        colour.y > 0.1,
        "the primary highlight is not white: {colour}"
    );
    common::assert_clean(&device);
}
