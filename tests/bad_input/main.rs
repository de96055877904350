//! The bad-input corpus: files and flags a careless or hostile user gives `fur`, each
//! run as a process bounded in time by this harness. Every case asserts the exit
//! status, that the message names the problem, and that nothing panicked. Models and
//! textures are in `models.rs`, flags and scripts in `flags.rs`, output paths in
//! `outputs.rs`.

mod flags;
mod models;
mod outputs;

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
