//! Self-shadowing: depth into the fur darkens, off costs nothing.

use super::*;

/// A dense tuft of straight hairs on a plane, seen from the side (+Z).
fn tuft(light: Vec3, shadows: bool, draw_fur: bool) -> (Mesh, GroomParams, FrameSettings) {
    let groom = GroomParams {
        segments: 6,
        segment_length: 0.05,
        comb_strength: 0.0,
        ..Default::default()
    };
    let settings = FrameSettings {
        camera: Camera {
            target: Vec3::new(0.0, 0.1, 0.0),
            yaw_deg: 0.0,
            pitch_deg: 25.0,
            distance: 2.2,
            fov_y_deg: 40.0,
        },
        lighting: Lighting {
            light_direction: light,
            shadows: Shadows {
                enabled: shadows,
                ..Default::default()
            },
            ..Default::default()
        },
        draw_fur,
        style: FurStyle {
            density: 20_000.0,
            hair_width: 0.002,
            ..FurStyle::default()
        },
        ..Default::default()
    };
    (Mesh::grid(8, 8, 1.0), groom, settings)
}

fn mean_luma(image: &RgbaImage) -> f32 {
    let (c, _) = mean_covered(image);
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

#[test]
fn shadows_darken_with_depth_into_the_fur_and_shade_the_skin() {
    let device = common::device();
    let draw = |light: Vec3, shadows: bool, draw_fur: bool| {
        let (mesh, groom, settings) = tuft(light, shadows, draw_fur);
        common::render(&device, &mesh, &groom, &settings, (96, 96)).0
    };
    // Light behind the tuft: the side the camera sees lies under all of it.
    let behind = Vec3::new(0.0, 0.4, -1.0);
    let (lit, shadowed) = (draw(behind, false, true), draw(behind, true, true));
    common::keep(&shadowed, "shadows_light_behind");
    let back = mean_luma(&shadowed) / mean_luma(&lit);
    // Light from the camera's side: the visible hairs are the ones nearest the light.
    let front = Vec3::new(0.0, 0.4, 1.0);
    let facing = mean_luma(&draw(front, true, true)) / mean_luma(&draw(front, false, true));
    eprintln!("fur with shadows / without: light behind {back:.3}, light in front {facing:.3}");
    assert!(
        back < 0.75,
        "light behind: shadows darken the fur only to {back}"
    );
    assert!(
        facing > back + 0.1,
        "the side facing the light darkens as much ({facing} vs {back})"
    );
    // The skin under the fur (drawn alone, the fur still casting).
    let above = Vec3::new(0.2, 1.0, 0.3);
    let skin = mean_luma(&draw(above, true, false)) / mean_luma(&draw(above, false, false));
    assert!(
        skin < 0.8,
        "the fur shades the skin under it only to {skin}"
    );
    common::assert_clean(&device);
}

#[test]
fn shadows_off_cost_nothing_and_their_settings_change_nothing() {
    let device = common::device();
    let (mesh, groom, mut settings) = tuft(Vec3::new(0.0, 0.4, -1.0), false, true);
    let strands = fur::scene::Strands::grow(&mesh, &groom).unwrap();
    let textures =
        fur::strand_textures::StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = ash::vk::Extent2D {
        width: 64,
        height: 64,
    };
    let mut renderer = fur::render::Renderer::new(&device, &mesh, &textures, extent, 1, 4).unwrap();
    let (plain, _) = renderer.render(&textures, &settings).unwrap();
    settings.lighting.shadows = Shadows {
        enabled: false,
        resolution: 16,
        opacity: 1.0,
        spacing: 1e-4,
    };
    let (other, _) = renderer.render(&textures, &settings).unwrap();
    assert_eq!(
        renderer.shadow_maps(),
        0,
        "a shadow map exists with shadows off"
    );
    assert!(
        plain.data == other.data,
        "shadow settings changed a frame without shadows"
    );
    settings.lighting.shadows.enabled = true;
    let (shadowed, _) = renderer.render(&textures, &settings).unwrap();
    assert_eq!(renderer.shadow_maps(), 1);
    assert!(shadowed.data != plain.data);
    common::assert_clean(&device);
}
