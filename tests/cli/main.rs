//! The `fur` binary: bad input gets a clear error and a non-zero exit, never a panic;
//! a simulated sequence shows the hair moving.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod budget;

fn fur(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the fur binary runs")
}

#[path = "../common/mod.rs"]
mod common;
use common::SMALL;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `fur` with `args`, expects failure with an error mentioning `needle`.
fn assert_fails_cleanly(args: &[&str], needle: &str) {
    let out = fur(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(!stderr.contains("panicked"), "{args:?} panicked:\n{stderr}");
    assert!(
        stderr.contains(needle),
        "{args:?}: error does not mention `{needle}`:\n{stderr}"
    );
}

#[test]
fn missing_model_is_a_clear_error() {
    assert_fails_cleanly(
        &["render", "--model", "/no/such/model.obj"],
        "/no/such/model.obj",
    );
}

#[test]
fn malformed_and_faceless_models_are_clear_errors() {
    let dir = scratch("bad_models");
    let cases = [
        ("garbage.obj", "v 1.0 banana 2.0\nf 1 2 3\n", "garbage.obj"),
        ("no_faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        (
            "bad_index.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
            "bad_index.obj",
        ),
        (
            "nan.obj",
            "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "nan.obj",
        ),
        (
            "degenerate.obj",
            "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
            "degenerate",
        ),
        ("empty.obj", "", "empty.obj"),
    ];
    for (name, text, needle) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let out = dir.join("out.png");
        assert_fails_cleanly(
            &[
                "render",
                "--model",
                path.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            needle,
        );
        assert!(!out.exists(), "{name}: an image was written");
    }
}

#[test]
fn impossible_parameters_are_clear_errors() {
    assert_fails_cleanly(&["render", "--segments", "0"], "segments");
    assert_fails_cleanly(&["render", "--segments", "64"], "segments");
    assert_fails_cleanly(&["render", "--substeps", "0"], "substeps");
    assert_fails_cleanly(&["render", "--local-stiffness", "1.5"], "local stiffness");
    assert_fails_cleanly(&["render", "--hair-length=-1"], "hair length");
    assert_fails_cleanly(&["render", "--width", "0"], "image size");
    assert_fails_cleanly(&["render", "--wind", "1,2"], "three");
    assert_fails_cleanly(&["render", "--motion", "dance"], "dance");
    assert_fails_cleanly(&["render", "--frames", "0"], "frames");
    assert_fails_cleanly(&["render", "--samples", "3"], "samples per pixel");
    assert_fails_cleanly(&["render", "--primitive", "cones"], "cones");
    assert_fails_cleanly(&["render", "--shading", "flat"], "flat");
    assert_fails_cleanly(&["render", "--vertex-lod=-1"], "vertex LOD");
    assert_fails_cleanly(&["render", "--yaw", "nan"], "--yaw");
    assert_fails_cleanly(&["render", "--collision", "maybe"], "maybe");
    assert_fails_cleanly(&["render", "--friction", "2"], "friction");
    assert_fails_cleanly(&["render", "--sdf-resolution", "4"], "resolution");
    assert_fails_cleanly(
        &["render", "--thickness-compensation", "perhaps"],
        "perhaps",
    );
    assert_fails_cleanly(&["export-model", "--model", "teapot.obj"], "built-in");
}

#[test]
fn a_simulated_sequence_moves_and_is_validated() {
    let dir = scratch("sequence");
    let out = fur(&[
        &[
            "render",
            "--validate",
            "--frames",
            "4",
            "--motion",
            "shake",
            "--rate",
            "3",
            "--out-dir",
            dir.to_str().unwrap(),
        ],
        SMALL.as_slice(),
    ]
    .concat());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "fur failed:\n{stderr}");
    // The run ends with the median of its warm frames.
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout.lines().last().unwrap_or_default();
    let ms: f64 = last
        .strip_prefix("median frame ")
        .and_then(|rest| rest.split(" ms").next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no median frame line: {stdout}"));
    assert!(ms > 0.0 && last.contains("2 warm frames"), "{last}");
    let frames: Vec<Vec<u8>> = (0..4)
        .map(|i| std::fs::read(dir.join(format!("frame_{i:04}.png"))).expect("frame written"))
        .collect();
    assert!(
        frames.windows(2).all(|w| w[0] != w[1]),
        "consecutive frames are identical"
    );
}

#[test]
fn the_shipped_model_is_the_built_in_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/blob.obj");
    let shipped = fur_core::scene::Mesh::load_obj(&path).unwrap();
    let built_in = fur_core::scene::Mesh::blob();
    assert_eq!(shipped.vertex_count(), built_in.vertex_count());
    assert_eq!(shipped.triangle_count(), built_in.triangle_count());
    // Loading renumbers vertices in order of first use; triangles keep their order.
    for (a, b) in shipped.indices.iter().zip(&built_in.indices) {
        let (pa, pb) = (
            shipped.positions[*a as usize],
            built_in.positions[*b as usize],
        );
        assert!((pa - pb).length() < 1e-5, "{pa} vs {pb}");
    }
    // Rendering it through the CLI works like the default scene.
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("blob_from_obj.png");
    let model = [
        "--model",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let run = fur(&[["render", "--validate"].as_slice(), &model, &SMALL].concat());
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(out.exists());
}

#[test]
fn the_original_sphere_is_built_in_and_exports() {
    let obj = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sphere.obj");
    let out = fur(&["export-model", "--model", "sphere", obj.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sphere = fur_core::scene::Mesh::load_obj(&obj).unwrap();
    assert_eq!(
        (sphere.vertex_count(), sphere.triangle_count()),
        (3161, 6240)
    );
    let png = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sphere.png");
    let run = fur(&[
        "render",
        "--validate",
        "--model",
        "sphere",
        "--out",
        png.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "54",
        "--samples",
        "1",
        "--primitive",
        "lines",
    ]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(stdout.contains("3161 master hairs"), "{stdout}");
    assert!(png.exists());
}

#[test]
fn nothing_is_left_alive_at_exit() {
    // A render, a simulated sequence with collision, and a benchmark section, each
    // with the validation layer on: its object tracker reports any Vulkan object still
    // alive when the device is destroyed, and gpu-allocator any memory not freed.
    let dir = scratch("leaks");
    let png = dir.join("one.png");
    let runs: [Vec<&str>; 3] = [
        vec![
            "render",
            "--validate",
            "--width",
            "64",
            "--height",
            "36",
            "--density-scale",
            "0.1",
            "--out",
            png.to_str().unwrap(),
        ],
        vec![
            "render",
            "--validate",
            "--frames",
            "3",
            "--width",
            "64",
            "--height",
            "36",
            "--density-scale",
            "0.1",
            "--out-dir",
            dir.to_str().unwrap(),
        ],
        vec![
            "bench",
            "--validate",
            "--quick",
            "--only",
            "sim_steps",
            "--out-dir",
            dir.to_str().unwrap(),
        ],
    ];
    for args in runs {
        let out = fur(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("validation at teardown") && !stderr.to_lowercase().contains("leak"),
            "{args:?} left something alive:\n{stderr}"
        );
    }
    assert!(png.exists());
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with(".tmp"), "left behind: {name}");
    }
}

/// Sends SIGINT to a running `fur` once `ready` holds, and returns its exit status and
/// how long it took to stop.
fn interrupt(
    args: &[&str],
    ready: impl Fn() -> bool,
) -> (Option<i32>, std::time::Duration, String) {
    use std::time::{Duration, Instant};
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !ready() {
        assert!(start.elapsed() < Duration::from_secs(60), "never got going");
        assert!(
            child.try_wait().unwrap().is_none(),
            "ended before the signal"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let sent = Instant::now();
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let out = child.wait_with_output().unwrap();
            return (
                status.code(),
                sent.elapsed(),
                String::from_utf8_lossy(&out.stderr).into_owned(),
            );
        }
        if sent.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            panic!("still running 20 s after Ctrl-C");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn ctrl_c_stops_a_sequence_and_the_benchmark_cleanly() {
    let dir = scratch("interrupted");
    let _ = std::fs::remove_dir_all(&dir);
    let args = [
        "render",
        "--frames",
        "10000",
        "--width",
        "96",
        "--height",
        "64",
        "--density-scale",
        "0.1",
        "--out-dir",
        dir.to_str().unwrap(),
    ];
    let third = dir.join("frame_0002.png");
    let (code, took, stderr) = interrupt(&args, || third.exists());
    assert_eq!(code, Some(130), "{stderr}");
    let unit = 6.0; // the unit in hand: a frame, or a pipeline build the driver must finish
    assert!(took.as_secs_f64() < unit, "took {took:?} to stop");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| n.ends_with(".png")),
        "half-written files: {names:?}"
    );
    assert!(
        names.len() >= 3,
        "frames already written were lost: {names:?}"
    );
    for name in &names {
        let bytes = std::fs::read(dir.join(name)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{name} is not a whole PNG");
    }

    let bench = scratch("interrupted_bench");
    let started = std::time::Instant::now();
    let (code, took, stderr) = interrupt(
        &["bench", "--quick", "--out-dir", bench.to_str().unwrap()],
        || started.elapsed().as_secs_f64() > 3.0,
    );
    assert_eq!(code, Some(130), "{stderr}");
    assert!(
        took.as_secs_f64() < unit,
        "the benchmark took {took:?} to stop"
    );
}

// `fur render --budget-ms` and `fur view --target-fps`: the budget steps a sequence
// down the quality ladder and prints the rungs, a generous one keeps the default
// drawing, and impossible values are refused.
