//! The fur pass end to end on lavapipe, validation on: coverage, lighting, level of
//! detail, exactly-once hair generation and big strand textures.

mod common;

use fur::render::{kajiya_kay, FrameSettings, FurStyle, Lighting, Primitive};
use fur::scene::{Camera, GroomParams, Mesh};
use glam::Vec3;

const SIZE: (u32, u32) = (192, 144);

fn blob_settings() -> FrameSettings {
    let mesh = Mesh::blob();
    let (center, radius) = mesh.bounds();
    FrameSettings {
        camera: Camera {
            target: center,
            distance: 2.6 * radius,
            ..Default::default()
        },
        ..Default::default()
    }
}

fn blob_groom() -> GroomParams {
    GroomParams {
        segments: 8,
        segment_length: 0.03,
        ..Default::default()
    }
}

#[test]
fn default_scene_grows_fur_beyond_the_silhouette_and_is_lit() {
    let device = common::device();
    let mesh = Mesh::blob();
    let settings = blob_settings();
    let bare = FrameSettings {
        draw_fur: false,
        ..settings.clone()
    };
    let (furry_image, stats, _) = common::render(&device, &mesh, &blob_groom(), &settings, SIZE);
    let (bare_image, _, _) = common::render(&device, &mesh, &blob_groom(), &bare, SIZE);
    common::keep(&furry_image, "default_furry");
    let furry = common::covered(&furry_image);
    let skin = common::covered(&bare_image);
    let beyond = furry.iter().zip(&skin).filter(|(f, s)| **f && !**s).count();
    let skin_count = skin.iter().filter(|c| **c).count();
    assert!(
        skin_count > 1000,
        "the mesh covers only {skin_count} pixels"
    );
    assert!(
        beyond as f32 > 0.05 * skin_count as f32,
        "fur covers only {beyond} pixels outside the bare silhouette of {skin_count}"
    );
    assert!(stats.geometry_invocations > 1000, "{stats:?}");
    // Lit, not flat: luma varies over the fur.
    let lumas: Vec<f32> = (0..furry_image.height)
        .flat_map(|y| (0..furry_image.width).map(move |x| (x, y)))
        .zip(&furry)
        .filter(|(_, c)| **c)
        .map(|((x, y), _)| furry_image.luma(x, y))
        .collect();
    let mean = lumas.iter().sum::<f32>() / lumas.len() as f32;
    let std = (lumas.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / lumas.len() as f32).sqrt();
    assert!(
        std > 0.05,
        "fur luma is nearly uniform: mean {mean}, std {std}"
    );
    common::assert_clean(&device);
}

/// Points a triangle patch generates at uniform level n (equal spacing, point mode).
fn points_per_patch(n: u64) -> u64 {
    3 + 3 * (n - 1) + inner_points(n)
}

/// Points strictly inside a triangle at uniform level n: rings of 3m points for
/// m = n-2, n-4, …, and a centre point when n is even.
fn inner_points(n: u64) -> u64 {
    let mut m = n as i64 - 2;
    let mut total = 0;
    while m >= 0 {
        total += if m == 0 { 1 } else { 3 * m as u64 };
        m -= 2;
    }
    total
}

#[test]
fn every_interpolated_hair_is_generated_and_drawn_exactly_once() {
    let device = common::device();
    let mesh = Mesh::icosphere(1);
    let (v, e, f) = (
        mesh.vertex_count() as u64,
        mesh.edge_count() as u64,
        mesh.triangle_count() as u64,
    );
    for n in [1u64, 2, 3, 5] {
        let mut settings = FrameSettings {
            camera: Camera {
                distance: 4.0,
                ..Default::default()
            },
            ..Default::default()
        };
        settings.style = FurStyle {
            fixed_level: n as u32,
            cull: false,
            ..FurStyle::default()
        };
        let groom = GroomParams {
            segments: 4,
            segment_length: 0.05,
            ..Default::default()
        };
        let unique = v + e * (n - 1) + f * inner_points(n);
        let segments = u64::from(groom.segments);
        for primitive in [Primitive::Ribbons, Primitive::Lines] {
            for samples in [1, 4] {
                settings.style.primitive = primitive;
                settings.style.samples = samples;
                settings.style.vertex_lod_px = 0.0;
                let (_, stats, counts) =
                    common::render(&device, &mesh, &groom, &settings, (64, 64));
                // Each patch evaluates each of its points once…
                assert_eq!(
                    stats.tess_eval_invocations,
                    f * points_per_patch(n),
                    "level {n}: {stats:?}"
                );
                assert_eq!(
                    stats.geometry_invocations, stats.tess_eval_invocations,
                    "level {n}"
                );
                // …and points shared along edges and corners are drawn by one patch
                // only: every distinct point of the tessellated surface is one hair,
                // with all its segments.
                assert_eq!(counts.hairs, unique, "level {n}, {primitive:?}");
                assert_eq!(
                    counts.segments,
                    unique * segments,
                    "level {n}, {primitive:?}"
                );
                let per_segment = if primitive == Primitive::Ribbons {
                    2
                } else {
                    1
                };
                assert_eq!(
                    stats.geometry_primitives,
                    unique * per_segment * segments,
                    "level {n}, {primitive:?}: {stats:?}"
                );
            }
        }
        // With vertex LOD the same hairs are drawn, in fewer segments (the groom's
        // comb bends them gently).
        settings.style.primitive = Primitive::Ribbons;
        settings.style.vertex_lod_px = 1.0;
        let (_, _, counts) = common::render(&device, &mesh, &groom, &settings, (64, 64));
        assert_eq!(counts.hairs, unique, "level {n} with vertex LOD");
        assert!(
            counts.segments < unique * segments && counts.segments >= unique,
            "level {n}: vertex LOD drew {} segments for {unique} hairs",
            counts.segments
        );
    }
    common::assert_clean(&device);
}

