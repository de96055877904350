//! Self-shadowing: depth into the fur darkens, off costs nothing.

use super::*;
use fur::render::Stage;

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
        coloured: true,
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

/// With the Marschner model, light comes through the fur in the fibres' colour. The
/// shadow view shows that light alone: through blond fibres its channels fall as the
/// CPU twin's per-layer transmittances do (ln T_red / ln T_blue is the twin's ratio at
/// any one depth; the map's filter, mixing depths, pulls it towards 1), white fur lets
/// the light in deeper, black fur's shadow is the grey term. The same frames with
/// coloured shadows off (`[shadows] coloured`, the default: fibres stop the light
/// greyly) fail the first two.
#[test]
fn light_through_fibres_takes_their_colour() {
    let device = common::device();
    let behind = Vec3::new(0.0, 0.4, -1.0);
    let draw = |colour: Vec3, shadows: bool, show: Stage, grey: bool| {
        let (mesh, groom, mut settings) = tuft(behind, shadows, true);
        settings.lighting.shadows.coloured = !grey;
        settings.show = show;
        // Wide opaque hairs: a pixel is one hair's colour, not a blend with the
        // background.
        settings.style.hair_width = 0.01;
        settings.style.thin_hair_aa = false;
        settings.draw_mesh = show != Stage::Shadow;
        let l = &mut settings.lighting;
        l.model = fur::render::LightingModel::Marschner;
        (l.root_color, l.tip_color, l.root_occlusion) = (colour, colour, 0.0);
        common::render(&device, &mesh, &groom, &settings, (96, 96)).0
    };
    let grey = true;
    let blond = fur::render::FurPreset::Blond.colour(0.3).unwrap();
    // The twin's ratio of ln transmittance, red over blue, per layer.
    let fibre = fur::render::Fibre::default();
    let sigma_a = fur::render::marschner::sigma_a_from_color(blond, fibre.azimuthal_roughness);
    let opacity = fur::render::Shadows::default().opacity;
    let one = fur::render::marschner::light_through_fibres(1.0, opacity, sigma_a, fibre.ior);
    let twin = one.x.ln() / one.z.ln();
    let ratio = |image: &RgbaImage| {
        let (mut r, mut b) = (0.0, 0.0);
        let background = image.pixel(0, 0);
        for y in 0..image.height {
            for x in 0..image.width {
                let p = image.pixel(x, y);
                let (lr, lb) = (linear(p[0]), linear(p[2]));
                // Hair in shadow: not the background, not the lit fringe (where 8 bits
                // leave ln T to rounding).
                if p != background && lb < 0.5 {
                    r += lr.ln();
                    b += lb.ln();
                }
            }
        }
        r / b
    };
    let shadow_view = draw(blond, true, Stage::Shadow, false);
    common::keep(&shadow_view, "shadow_view_blond_marschner");
    let coloured = ratio(&shadow_view);
    let flat = ratio(&draw(blond, true, Stage::Shadow, grey));
    eprintln!("ln T red / ln T blue through blond fur: drawn {coloured:.3}, twin {twin:.3}, grey {flat:.3}");
    // The map's bilinear filter and the vertices' interpolation mix depths, which pulls
    // the ratio from the twin's towards 1 (an equal mix of the lit and a deep layer
    // is grey): it lies between the two (measured 0.86), clear of the grey term's 1
    // (measured 1.02; 8-bit rounding moves it by ±0.02).
    assert!(
        coloured > 0.9 * twin && coloured < 0.92,
        "the shadow's colour is not the twin's: {coloured} vs {twin}"
    );
    assert!(
        (flat - 1.0).abs() < 0.05,
        "the grey term is not grey: {flat}"
    );
    // Per channel: the shadowed fur's mean over the unshadowed one's.
    let kept = |colour: Vec3, grey: bool| {
        let (lit, _) = mean_covered(&draw(colour, false, Stage::Lit, grey));
        let (shadowed, _) = mean_covered(&draw(colour, true, Stage::Lit, grey));
        shadowed / lit
    };
    let (white, white_grey) = (kept(Vec3::ONE, false), kept(Vec3::ONE, grey));
    eprintln!("white, kept: coloured {white:.3}, grey {white_grey:.3}");
    // Measured 0.834 against 0.745 (the ambient and multiple-scattering terms, which
    // shadows do not reach, keep both well above 0).
    assert!(
        white.y > 1.06 * white_grey.y,
        "light goes no deeper into white fur: {white} vs grey {white_grey}"
    );
    let black = fur::render::FurPreset::Black.colour(0.3).unwrap();
    let (a, b) = (
        draw(black, true, Stage::Lit, false),
        draw(black, true, Stage::Lit, grey),
    );
    let differ = a
        .data
        .iter()
        .zip(&b.data)
        .filter(|(x, y)| x.abs_diff(**y) > 1)
        .count();
    assert!(
        differ * 100 < a.data.len(),
        "black fur's shadow is not grey: {differ} values differ"
    );
    common::assert_clean(&device);
}
