//! Self-shadowing: depth into the fur darkens, off costs nothing.

use super::*;
use fur_core::render::Stage;

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
            // The seed's model, whose shadow is the grey (1 − α)^layers; the Marschner
            // model's light through the coat is checked below, named.
            model: fur_core::render::LightingModel::KajiyaKay,
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
    // The shadow map's depth as the fixed-function rasteriser shows it, each sample the
    // nearest hair: the compute passes blend the hairs behind the nearest too, which
    // narrows the two sides' difference (0.66 against 0.75 there); their shadows are
    // measured against the path-traced truth (`fur bench --only truth`).
    let draw = |light: Vec3, shadows: bool, draw_fur: bool| {
        let (mesh, groom, mut settings) = tuft(light, shadows, draw_fur);
        settings.style.raster = fur_core::render::Raster::Hardware;
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
    let strands = fur_core::scene::Strands::grow(&mesh, &groom).unwrap();
    let textures =
        fur_gpu::strand_textures::StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = ash::vk::Extent2D {
        width: 64,
        height: 64,
    };
    let mut renderer =
        fur_gpu::render::Renderer::new(&device, &mesh, &textures, extent, 1, 4).unwrap();
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

/// With the Marschner model, light comes through the fur in the fibres' colour: of
/// each layer's light, dual scattering passes 1 − α unscattered (grey) and α · a_f
/// forward in the fibres' colour. The shadow view shows all that comes through: through
/// blond fibres its channels fall as the CPU twin's per-layer transmittances do
/// (ln T_red / ln T_blue is the twin's ratio at any one depth; the map's filter, mixing
/// depths and the lit fringe, pulls it towards 1), through black fibres (a_f ≈ 0) it is
/// grey, and white fibres let more of it through than black ones (seen failing with
/// the forward-scattered part left out: every colour then grey and alike).
#[test]
fn light_through_fibres_takes_their_colour() {
    let device = common::device();
    let behind = Vec3::new(0.0, 0.4, -1.0);
    let draw = |colour: Vec3| {
        let (mesh, groom, mut settings) = tuft(behind, true, true);
        settings.show = Stage::Shadow;
        // Wide opaque hairs: a pixel is one hair's colour, not a blend with the
        // background.
        settings.style.hair_width = 0.01;
        settings.style.thin_hair_aa = false;
        settings.draw_mesh = false;
        let l = &mut settings.lighting;
        l.model = fur_core::render::LightingModel::Marschner;
        (l.root_color, l.tip_color) = (colour, colour);
        common::render(&device, &mesh, &groom, &settings, (96, 96)).0
    };
    // The twin's ratio of ln transmittance, red over blue, per layer, at the hairs'
    // angle to the light (they stand along +Y).
    let fibre = fur_core::render::Fibre::default();
    let table = fur_core::render::dual_scattering::cached_table(&fibre);
    let twin_ratio = |colour: Vec3| {
        let ln_c = Vec3::from_array(colour.to_array().map(f32::ln));
        let u = behind.normalize().y;
        let a_f = fur_core::render::dual_scattering::fibre_averages(&table, u, ln_c).a_f;
        let one = fur_core::render::marschner::Layers {
            count: 1.0,
            opacity: fur_core::render::Shadows::default().opacity,
        };
        let (_, through) = one.through(a_f);
        through.x.ln() / through.z.ln()
    };
    let ratio = |image: &RgbaImage| {
        let (mut r, mut b) = (0.0, 0.0);
        let background = image.pixel(0, 0);
        for y in 0..image.height {
            for x in 0..image.width {
                let p = image.pixel(x, y);
                let (lr, lb) = (linear(p[0]), linear(p[2]));
                // Hair in shadow: not the background, not the lit fringe (where 8 bits
                // leave ln T to rounding).
                if p != background && lb < 0.5 && lb > 0.0 {
                    r += lr.ln();
                    b += lb.ln();
                }
            }
        }
        r / b
    };
    let blond = fur_core::render::FurPreset::Blond.colour(0.3).unwrap();
    let blond_view = draw(blond);
    common::keep(&blond_view, "shadow_view_blond_marschner");
    let (drawn, twin) = (ratio(&blond_view), twin_ratio(blond));
    let black = fur_core::render::FurPreset::Black.colour(0.3).unwrap();
    let black_view = draw(black);
    let grey = ratio(&black_view);
    eprintln!(
        "ln T red / ln T blue through blond fur: drawn {drawn:.3}, twin {twin:.3}; black {grey:.3}"
    );
    assert!(twin < 0.8, "the twin's blond is nearly grey: {twin}");
    // Between the twin's ratio and 1, clear of 1 (measured 0.833 against the twin's
    // 0.483 and black's 1.015: mixing a deep pixel with lit light raises its blue far
    // more than its red).
    assert!(
        drawn > twin - 0.03 && drawn < 1.0 - 0.25 * (1.0 - twin),
        "the shadow's colour is not the twin's: {drawn} vs {twin}"
    );
    assert!(
        (grey - 1.0).abs() < 0.05,
        "light through black fur is not grey: {grey}"
    );
    // White fibres pass more on than black ones.
    let (white_light, _) = mean_covered(&draw(Vec3::ONE));
    let (black_light, _) = mean_covered(&black_view);
    eprintln!("light through white fur {white_light}, through black {black_light}");
    assert!(
        white_light.y > 1.1 * black_light.y,
        "light goes no deeper into white fur: {white_light} vs {black_light}"
    );
    common::assert_clean(&device);
}

/// Under the Marschner model without a shadow map the skin lies under the coat's
/// estimate: L hair layers (the coat's mean height at the layer spacing), which the
/// light crosses slanted by its angle θ to the skin and the sky straight down, each
/// layer passing 1 − α. The skin alone (the fur not drawn) against the same under
/// Kajiya–Kay, whose skin the coat does not shade: (ambient · (1 − α)^L + Kd · I ·
/// cos θ · (1 − α)^(L / cos θ)) / (ambient + Kd · I · cos θ), over every skin pixel.
#[test]
fn the_coat_shades_the_skin_under_the_marschner_model() {
    let device = common::device();
    let light = Vec3::new(0.0, 1.0, 0.8).normalize();
    let (mesh, groom, mut settings) = tuft(light, false, false);
    settings.lighting.skin_color = Vec3::splat(0.5);
    // Two layers over the skin: a spacing of half the coat's height.
    let strands = fur_core::scene::Strands::grow(&mesh, &groom).unwrap();
    let height = strands.coat_height();
    settings.lighting.shadows.spacing = height / 2.0;
    let bare = common::render(&device, &mesh, &groom, &settings, (64, 64)).0;
    settings.lighting.model = fur_core::render::LightingModel::Marschner;
    let shaded = common::render(&device, &mesh, &groom, &settings, (64, 64)).0;
    let luma = |image: &RgbaImage| {
        let (mut sum, mut n) = (0.0, 0);
        for (p, covered) in image.data.chunks(4).zip(common::covered(image)) {
            if covered {
                sum += 0.2126 * linear(p[0]) + 0.7152 * linear(p[1]) + 0.0722 * linear(p[2]);
                n += 1;
            }
        }
        assert!(n > 500, "{n} skin pixels");
        sum / n as f32
    };
    let l = &settings.lighting;
    let (layers, pass, cos) = (2.0_f32, 1.0 - l.shadows.opacity, light.y);
    let direct = l.kd * l.intensity * cos;
    let expected =
        (l.ambient * pass.powf(layers) + direct * pass.powf(layers / cos)) / (l.ambient + direct);
    let measured = luma(&shaded) / luma(&bare);
    eprintln!("skin under the coat / bare: {measured:.4}, expected {expected:.4}");
    assert!(
        (measured - expected).abs() < 0.03 * expected,
        "the skin under the coat takes {measured} of the bare skin's light, not {expected}"
    );
    common::assert_clean(&device);
}
