//! `fur bench --quick` runs (validation on) and writes a complete, finite CSV, its
//! Markdown tables and the charts; `--only` runs chosen sections and rejects unknown
//! ones before any work.

use std::collections::HashSet;
use std::path::Path;
use std::process::Command;

#[test]
fn quick_bench_writes_every_expected_measurement() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench_quick");
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_fur"))
        .args([
            "bench",
            "--quick",
            "--validate",
            "--out-dir",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("section,case,metric,value,unit"));
    let mut seen = HashSet::new();
    let mut values = std::collections::HashMap::new();
    for line in lines {
        // Split off the quoted case, if any.
        let fields: Vec<String> = if let Some(start) = line.find('"') {
            let end = line[start + 1..].find('"').unwrap() + start + 1;
            let mut f: Vec<String> = vec![
                line[..start - 1].to_string(),
                line[start + 1..end].to_string(),
            ];
            f.extend(line[end + 2..].split(',').map(str::to_string));
            f
        } else {
            line.split(',').map(str::to_string).collect()
        };
        assert_eq!(fields.len(), 5, "malformed row: {line}");
        let value: f64 = fields[3]
            .parse()
            .unwrap_or_else(|_| panic!("not a number: {line}"));
        assert!(value.is_finite(), "non-finite measurement: {line}");
        seen.insert((fields[0].clone(), fields[1].clone(), fields[2].clone()));
        values.insert(
            (fields[0].clone(), fields[1].clone(), fields[2].clone()),
            value,
        );
    }
    let value = |section: &str, case: &str, metric: &str| {
        values[&(section.to_string(), case.to_string(), metric.to_string())]
    };
    let expect = |section: &str, case: &str, metric: &str| {
        assert!(
            seen.contains(&(section.to_string(), case.to_string(), metric.to_string())),
            "missing {section} / {case} / {metric}"
        );
    };
    // The truth section, where the path-traced reference is set up (CI requires it):
    // every scene (the walking critter too) with its terms dropped one at a time, and
    // dropping the multiple-scattering term changes the distance (the terms reach
    // the drawing).
    let truth_runs = seen.iter().any(|(section, _, _)| section == "truth");
    assert!(
        truth_runs || std::env::var_os("FUR_REFERENCE_REQUIRED").is_none(),
        "the truth section did not run although the reference is required"
    );
    if truth_runs {
        for scene in ["blob", "sphere", "critter-walking", "groom-drawn"] {
            expect("truth", scene, "own_flip");
            expect("truth", scene, "noise_flip");
            // What the reference cost (this run path-traced it: the folder is new).
            let seconds = value("truth", scene, "reference_seconds");
            assert!(seconds > 0.0, "{scene}: a reference traced in {seconds} s");
            // The seed's spread is measured drawing by drawing: never below zero, and
            // under the reference's own noise (a figure moves less than the image).
            let spread = value("truth", scene, "seed_spread_flip");
            let noise = value("truth", scene, "noise_flip");
            assert!(
                (0.0..=noise).contains(&spread),
                "{scene}: seed spread {spread} against reference noise {noise}"
            );
            let all = value("truth", &format!("{scene}: all terms"), "flip");
            for term in ["R", "TT", "TRT", "multiple scattering"] {
                expect("truth", &format!("{scene}: without {term}"), "flip");
            }
            let without = value(
                "truth",
                &format!("{scene}: without multiple scattering"),
                "flip",
            );
            assert!(
                (without - all).abs() > 1e-3,
                "{scene}: dropping multiple scattering left ꟻLIP at {without} (all terms {all})"
            );
        }
        // Each fur variant of the first scene has its terms taken apart too (the quick
        // suite's two: a preset and the texture).
        for variant in ["white", "tabby"] {
            for term in ["all terms", "without R", "without multiple scattering"] {
                expect("truth", &format!("blob-{variant}: {term}"), "flip");
            }
            // Each lit by the sun alone and by the sky alone: light adds, so the two
            // images over the full one are the background counted twice where no hair
            // covers it (between none and all of it, the path tracer's noise aside);
            // a light left on in its image, or lost from the export, breaks this.
            for light in ["sun", "sky"] {
                let case = format!("blob-{variant}: {light} alone");
                for metric in ["kajiya_kay_flip", "marschner_flip", "brightness"] {
                    expect("truth", &case, metric);
                }
            }
            // Each drawing's distance by scale: matching its light to the reference's
            // over ever smaller neighbourhoods leaves ever less of it (a match that
            // added its error, or kept the coarse light, would not fall so).
            for model in ["Kajiya–Kay", "Marschner"] {
                let case = format!("blob-{variant}: {model} by scale");
                let raw = value("truth", &case, "flip");
                let coarse = value("truth", &case, "matched_tenth_flip");
                let fine = value("truth", &case, "matched_thirty_sixth_flip");
                expect("truth", &case, "matched_twentieth_flip");
                assert!(
                    0.0 < fine && fine < coarse && coarse < raw,
                    "{case}: ꟻLIP {raw}, matched over a tenth of the width {coarse}, \
                     over a thirty-sixth {fine}"
                );
            }
            let case = format!("blob-{variant}: lights summed");
            let drawing = value("truth", &case, "drawing");
            assert!(
                (-0.05..=1.05).contains(&drawing),
                "{case}: the drawings' sum over the full one, {drawing} of the background"
            );
            let reference = value("truth", &case, "reference");
            assert!(
                (-0.5..=1.5).contains(&reference),
                "{case}: the references' sum over the full one, {reference} of the background"
            );
        }
    }
    for scene in ["blob", "sphere"] {
        for drawing in ["default", "reference quality"] {
            for metric in ["wall_ms", "gpu_ms", "hairs_drawn", "speedup_vs_original"] {
                expect("frame", &format!("{scene}, {drawing}"), metric);
            }
        }
        for pass in [
            "simulation",
            "mesh pass",
            "fur pass",
            "clear, resolve, copy",
        ] {
            expect("frame_passes", &format!("{scene}, {pass}"), "wall_ms");
        }
        for setting in ["reference quality", "default", "1x lines"] {
            let case = format!("{scene}: {setting}");
            for metric in [
                "frame_ms",
                "flip",
                "rmse",
                "hairs_drawn",
                "segments_drawn",
                "pareto",
            ] {
                expect("render_quality", &case, metric);
            }
        }
    }
    for it in [1, 2] {
        for sub in [1, 2] {
            let case = format!("iterations {it}, substeps {sub}");
            for metric in [
                "mean_position_error",
                "max_position_error",
                "max_stretch",
                "wall_ms_per_frame",
                "pareto",
            ] {
                expect("sim_accuracy", &case, metric);
            }
        }
    }
    for step in [
        "integrate",
        "global shape",
        "local shape",
        "edge length",
        "wind",
    ] {
        expect("sim_steps", step, "step_ms");
    }
    expect("sim_scaling", "1024 strands", "ns_per_strand");
    for saving in [
        "wind off: wind step compiled out",
        "S_G = 0: global-shape step compiled out",
        "collision off: collision step compiled out",
        "culling: hairs drawn",
        "density LOD: hairs drawn",
    ] {
        for metric in ["with", "without", "ratio"] {
            expect("savings", saving, metric);
        }
    }
    // The two strand rasterisers on both scenes: every figure, each compute step, the
    // pools' counts, and the same hair drawn by both.
    let on_cpu = fur_gpu::gpu::headless(false)
        .expect("a device")
        .info()
        .is_cpu();
    for scene in ["blob", "sphere"] {
        for raster in ["hardware", "compute"] {
            let case = format!("{scene}, {raster}");
            for metric in ["wall_ms", "gpu_ms", "fur_gpu_ms", "flip", "rmse"] {
                expect("raster", &case, metric);
            }
        }
        let hairs = |raster: &str| value("raster", &format!("{scene}, {raster}"), "hairs_drawn");
        assert_eq!(hairs("hardware"), hairs("compute"), "{scene}: hairs drawn");
        assert!(hairs("compute") > 0.0, "{scene}: no hair drawn");
        expect("raster", &format!("{scene}, between"), "flip");
        // The tiny frames put far more fragments in a pixel than it keeps in order:
        // under Kajiya–Kay (the sphere's default), every compute drawing errs less than
        // the fixed-function one against the supersampled reference, and keeping 4 or
        // 16 in order moves its error by under a fifth (the tail blended in the order
        // it comes). Seen failing against the tail as the mean of its fragments (the
        // blob's compute frames, then under Kajiya–Kay, 1.6–3.0× the fixed-function
        // frame's ꟻLIP, 4 in order 1.8× 16). Under the Marschner model (the blob's
        // default) the two drawings of the blob err alike here (ꟻLIP 0.0216 and
        // 0.0215, measured when it became the default): each compute drawing within a
        // tenth of the fixed-function one.
        let error = |case: &str| value("raster", &format!("{scene}, {case}"), "flip");
        // (On a CPU driver: a GPU's fixed-function frame has not been measured so.)
        let fixed = error("hardware");
        let allowed = if scene == "sphere" { 1.0 } else { 1.1 };
        for case in ["compute", "compute, 4 in order", "compute, 16 in order"] {
            assert!(
                !on_cpu || error(case) < allowed * fixed,
                "{scene}: {case} ꟻLIP {} against the fixed-function {fixed}",
                error(case)
            );
        }
        let (four, sixteen) = (error("compute, 4 in order"), error("compute, 16 in order"));
        assert!(
            (four - sixteen).abs() < 0.2 * four.min(sixteen),
            "{scene}: 4 in order ꟻLIP {four}, 16 in order {sixteen}"
        );
        for step in fur_gpu::render::STEP_NAMES {
            let step = step.trim_start_matches("strand ");
            expect("raster_steps", &format!("{scene}, {step}"), "gpu_ms");
            // A CPU driver's steps are also measured by leaving each out.
            if on_cpu {
                expect(
                    "raster_steps_left_out",
                    &format!("{scene}, {step}"),
                    "wall_ms",
                );
            }
        }
        if on_cpu {
            for part in ["the rest", "frame"] {
                expect(
                    "raster_steps_left_out",
                    &format!("{scene}, {part}"),
                    "wall_ms",
                );
            }
        }
        let count = |metric: &str| value("raster_counts", scene, metric);
        assert!(
            count("entries") >= count("segments"),
            "{scene}: fewer entries than segments"
        );
        // Each pixel a hair covers takes at least one fragment, and a tail's fragments
        // are some of them.
        assert!(
            count("fragments") >= count("tail_fragments") && count("fragments") > 0.0,
            "{scene}: {} fragments, {} in tails",
            count("fragments"),
            count("tail_fragments")
        );
        assert_eq!(
            count("hairs_lost") + count("entries_lost"),
            0.0,
            "{scene}: pools overflowed"
        );
    }
    // The quality ladder: every rung measured on both scenes, and its image error
    // ordered (each rung errs more than the one above; cost is the benchmark's to
    // measure, not a test's).
    // The device's ladder: the one the binary steps along on the device it chooses,
    // for the default drawing (both scenes draw with it).
    let ladder = fur_gpu::gpu::headless(false)
        .expect("a device")
        .info()
        .ladder(fur_core::render::FurStyle::default().raster);
    for scene in ["blob", "sphere"] {
        let mut last = -1.0f64;
        for (r, rung) in ladder.rungs.iter().enumerate() {
            let case = format!("{scene}: rung {r} ({})", rung.name);
            for metric in ["frame_ms", "flip", "ordered"] {
                expect("ladder", &case, metric);
            }
            let error = value("ladder", &case, "flip");
            assert!(
                error >= last,
                "{case}: ꟻLIP {error} below the rung above ({last})"
            );
            last = error;
        }
    }
    // The budget at work on the first scene: an orbit, then stillness.
    let orbit = "blob: orbit at 100 ms";
    for metric in [
        "median_ms",
        "settled_frames",
        "rung",
        "flip",
        "default_chosen_s",
        "back_to_default_s",
    ] {
        expect("ladder", orbit, metric);
    }
    let rung = value("ladder", orbit, "rung");
    assert!(rung >= 0.0 && rung < ladder.len() as f64);
    assert!(value("ladder", orbit, "settled_frames") >= 1.0);
    let chosen = value("ladder", orbit, "default_chosen_s");
    assert!(chosen >= 0.0 && value("ladder", orbit, "back_to_default_s") > chosen);
    // Animation: skinning, walking against standing, each way of colliding.
    expect("animation", "skinning", "us_per_vertex");
    expect("animation", "walking / standing", "ratio");
    for clip in ["Walk", "Idle"] {
        for metric in ["mean_offset", "max_offset", "max_normal_degrees"] {
            expect("animation", &format!("LBS vs DQS: {clip}"), metric);
        }
        // The clips bend joints, where the two methods differ: a measurement that
        // compared one skin with itself would give zero.
        assert!(value("animation", &format!("LBS vs DQS: {clip}"), "max_offset") > 0.0);
    }
    for metric in [
        "sampling_ms",
        "device_kib",
        "mean_penetration",
        "max_penetration",
    ] {
        for way in [
            "rest field carried by each root pose + bone capsules, the hair's first eighth by \
             its root's bone and its outer eighth through the skin's blend of bones (default)",
            "the same without the skin's blend (`--skin-blend off`)",
            "collision off",
        ] {
            expect("animation", way, metric);
        }
    }
    // Every stage view timed against the lit frame (the lit one's ratio is exactly 1).
    for stage in fur_core::render::Stage::ALL {
        for metric in ["frame", "ratio to lit"] {
            expect("stages", stage.name(), metric);
        }
    }
    assert_eq!(value("stages", "lit", "ratio to lit"), 1.0);
    // Groom files read: each format timed, USD's decoding memory within its limit.
    for format in ["usda", "usdc", "hair"] {
        expect("grooms", format, "read_s");
        assert!(value("grooms", format, "file_mib") > 0.0);
    }
    // The decoding's new address space is within its limit (memory the process had
    // freed before the fork is reused without being counted: after the other sections
    // it can be all the decoding needs, so zero is a valid peak here).
    for format in ["usda", "usdc"] {
        let peak = value("grooms", format, "peak_mib");
        let limit = fur_core::groom_file::usd_limits(0).memory as f64 / f64::from(1 << 20)
            + fur_core::groom_file::USD_MEMORY_PER_BYTE as f64
                * value("grooms", format, "file_mib");
        assert!(
            (0.0..limit).contains(&peak),
            "{format}: {peak} MiB against {limit}"
        );
    }
    // The flow laid on the quick suite's models: timed, and turning as a closed body's
    // field must (index sum 2).
    for model in ["blob", "critter (as a rigid body)"] {
        for metric in ["field_s", "grow_s"] {
            expect("flow", model, metric);
        }
        assert_eq!(value("flow", model, "index_sum"), 2.0, "{model}");
    }
    let md = std::fs::read_to_string(dir.join("results.md")).unwrap();
    assert!(md.contains("| iterations | substeps |"));
    assert!(md.contains("| view | frame ms | × lit |"));
    assert!(md.contains("| setting | frame ms | ꟻLIP | RMSE |"));
    for chart in ["sim_pareto.svg", "render_pareto.svg", "sim_scaling.svg"] {
        let svg = std::fs::read_to_string(dir.join(chart)).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("<circle"),
            "{chart} is not a chart"
        );
    }
}

#[test]
fn only_runs_the_chosen_sections_and_rejects_unknown_ones() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench_only");
    let _ = std::fs::remove_dir_all(&dir);
    let run = |only: &str| {
        Command::new(env!("CARGO_BIN_EXE_fur"))
            .args(["bench", "--quick", "--only", only, "--out-dir"])
            .arg(&dir)
            .output()
            .unwrap()
    };
    let out = run("sim_steps");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let sections: HashSet<&str> = csv
        .lines()
        .skip(1)
        .filter_map(|l| l.split(',').next())
        .collect();
    assert_eq!(sections, HashSet::from(["sim_steps"]));
    let bad = run("frame,warp_drive");
    assert!(!bad.status.success());
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("warp_drive") && stderr.contains("sim_scaling"),
        "{stderr}"
    );
}