#[test]
fn hair_count_grows_as_the_camera_approaches_and_culled_triangles_cost_nothing() {
    let device = common::device();
    let mesh = Mesh::icosphere(2);
    let groom = GroomParams {
        segments: 4,
        segment_length: 0.05,
        ..Default::default()
    };
    let mut counts = Vec::new();
    for distance in [2.5f32, 5.0, 10.0, 20.0] {
        let mut settings = FrameSettings {
            camera: Camera {
                distance,
                ..Default::default()
            },
            ..Default::default()
        };
        settings.style.density = 3000.0;
        settings.style.lod_distance = 2.0;
        let (_, stats, _) = common::render(&device, &mesh, &groom, &settings, (96, 96));
        counts.push(stats.tess_eval_invocations);
    }
    assert!(
        counts.windows(2).all(|w| w[0] > w[1]),
        "not decreasing with distance: {counts:?}"
    );

    // Looking away from the model: every triangle is off-screen.
    let mut away = FrameSettings {
        camera: Camera {
            target: Vec3::new(0.0, 0.0, 10.0),
            yaw_deg: 180.0, // the eye sits at z = 5, looking further away from the model
            pitch_deg: 0.0,
            distance: 5.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let (_, stats, _) = common::render(&device, &mesh, &groom, &away, (96, 96));
    assert_eq!(stats.patches, mesh.triangle_count() as u64);
    assert_eq!(
        stats.tess_eval_invocations, 0,
        "off-screen triangles generated hairs"
    );

    // A flat patch of fur seen from behind: back-facing, culled.
    let plane = Mesh::grid(4, 4, 1.0);
    away.camera = Camera {
        pitch_deg: -60.0,
        distance: 2.0,
        ..Default::default()
    };
    let (_, from_below, _) = common::render(&device, &plane, &groom, &away, (96, 96));
    away.camera.pitch_deg = 60.0;
    let (_, from_above, _) = common::render(&device, &plane, &groom, &away, (96, 96));
    assert_eq!(
        from_below.tess_eval_invocations, 0,
        "back-facing triangles generated hairs"
    );
    assert!(from_above.tess_eval_invocations > 0);
    common::assert_clean(&device);
}

#[test]
fn kajiya_kay_brightness_follows_the_cpu_formula() {
    // Straight hairs standing up (+Y) on a plane, seen from the side; the light turns
    // from along the hair to across it. The tangent parallel to the light is darkest.
    let device = common::device();
    let plane = Mesh::grid(6, 6, 1.0);
    let groom = GroomParams {
        segments: 6,
        segment_length: 0.06,
        comb_strength: 0.0,
        ..Default::default()
    };
    let camera = Camera {
        target: Vec3::new(0.0, 0.2, 0.0),
        yaw_deg: 0.0,
        pitch_deg: 20.0,
        distance: 2.0,
        ..Default::default()
    };
    let mut measured = Vec::new();
    let mut predicted = Vec::new();
    for angle in [0.0f32, 30.0, 60.0, 90.0] {
        let a = angle.to_radians();
        let light = Vec3::new(a.sin(), a.cos(), 0.0);
        let lighting = Lighting {
            light_direction: light,
            ks: 0.0,
            ambient: 0.0,
            root_occlusion: 0.0,
            root_color: Vec3::splat(0.8),
            tip_color: Vec3::splat(0.8),
            ..Default::default()
        };
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
        let (image, _, _) = common::render(&device, &plane, &groom, &settings, (128, 96));
        common::keep(&image, &format!("kajiya_kay_{angle}"));
        let covered = common::covered(&image);
        let lumas: Vec<f32> = (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .zip(&covered)
            .filter(|(_, c)| **c)
            .map(|((x, y), _)| image.luma(x, y))
            .collect();
        assert!(lumas.len() > 200, "too little fur visible at {angle}°");
        measured.push(lumas.iter().sum::<f32>() / lumas.len() as f32);
        let eye_to_hair = (Vec3::new(0.0, 0.2, 0.0) - camera.eye()).normalize();
        predicted.push(kajiya_kay(Vec3::Y, light, eye_to_hair, &lighting).diffuse);
    }
    for i in 1..measured.len() {
        assert!(
            (measured[i] > measured[i - 1]) == (predicted[i] > predicted[i - 1]),
            "brightness {measured:?} does not follow Kajiya–Kay {predicted:?}"
        );
    }
    assert!(
        measured[0] < 0.5 * measured[3],
        "hair along the light is not dark: {measured:?}"
    );
    common::assert_clean(&device);
}

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
    let strands = fur::scene::Strands::grow(&mesh, &groom).unwrap();
    let textures =
        fur::strand_textures::StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let max = device.info().limits.max_image_dimension2_d;
    assert!(strands.count() as u32 > max.min(16_384) || textures.layout.height > 1);
    // Every strand vertex reads back where the layout put it.
    let back = textures.read_positions(textures.current).unwrap();
    assert_eq!(back.len(), strands.positions.len());
    assert!(
        back.iter().zip(&strands.positions).all(|(a, b)| a == b),
        "strand texture round trip differs"
    );
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
    common::keep(&image, "fifty_thousand");
    assert!(stats.geometry_invocations > 10_000, "{stats:?}");
    assert!(common::covered(&image).iter().filter(|c| **c).count() > 1000);
    common::assert_clean(&device);
}
