//! Impossible flags, oversized work and viewer scripts.

use super::*;

#[test]
fn oversized_work_is_refused_before_it_starts() {
    // A polygon of 100,000 sides: triangulated and drawn, or refused, but never a hang.
    let mut polygon = String::new();
    let n = 100_000;
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        polygon += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    polygon += "f";
    for i in 1..=n {
        polygon += &format!(" {i}");
    }
    polygon += "\n";
    let outcome = render_model(&file("polygon.obj", polygon.as_bytes()), &[]);
    assert!(!outcome.stderr.contains("panicked"), "{}", outcome.stderr);
    assert!(
        outcome.code == Some(0) || outcome.stderr.contains("limit"),
        "100,000-sided face: {:?}\n{}",
        outcome.code,
        outcome.stderr
    );
    // A grid of 640,000 vertices each growing 17: over the strand-vertex limit.
    let mut grid = String::with_capacity(20_000_000);
    let side = 800;
    for j in 0..side {
        for i in 0..side {
            grid += &format!("v {i} 0 {j}\n");
        }
    }
    for j in 0..side - 1 {
        for i in 0..side - 1 {
            let a = j * side + i + 1;
            grid += &format!("f {} {} {}\n", a, a + side, a + 1);
        }
    }
    fails(
        &render_model(&file("big.obj", grid.as_bytes()), &[]),
        "strand vertices",
        "640,000 vertices",
    );
    fails(
        &run(&[
            "render",
            "--density-scale",
            "1e9",
            "--width",
            "64",
            "--height",
            "36",
        ]),
        "limit",
        "density ×1e9",
    );
    fails(
        &run(&["render", "--width", "16384", "--height", "16384"]),
        "GiB",
        "a 16384² image",
    );
    // One sample fits the target's limit; the compute rasteriser's pools do not, and
    // are refused before the target is made.
    fails(
        &run(&[
            "render",
            "--raster",
            "compute",
            "--samples",
            "1",
            "--width",
            "16384",
            "--height",
            "16384",
        ]),
        "compute rasteriser's pools for a 16384×16384 image",
        "a 16384² image in compute",
    );
}

#[test]
fn impossible_flags_fail_cleanly() {
    let cases: &[(&[&str], &str)] = &[
        (&["render", "--yaw", "nan"], "--yaw"),
        (&["render", "--pitch", "inf"], "--pitch"),
        (&["render", "--distance=-1"], "camera distance"),
        (&["render", "--distance", "nan"], "camera distance"),
        (&["render", "--hair-length", "0"], "hair length"),
        (&["render", "--density-scale", "nan"], "density"),
        (&["render", "--segments", "0"], "segments"),
        (&["render", "--samples", "3"], "samples per pixel"),
        (&["render", "--width", "0"], "image size"),
        (&["render", "--frames", "0"], "frames"),
        (&["render", "--gravity", "nan"], "gravity"),
        (&["render", "--wind", "nan,0,0"], "wind"),
        (
            &["render", "--frames", "3", "--amplitude", "nan"],
            "amplitude",
        ),
        (&["render", "--frames", "3", "--rate=-1"], "rate"),
        (&["render", "--friction", "2"], "friction"),
        (&["render", "--collision-margin", "5"], "collision margin"),
        (&["render", "--sdf-resolution", "4"], "resolution"),
        (&["render", "--skin-blend", "perhaps"], "skin-blend"),
        (
            &[
                "render",
                "--model",
                "critter",
                "--skin-blend",
                "on",
                "--sdf-resolution",
                "128",
                "--thickness-limit",
                "0",
            ],
            "32 MiB",
        ),
        (&["render", "--vertex-lod=-1"], "vertex LOD"),
        (&["render", "--primitive", "cones"], "cones"),
        (
            &["render", "--model", "sphere", "--ribbon-above", "nan"],
            "ribbon",
        ),
        (&["bench", "--only", "warp_drive"], "warp_drive"),
        (
            &["render", "--shadow-resolution", "4"],
            "shadow map resolution",
        ),
        (&["render", "--shadow-opacity", "2"], "shadow opacity"),
        (&["render", "--shadow-spacing=-1"], "shadow spacing"),
        (&["render", "--primary-shift", "90"], "primary highlight"),
        (
            &["render", "--secondary-shininess", "0"],
            "secondary highlight",
        ),
        (
            &["render", "--secondary-strength", "nan"],
            "secondary highlight",
        ),
        (&["render", "--texture", ""], "tabby"),
        (&["render", "--shadows", "maybe"], "--shadows"),
    ];
    for (args, needle) in cases {
        fails(&run(args), needle, &args.join(" "));
    }
}

#[test]
fn viewer_scripts_are_checked_before_a_window_opens() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["view", "--frames", "3", "--script", "5:screenshot=a.png"],
            "would never run",
        ),
        (
            &["view", "--frames", "10", "--script", "10:wind=on"],
            "would never run",
        ),
        (&["view", "--script", "5:teleport=1"], "bad script event"),
        (&["view", "--script", "x:wind=on"], "bad script event"),
        (&["view", "--frames", "0"], "frames"),
    ];
    for (args, needle) in cases {
        fails(&run(args), needle, &args.join(" "));
    }
}
