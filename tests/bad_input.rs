//! The bad-input corpus: files and flags a careless or hostile user gives `fur`, each
//! run as a process bounded in time by this harness. Every case asserts the exit
//! status, that the message names the problem, and that nothing panicked.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest any case may run before it counts as a hang.
const LIMIT: Duration = Duration::from_secs(90);

struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str]) -> Outcome {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("fur runs");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let out = child.wait_with_output().expect("output");
            return Outcome {
                code: status.code(),
                stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
                stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            };
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            panic!(
                "`fur {}` hung: still running after {LIMIT:?}",
                args.join(" ")
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn scratch() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bad_input");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn file(name: &str, bytes: &[u8]) -> String {
    let path = scratch().join(name);
    std::fs::File::create(&path)
        .unwrap()
        .write_all(bytes)
        .unwrap();
    path.to_str().unwrap().to_string()
}

/// A small valid OBJ: an octahedron scaled by `scale`, faces wound `outwards`.
fn octahedron(scale: f32, outwards: bool) -> String {
    let mut text = String::from("# octahedron\n");
    for p in [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ] {
        text += &format!("v {} {} {}\n", p[0] * scale, p[1] * scale, p[2] * scale);
    }
    for f in [
        [1, 3, 5],
        [3, 2, 5],
        [2, 4, 5],
        [4, 1, 5],
        [3, 1, 6],
        [2, 3, 6],
        [4, 2, 6],
        [1, 4, 6],
    ] {
        if outwards {
            text += &format!("f {} {} {}\n", f[0], f[1], f[2]);
        } else {
            text += &format!("f {} {} {}\n", f[0], f[2], f[1]);
        }
    }
    text
}

const SMALL: [&str; 6] = ["--width", "64", "--height", "36", "--density-scale", "0.05"];

/// `fur render --model MODEL` at a small size, writing into the scratch folder.
fn render_model(model: &str, extra: &[&str]) -> Outcome {
    let out = scratch().join(format!(
        "{}.png",
        Path::new(model).file_name().unwrap().to_string_lossy()
    ));
    let mut args = vec!["render", "--model", model, "--out", out.to_str().unwrap()];
    args.extend_from_slice(&SMALL);
    args.extend_from_slice(extra);
    let out = args.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    run(&out.iter().map(String::as_str).collect::<Vec<_>>())
}

fn fails(outcome: &Outcome, needle: &str, case: &str) {
    assert!(
        !outcome.stderr.contains("panicked"),
        "{case}: panicked:\n{}",
        outcome.stderr
    );
    assert!(
        matches!(outcome.code, Some(c) if c != 0 && c != 101),
        "{case}: exit status {:?}, expected a clean failure; stderr:\n{}",
        outcome.code,
        outcome.stderr
    );
    assert!(
        outcome
            .stderr
            .to_lowercase()
            .contains(&needle.to_lowercase()),
        "{case}: the message does not name the problem (`{needle}`):\n{}",
        outcome.stderr
    );
}

fn succeeds(outcome: &Outcome, warning: Option<&str>, case: &str) {
    assert!(
        !outcome.stderr.contains("panicked"),
        "{case}: panicked:\n{}",
        outcome.stderr
    );
    assert_eq!(
        outcome.code,
        Some(0),
        "{case}: failed:\n{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    if let Some(w) = warning {
        assert!(
            outcome.stderr.contains(w),
            "{case}: no warning `{w}`:\n{}",
            outcome.stderr
        );
    }
}

#[test]
fn malformed_models_fail_cleanly() {
    let garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "missing file",
            scratch().join("nope.obj").to_str().unwrap().into(),
            "no such file",
        ),
        ("a folder", scratch().to_str().unwrap().into(), "folder"),
        ("empty file", file("empty.obj", b""), "no faces"),
        (
            "vertices only",
            file("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
            "no faces",
        ),
        (
            "lines and points only",
            file("lines.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n"),
            "no faces",
        ),
        ("binary garbage", file("garbage.obj", &garbage), "no faces"),
        (
            "index out of bounds",
            file("oob.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            "vertex index out of bounds",
        ),
        (
            "negative index out of bounds",
            file("neg.obj", b"v 0 0 0\nv 1 0 0\nf -1 -2 -7\n"),
            "vertex index out of bounds",
        ),
        (
            "NaN coordinate",
            file("nan.obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
            "not finite",
        ),
        (
            "infinite coordinate",
            file("inf.obj", b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"),
            "not finite",
        ),
        (
            "degenerate faces",
            file("flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n"),
            "degenerate",
        ),
        (
            "missing normal index",
            file(
                "badvn.obj",
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//3\n",
            ),
            "normal index out of bounds",
        ),
        (
            "non-numeric vertex",
            file("text.obj", b"v zero one two\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            "position parse error",
        ),
    ];
    for (case, path, needle) in cases {
        let outcome = render_model(&path, &[]);
        fails(&outcome, needle, case);
        // And it names the model it could not read.
        let name = Path::new(&path).file_name().unwrap().to_string_lossy();
        assert!(
            outcome.stderr.contains("cannot read model") && outcome.stderr.contains(&*name),
            "{case}: the message does not name the model `{name}`:\n{}",
            outcome.stderr
        );
    }
}

#[test]
fn awkward_but_valid_models_render() {
    let plain = octahedron(1.0, true);
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend_from_slice(plain.as_bytes());
    let mut latin1 = b"# caf\xE9 \xFF model\n".to_vec();
    latin1.extend_from_slice(plain.as_bytes());
    let crlf = plain.replace('\n', "\r\n");
    let cases: Vec<(&str, String, Option<&str>)> = vec![
        ("byte-order mark", file("bom.obj", &bom), None),
        ("non-UTF-8 comment", file("latin1.obj", &latin1), None),
        ("CRLF line ends", file("crlf.obj", crlf.as_bytes()), None),
        (
            "a millionth of a unit",
            file("tiny.obj", octahedron(1e-6, true).as_bytes()),
            Some("scaled"),
        ),
        (
            "1e30 units",
            file("huge.obj", octahedron(1e30, true).as_bytes()),
            Some("scaled"),
        ),
        (
            "inside out",
            file(
                "inverted.obj",
                format!("{}vn 0 0 1\n", octahedron(1.0, false)).as_bytes(),
            ),
            None,
        ),
    ];
    for (case, path, warning) in cases {
        succeeds(&render_model(&path, &[]), warning, case);
    }
    // Normals in the file pointing inwards grow fur inwards: flipped, with a warning.
    let mut inward = String::new();
    for line in octahedron(1.0, true).lines() {
        inward += line;
        inward += "\n";
    }
    for i in 0..6 {
        let n = [
            [-1, 0, 0],
            [1, 0, 0],
            [0, -1, 0],
            [0, 1, 0],
            [0, 0, -1],
            [0, 0, 1],
        ][i];
        inward += &format!("vn {} {} {}\n", n[0], n[1], n[2]);
    }
    let inward = inward
        .lines()
        .map(|l| {
            if let Some(rest) = l.strip_prefix("f ") {
                let ids: Vec<&str> = rest.split_whitespace().collect();
                format!(
                    "f {}//{} {}//{} {}//{}\n",
                    ids[0], ids[0], ids[1], ids[1], ids[2], ids[2]
                )
            } else {
                format!("{l}\n")
            }
        })
        .collect::<String>();
    succeeds(
        &render_model(&file("inward.obj", inward.as_bytes()), &[]),
        Some("inside out"),
        "normals pointing inwards",
    );
    // Asking for the skin's blend on a body with no skin: it renders, and says the
    // flag changes nothing.
    succeeds(
        &render_model("sphere", &["--skin-blend", "on"]),
        Some("changes nothing"),
        "the skin's blend on a rigid body",
    );
}

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
            ],
            "64 MiB",
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

/// A run that fails after its output folder was checked leaves no folder behind.
#[test]
fn a_failed_run_leaves_no_output_folder() {
    let folder = scratch().join("never_made").join("frames");
    let _ = std::fs::remove_dir_all(scratch().join("never_made"));
    let out = folder.to_str().unwrap();
    let o = run(&[
        "render",
        "--frames",
        "3",
        "--amplitude",
        "nan",
        "--out-dir",
        out,
    ]);
    fails(&o, "amplitude", "render --amplitude nan --out-dir");
    assert!(
        !scratch().join("never_made").exists(),
        "the failed run left {}",
        folder.display()
    );
}

#[test]
fn bad_output_paths_fail_before_any_work() {
    let dir = scratch();
    let a_file = file("not_a_folder.txt", b"x");
    let under_file = format!("{a_file}/frame.png");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "render".into(),
                "--out".into(),
                dir.to_str().unwrap().into(),
            ],
            "folder",
        ),
        (
            vec!["render".into(), "--out".into(), under_file.clone()],
            "folder",
        ),
        (
            vec![
                "render".into(),
                "--frames".into(),
                "3".into(),
                "--out-dir".into(),
                a_file.clone(),
            ],
            "a regular file, not a folder",
        ),
        (
            vec!["export-model".into(), dir.to_str().unwrap().into()],
            "folder",
        ),
        (vec!["export-model".into(), under_file], "folder"),
        (
            vec!["bench".into(), "--out-dir".into(), a_file],
            "a regular file, not a folder",
        ),
    ];
    for (args, needle) in cases {
        let start = Instant::now();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        fails(&run(&args), needle, &args.join(" "));
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "`{}` worked before checking its output",
            args.join(" ")
        );
    }
    // Into a folder that does not exist yet: made, then written.
    let fresh = dir.join("new_folder/deeper/blob.obj");
    let _ = std::fs::remove_dir_all(dir.join("new_folder"));
    succeeds(
        &run(&["export-model", fresh.to_str().unwrap()]),
        None,
        "export into a new folder",
    );
    assert!(fresh.exists());
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

#[test]
fn bad_textures_fail_cleanly_and_a_missing_material_warns() {
    let dir = scratch();
    let missing = dir.join("no_such_texture.png");
    let text = file("notes.png", b"this is not an image\n");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--texture".into(), missing.display().to_string()],
            "no_such_texture.png",
        ),
        (vec!["--texture".into(), text.clone()], "notes.png"),
        (
            vec!["--texture".into(), dir.display().to_string()],
            "folder",
        ),
    ];
    for (extra, needle) in &cases {
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        fails(&render_model("sphere", &extra), needle, &extra.join(" "));
    }
    // A model without texture coordinates cannot take one.
    let plain = file("plain_octahedron.obj", octahedron(1.0, true).as_bytes());
    fails(
        &render_model(&plain, &["--texture", "tabby"]),
        "texture coordinates",
        "a texture on a model without UVs",
    );
    // A material library that is not there: a warning, and the model renders.
    let mut obj = String::from("mtllib gone.mtl\nusemtl fur\n");
    obj += &octahedron(1.0, true);
    let model = file("octahedron_without_mtl.obj", obj.as_bytes());
    succeeds(
        &render_model(&model, &[]),
        Some("gone.mtl"),
        "a missing .mtl",
    );
}
