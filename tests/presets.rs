//! Fur presets reach the frame (lavapipe, validation on): the path tracer is handed the
//! preset's colour exactly, so it sees the preset's melanin; white fur draws brighter
//! than black; `none` is the scene's own colours.

mod common;

use std::path::Path;

use fur_core::render::FurPreset;
use glam::Vec3;

fn ok(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "fur failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn mean(path: &Path) -> f32 {
    let img = image::open(path).unwrap().to_rgb8();
    img.pixels()
        .map(|p| f32::from(p[0]) + f32::from(p[1]) + f32::from(p[2]))
        .sum::<f32>()
        / img.pixels().len() as f32
}

#[test]
fn a_preset_colours_the_drawing_and_the_export_alike() {
    let dir = common::scratch("presets", "draw");
    let size = ["--width", "96", "--height", "54", "--validate"];
    let png = |name: &str| dir.join(format!("{name}.png"));
    for preset in ["none", "white", "black"] {
        let out = png(preset);
        ok(&common::fur(
            &[
                &[
                    "render",
                    "--fur-preset",
                    preset,
                    "--out",
                    out.to_str().unwrap(),
                ][..],
                &size,
            ]
            .concat(),
        ));
    }
    let plain = png("plain");
    ok(&common::fur(
        &[&["render", "--out", plain.to_str().unwrap()][..], &size].concat(),
    ));
    assert_eq!(
        std::fs::read(png("none")).unwrap(),
        std::fs::read(&plain).unwrap()
    );
    assert!(
        mean(&png("white")) > 1.5 * mean(&png("black")),
        "white {} vs black {}",
        mean(&png("white")),
        mean(&png("black"))
    );
    // The export hands the path tracer the preset's colour, to the bit.
    let usda = dir.join("blond.usda");
    ok(&common::fur(
        &[
            &[
                "export-frame",
                usda.to_str().unwrap(),
                "--fur-preset",
                "blond",
            ][..],
            &[
                "--width",
                "96",
                "--height",
                "54",
                "--out",
                png("blond").to_str().unwrap(),
            ],
        ]
        .concat(),
    ));
    let text = std::fs::read_to_string(&usda).unwrap();
    // The hairs' colours (the body's come first).
    let line = text
        .lines()
        .rfind(|l| l.contains("primvars:displayColor"))
        .unwrap();
    let first = line
        .split("= [(")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let c: Vec<f32> = first.split(", ").map(|x| x.parse().unwrap()).collect();
    let want = FurPreset::Blond.colour(0.3).unwrap();
    assert_eq!(Vec3::new(c[0], c[1], c[2]), want, "{line:.200}");
}
