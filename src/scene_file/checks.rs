//! The ranges a scene's values must lie in, each traced to the key that sets it.

use super::Scene;

/// Every range a scene's values must lie in, by section and key.
pub(super) fn checks(
    scene: &Scene,
) -> Vec<(&'static str, &'static str, std::result::Result<(), String>)> {
    let o = &scene.options;
    let positive = |v: f32| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(format!("must be a positive number, got {v}"))
        }
    };
    let within = |v: f32, lo: f32, hi: f32| {
        if v.is_finite() && (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(format!("must be in [{lo}, {hi}], got {v}"))
        }
    };
    let image = |v: u32| {
        if (1..=16384).contains(&v) {
            Ok(())
        } else {
            Err(format!("must be 1..=16384 pixels, got {v}"))
        }
    };
    let mut out = vec![
        ("image", "width", image(scene.width)),
        ("image", "height", image(scene.height)),
        ("camera", "yaw", within(o.yaw_deg, -1e6, 1e6)),
        ("camera", "pitch", within(o.pitch_deg, -1e6, 1e6)),
        ("camera", "distance", positive(o.distance.unwrap_or(1.0))),
        ("camera", "fov", within(o.fov_deg, 1.0, 170.0)),
        ("groom", "hair_length", positive(o.hair_length)),
        (
            "animation",
            "speed",
            within(scene.animation.speed, 0.0, 100.0),
        ),
        (
            "animation",
            "start",
            within(scene.animation.start, 0.0, 1e6),
        ),
        (
            "groom",
            "segments",
            if (1..=63).contains(&o.segments) {
                Ok(())
            } else {
                Err(format!("must be 1..=63, got {}", o.segments))
            },
        ),
        ("groom", "density_scale", positive(o.density_scale)),
        ("groom", "comb", within(o.comb, 0.0, 1e3)),
        ("groom", "curl", within(o.curl, 0.0, 1e3)),
        (
            "groom",
            "thickness_limit",
            within(o.thickness_limit, 0.0, 1e3),
        ),
        (
            "render",
            "samples",
            if matches!(o.draw.samples, 1 | 2 | 4 | 8 | 16) {
                Ok(())
            } else {
                Err(format!("must be 1, 2, 4, 8 or 16, got {}", o.draw.samples))
            },
        ),
        (
            "render",
            "ribbon_above",
            within(o.draw.ribbon_above_px, 0.0, 1e6),
        ),
        (
            "render",
            "vertex_lod",
            within(o.draw.vertex_lod_px, 0.0, 1e6),
        ),
        ("render", "lod_distance", positive(o.draw.lod_distance)),
        ("render", "hair_width", positive(o.draw.hair_width)),
        (
            "render",
            "min_pixel_width",
            within(o.draw.min_pixel_width, 0.0, 64.0),
        ),
        ("render", "jitter", within(o.draw.jitter, 0.0, 1e3)),
        (
            "render",
            "length_jitter",
            within(o.draw.length_jitter, 0.0, 1.0),
        ),
    ];
    let light = o.lighting.validate().map_err(|e| e.to_string());
    let (section, key) = light_key(&light);
    out.push((section, key, light));
    let sim = scene.sim.validate().map_err(|e| e.to_string());
    out.push((sim_section(&sim), sim_key(&sim), sim));
    let motion = if scene.motion.amplitude.is_finite() && scene.motion.rate.is_finite() {
        if scene.motion.rate >= 0.0 {
            Ok(())
        } else {
            Err(format!("must be ≥ 0, got {}", scene.motion.rate))
        }
    } else {
        Err("amplitude and rate must be finite".to_string())
    };
    out.push(("motion", "rate", motion));
    out
}

/// The section and key a lighting error is about, from its message.
fn light_key(error: &std::result::Result<(), String>) -> (&'static str, &'static str) {
    let Err(message) = error else {
        return ("light", "");
    };
    let shadows = [
        ("shadow opacity", "opacity"),
        ("shadow spacing", "spacing"),
        ("shadow map resolution", "resolution"),
    ];
    if let Some((_, key)) = shadows.iter().find(|(n, _)| message.contains(n)) {
        return ("shadows", key);
    }
    let fibre = [
        ("longitudinal roughness", "longitudinal_roughness"),
        ("azimuthal roughness", "azimuthal_roughness"),
        ("cuticle tilt", "cuticle_tilt"),
        ("index of refraction", "ior"),
    ];
    if let Some((_, key)) = fibre.iter().find(|(n, _)| message.contains(n)) {
        return ("fibre", key);
    }
    let key = [
        ("primary highlight's shift", "primary_shift"),
        ("secondary highlight's shift", "secondary_shift"),
        ("secondary highlight's exponent", "secondary_shininess"),
        ("secondary highlight's strength", "secondary_strength"),
        ("direction", "direction"),
        ("intensity", "intensity"),
        ("Kd", "kd"),
        ("Ks", "ks"),
        ("ambient", "ambient"),
        ("root occlusion", "root_occlusion"),
        ("exponent", "shininess"),
        ("root colour", "root_color"),
        ("tip colour", "tip_color"),
        ("skin colour", "skin_color"),
    ]
    .iter()
    .find(|(needle, _)| message.contains(needle))
    .map_or("", |(_, key)| key);
    ("light", key)
}

const SIM_KEYS: [(&str, &str, &str); 15] = [
    ("dt", "simulation", "dt"),
    ("substeps", "simulation", "substeps"),
    ("gravity", "simulation", "gravity"),
    ("damping", "simulation", "damping"),
    ("global stiffness", "simulation", "global_stiffness"),
    ("global range", "simulation", "global_range"),
    ("local stiffness", "simulation", "local_stiffness"),
    ("local iterations", "simulation", "local_iterations"),
    ("length iterations", "simulation", "length_iterations"),
    ("wind cone", "simulation", "wind_cone"),
    ("wind", "simulation", "wind"),
    ("collision margin", "collision", "margin"),
    ("friction", "collision", "friction"),
    ("resolution", "collision", "sdf_resolution"),
    ("collision", "collision", "enabled"),
];

fn sim_entry(error: &std::result::Result<(), String>) -> Option<(&'static str, &'static str)> {
    let Err(message) = error else { return None };
    SIM_KEYS
        .iter()
        .find(|(needle, _, _)| message.contains(needle))
        .map(|(_, section, key)| (*section, *key))
}

fn sim_section(error: &std::result::Result<(), String>) -> &'static str {
    sim_entry(error).map_or("simulation", |e| e.0)
}

fn sim_key(error: &std::result::Result<(), String>) -> &'static str {
    sim_entry(error).map_or("", |e| e.1)
}
