//! `fur render --budget-ms` and `fur view --target-fps` from the command line: the
//! budget steps a sequence down the quality ladder and prints the rungs, a generous one
//! keeps the default drawing, and impossible values are refused with a clear error.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fur(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the fur binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("budget_cli")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small validated sequence of `frames` under a budget of `ms`; its standard output
/// and error.
fn sequence(name: &str, frames: &str, ms: &str) -> (String, String) {
    let dir = scratch(name);
    let out = fur(&[
        "render",
        "--validate",
        "--frames",
        frames,
        "--budget-ms",
        ms,
        "--width",
        "96",
        "--height",
        "64",
        "--density-scale",
        "0.2",
        "--segments",
        "6",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "fur failed:\n{stderr}");
    (stdout, stderr)
}

/// The rung the summary line says the last frame was drawn at.
fn last_rung(stdout: &str) -> usize {
    let line = stdout
        .lines()
        .find(|l| l.contains("the last frame was drawn at quality rung"))
        .unwrap_or_else(|| panic!("no budget summary in:\n{stdout}"));
    let after = line.split("quality rung ").nth(1).unwrap();
    after.split_whitespace().next().unwrap().parse().unwrap()
}

/// An unreachable budget (a microsecond a frame) walks the sequence down the ladder to
/// its cheapest rung, printing each step, and says the budget is still missed; a
/// generous one (ten seconds a frame) never leaves the default drawing. A budget that
/// did nothing passes neither.
#[test]
fn a_budget_steps_a_sequence_down_the_ladder_and_prints_the_rungs() {
    let rungs = fur::render::budget::LADDER.len();
    let (stdout, stderr) = sequence("tight", "64", "0.001");
    let steps: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains(": quality rung "))
        .collect();
    assert!(!steps.is_empty(), "no rung was printed:\n{stderr}");
    assert_eq!(
        last_rung(&stdout),
        rungs - 1,
        "an unreachable budget ends at the cheapest rung:\n{stdout}"
    );
    assert!(
        stdout.contains("even the cheapest rung misses the budget"),
        "{stdout}"
    );
    let (stdout, stderr) = sequence("generous", "6", "10000");
    assert_eq!(last_rung(&stdout), 0, "{stdout}");
    assert!(!stderr.contains(": quality rung "), "{stderr}");
    assert!(!stdout.contains("misses the budget"), "{stdout}");
}

/// Runs `fur` with `args`, expects failure with an error mentioning `needle`.
fn refused(args: &[&str], needle: &str) {
    let out = fur(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(!stderr.contains("panicked"), "{args:?} panicked:\n{stderr}");
    assert!(
        stderr.contains(needle),
        "{args:?}: the error does not mention `{needle}`:\n{stderr}"
    );
}

#[test]
fn impossible_budgets_and_frame_rates_are_refused() {
    for ms in ["0", "-5", "NaN", "inf", "1e400", "3600000"] {
        refused(
            &["render", "--frames", "4", "--budget-ms", ms],
            "--budget-ms must be a positive number of milliseconds",
        );
    }
    refused(
        &["render", "--budget-ms", "100"],
        "--budget-ms needs a sequence",
    );
    refused(
        &["render", "--frames", "1", "--budget-ms", "100"],
        "--budget-ms needs a sequence",
    );
    refused(&["render", "--budget-ms", "fast"], "--budget-ms");
    // The viewer checks its frame rate before it opens a window.
    for fps in ["-1", "NaN", "inf", "1001"] {
        refused(
            &["view", "--target-fps", fps],
            "--target-fps must be 0 (off) to 1000 frames per second",
        );
    }
}
