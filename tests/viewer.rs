//! `fur view` in a real X window under Xvfb (validation on): scripted resizes, camera
//! moves, wind and motion, minimising, and a screenshot that shows fur.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs `fur view` with `args` on the current display, or under `xvfb-run` when there
/// is none. Kills it after `limit` (a hang fails the test).
fn view(args: &[&str], limit: Duration) -> Output {
    let fur = env!("CARGO_BIN_EXE_fur");
    let mut command = if std::env::var_os("DISPLAY").is_some() {
        let mut c = Command::new(fur);
        c.arg("view");
        c
    } else {
        assert!(
            Command::new("xvfb-run").arg("--help").output().is_ok(),
            "no DISPLAY and no xvfb-run: install xvfb (see README)"
        );
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1280x1024x24", fur, "view"]);
        c
    };
    let mut child = command
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("fur view starts");
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!(
                "fur view hung for {limit:?}:\n{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("viewer")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn assert_ok(out: &Output) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "fur view failed:\n{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Nothing left alive at exit: the validation layer's object tracker and
    // gpu-allocator report leaks while the device is torn down.
    assert!(
        !stderr.contains("validation at teardown") && !stderr.to_lowercase().contains("leak"),
        "{stderr}"
    );
}

#[test]
fn scripted_session_is_validated_and_its_screenshot_shows_fur() {
    let dir = scratch("session");
    let shot = dir.join("shot.png");
    let script = format!(
        "10:resize=400x300; 30:orbit=40,-10; 40:wind=on; 60:resize=300x220; 70:move=0.1,0,0; 80:shake=on; 110:screenshot={}",
        shot.display()
    );
    let out = view(
        &[
            "--validate",
            "--frames",
            "120",
            "--width",
            "320",
            "--height",
            "240",
            "--density-scale",
            "0.3",
            "--segments",
            "8",
            "--script",
            &script,
        ],
        Duration::from_secs(240),
    );
    assert_ok(&out);
    let (pixels, size) = screenshot(&shot);
    // The window was resized to 300×220 before the screenshot.
    assert_eq!(size, (300, 220));
    let covered = covered(&pixels);
    assert!(
        covered.len() > pixels.len() / 10,
        "the model covers only {} pixels",
        covered.len()
    );
    // Fur: a light, warm colour ramp with variation, unlike the flat dark skin.
    let luma: Vec<f32> = covered
        .iter()
        .map(|p| (0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32) / 255.0)
        .collect();
    let mean = luma.iter().sum::<f32>() / luma.len() as f32;
    let std = (luma.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / luma.len() as f32).sqrt();
    assert!(
        mean > 0.3 && std > 0.03,
        "covered pixels look flat: mean {mean}, std {std}"
    );
    let warm = covered.iter().filter(|p| p[0] > p[2]).count();
    assert!(
        warm > covered.len() / 2,
        "the covered pixels are not fur-coloured"
    );
}

#[test]
fn a_one_pixel_window_and_minimising_neither_crash_nor_hang() {
    let out = view(
        &[
            "--validate",
            "--frames",
            "40",
            "--width",
            "64",
            "--height",
            "48",
            "--density-scale",
            "0.1",
            "--segments",
            "4",
            "--script",
            "5:resize=1x1; 15:minimize=on; 25:minimize=off; 30:resize=80x60",
        ],
        Duration::from_secs(120),
    );
    assert_ok(&out);
}

#[test]
fn without_a_display_it_says_to_use_render() {
    let out = Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("fur render") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

#[test]
fn bad_scripts_are_rejected_before_opening_a_window() {
    let out = Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["view", "--script", "10:fly=away"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("10:fly=away"), "{stderr}");
    // A setting changed live: an unknown one, a bad value, one read only at start.
    for (script, named) in [
        ("10:set=render.rasteriser=compute", "render.rasteriser"),
        ("10:set=render.raster=sideways", "sideways"),
        ("10:set=render.nearest=99", "99"),
        ("10:set=collision.sdf_resolution=32", "--sdf-resolution"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_fur"))
            .args(["view", "--script", script])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{script}");
        assert!(stderr.contains(named), "{script}: {stderr}");
    }
}

/// The pixels of the PNG at `path` and its size.
fn screenshot(path: &Path) -> (Vec<[u8; 4]>, (u32, u32)) {
    let file = std::fs::File::open(path).expect("the screenshot was written");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut data = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut data).unwrap();
    let pixels = data
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect();
    (pixels, (info.width, info.height))
}

/// The pixels unlike the first (the background's): what the model covers.
fn covered(pixels: &[[u8; 4]]) -> Vec<[u8; 4]> {
    let background = pixels[0];
    pixels
        .iter()
        .copied()
        .filter(|p| (0..3).any(|c| p[c].abs_diff(background[c]) > 8))
        .collect()
}

/// The strand rasteriser switched live, as the panel switches it (a scripted `set=`):
/// hardware to compute, the fragments in order changed, back to hardware, the hair
/// paused so that only the drawing changes; every frame validation-clean, each
/// screenshot fur. On a GPU the compute frames differ from the hardware one and from
/// each other; on a CPU driver the viewer keeps the fixed-function rasteriser (Mesa
/// 22.3's lavapipe crashes drawing the window after the compute passes: seen, a
/// segmentation fault on the second frame), says so once, and the frames are equal.
#[test]
fn the_strand_rasteriser_switches_live() {
    let dir = scratch("raster_live");
    let shot = |name: &str| dir.join(format!("{name}.png"));
    let script = format!(
        "0:pause=on; 4:set=render.raster=compute; 10:screenshot={}; 12:set=render.nearest=1; \
         18:screenshot={}; 20:set=render.raster=hardware; 26:screenshot={}",
        shot("compute").display(),
        shot("nearest1").display(),
        shot("hardware").display()
    );
    let out = view(
        &[
            "--validate",
            "--frames",
            "28",
            "--width",
            "240",
            "--height",
            "180",
            "--target-fps",
            "0",
            "--density-scale",
            "0.3",
            "--segments",
            "8",
            "--script",
            &script,
        ],
        Duration::from_secs(300),
    );
    assert_ok(&out);
    let [compute, nearest1, hardware] = ["compute", "nearest1", "hardware"].map(|name| {
        let (pixels, size) = screenshot(&shot(name));
        assert_eq!(size, (240, 180), "{name}");
        let covered = covered(&pixels).len();
        assert!(
            covered > pixels.len() / 10,
            "{name}: {covered} pixels covered"
        );
        pixels
    });
    let differing = |a: &[[u8; 4]], b: &[[u8; 4]]| a.iter().zip(b).filter(|(p, q)| p != q).count();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let held = stderr
        .matches("draws the strands with the fixed-function rasteriser")
        .count();
    if held > 0 {
        assert_eq!(held, 1, "said more than once:\n{stderr}");
        assert_eq!(
            differing(&compute, &hardware),
            0,
            "held, yet drawn differently"
        );
        assert_eq!(
            differing(&compute, &nearest1),
            0,
            "held, yet drawn differently"
        );
    } else {
        assert!(
            differing(&compute, &hardware) > 100,
            "the compute frame is the hardware one"
        );
        assert!(
            differing(&compute, &nearest1) > 100,
            "nearest 1 changed nothing"
        );
    }
}

#[test]
fn the_viewer_saves_a_scene_that_reproduces_its_view() {
    let dir = scratch("save_scene");
    let saved = dir.join("saved.toml");
    let _ = std::fs::remove_file(&saved);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/velvet.toml");
    let out = view(
        &[
            scene.to_str().unwrap(),
            "--validate",
            "--width",
            "160",
            "--height",
            "120",
            "--frames",
            "6",
            "--script",
            "1:orbit=30,-10; 2:zoom=0.5; 3:wind=off",
            "--save-scene",
            saved.to_str().unwrap(),
        ],
        Duration::from_secs(120),
    );
    assert_ok(&out);
    let original = fur_core::scene_file::Scene::load(Some(&scene), None).unwrap();
    let loaded = fur_core::scene_file::Scene::load(Some(&saved), None).unwrap();
    // The file's look, the script's camera and wind, the window's size.
    assert_eq!(loaded.options.segments, original.options.segments);
    // The same light (the viewer keeps its direction normalised).
    let (a, b) = (&loaded.options.lighting, &original.options.lighting);
    assert!(
        a.light_direction
            .normalize()
            .distance(b.light_direction.normalize())
            < 1e-5
    );
    assert_eq!(
        fur_core::render::Lighting {
            light_direction: b.light_direction,
            ..a.clone()
        },
        *b
    );
    assert!((loaded.options.yaw_deg - (original.options.yaw_deg + 30.0)).abs() < 1e-4);
    assert!((loaded.options.pitch_deg - (original.options.pitch_deg - 10.0)).abs() < 1e-4);
    assert!(
        (loaded.options.distance.unwrap() - 0.5 * original.options.distance.unwrap()).abs() < 1e-4
    );
    assert!((loaded.options.draw.density / original.options.draw.density - 1.0).abs() < 1e-3);
    assert_eq!(loaded.sim.wind, glam::Vec3::ZERO);
    assert_eq!((loaded.width, loaded.height), (160, 120));
    // And it renders.
    let png = dir.join("saved.png");
    let render = Command::new(env!("CARGO_BIN_EXE_fur"))
        .args([
            "render",
            saved.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        render.status.success(),
        "{}",
        String::from_utf8_lossy(&render.stderr)
    );
}

/// With a budget no drawing can meet, the viewer steps down the quality ladder while
/// the camera moves, climbs back to the default once input stops (measuring the ꟻLIP of
/// the rung it moved at there), and its last frame is the default drawing, pixel for
/// pixel (the same run without a budget).
#[test]
fn the_budget_steps_down_while_moving_and_back_when_still() {
    let dir = scratch("budget");
    // A person orbiting: input every frame for 40 frames.
    let orbits: String = (1..=40).map(|k| format!("; {k}:orbit=1,0")).collect();
    let shot = |name: &str, fps: &str| {
        let path = dir.join(name);
        let script = format!(
            "0:resize=160x120; 0:pause=on{orbits}; 159:screenshot={}",
            path.display()
        );
        let out = view(
            &[
                "--model",
                "sphere",
                "--density-scale",
                "0.3",
                "--frames",
                "160",
                "--target-fps",
                fps,
                "--validate",
                "--script",
                &script,
            ],
            Duration::from_secs(240),
        );
        assert_ok(&out);
        (path, String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let (budgeted, log) = shot("budget.png", "1000");
    let line = log
        .lines()
        .find(|l| l.starts_with("quality:"))
        .unwrap_or_else(|| panic!("no quality line:\n{log}"));
    let rungs: Vec<usize> = line
        .split("rung ")
        .skip(1)
        .map(|s| s.split(' ').next().unwrap().parse().unwrap())
        .collect();
    assert!(
        rungs.iter().any(|&r| r >= 2),
        "never stepped down far: {line}"
    );
    assert_eq!(rungs.last(), Some(&0), "did not climb back: {line}");
    // At the still view the rung the view moved at was measured against the default
    // drawing: a cheaper drawing differs from it.
    let measured = log
        .lines()
        .find(|l| l.starts_with("measured: rung "))
        .unwrap_or_else(|| panic!("no rung was measured:\n{log}"));
    let rung: usize = measured["measured: rung ".len()..]
        .split(' ')
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no rung in {measured}"));
    assert!(rung > 0 && rungs.contains(&rung), "{measured} ({line})");
    let error: f64 = measured
        .split("ꟻLIP ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no ꟻLIP in {measured}"));
    assert!(error > 0.0 && error < 1.0, "{measured}");
    let (plain, _) = shot("plain.png", "0");
    let a = image::open(&budgeted).unwrap().to_rgba8();
    let b = image::open(&plain).unwrap().to_rgba8();
    assert_eq!(a.dimensions(), b.dimensions());
    let differing = a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
    assert_eq!(
        differing, 0,
        "{differing} pixels differ from the default drawing"
    );
}

/// Stepping through: paused at the first frame, the simulation runs exactly one step
/// (1/60 s) per press of the step key, and none otherwise; switching to the simulation
/// view with arrows on the way (the number key 6) rebuilds the kernel with frames in
/// flight, validation-clean. Unpaused counted runs step once a frame.
#[test]
fn a_paused_viewer_steps_exactly_once_per_step_key() {
    let run = |script: &str| {
        let out = view(
            &[
                "--validate",
                "--frames",
                "14",
                "--width",
                "200",
                "--height",
                "150",
                "--density-scale",
                "0.2",
                "--segments",
                "6",
                "--arrows",
                "length",
                "--script",
                script,
            ],
            Duration::from_secs(180),
        );
        assert_ok(&out);
        let stdout = String::from_utf8_lossy(&out.stdout).to_string();
        let summary = stdout
            .lines()
            .find(|l| l.contains("simulation steps"))
            .unwrap_or_else(|| panic!("no summary in:\n{stdout}"))
            .to_string();
        summary
    };
    let stepped = run("0:pause=on; 2:key=6; 4:key=n; 7:key=n; 9:key=n");
    assert!(
        stepped.contains("; 3 simulation steps (0.0500 s simulated)"),
        "{stepped}"
    );
    let held = run("0:pause=on; 2:key=6");
    assert!(
        held.contains("; 0 simulation steps (0.0000 s simulated)"),
        "{held}"
    );
    let running = run("2:key=6");
    assert!(running.contains("; 14 simulation steps"), "{running}");
}
