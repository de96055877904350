//! The frame-time budget of a sequence (`fur render --frames N --budget-ms X`): it steps
//! down the device's ladder and says so, and impossible budgets are refused.

use super::{assert_fails_cleanly, fur, scratch, SMALL};

/// A small validated sequence of `frames` under a budget of `ms`; its standard output
/// and error.
fn sequence(name: &str, frames: &str, ms: &str) -> (String, String) {
    let dir = scratch(&format!("budget_{name}"));
    let out = fur(&[
        &[
            "render",
            "--validate",
            "--frames",
            frames,
            "--budget-ms",
            ms,
            "--out-dir",
            dir.to_str().unwrap(),
        ],
        SMALL.as_slice(),
    ]
    .concat());
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

/// An unreachable budget (a microsecond a frame) takes the sequence down the device's
/// ladder to its cheapest rung within three warm frames, printing each change, and says
/// the budget is still missed; a generous one (ten seconds a frame) never leaves the
/// default drawing. A budget that did nothing passes neither.
#[test]
fn a_budget_steps_a_sequence_down_the_ladder_and_prints_the_rungs() {
    let device = fur_gpu::gpu::headless(false).expect("a device");
    let rungs = device
        .info()
        .ladder(fur_core::render::FurStyle::default().raster)
        .len();
    let (stdout, stderr) = sequence("tight", "64", "0.001");
    let steps: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains(": quality rung "))
        .collect();
    assert!(!steps.is_empty(), "no rung was printed:\n{stderr}");
    // The first descent is quick: the cheapest rung is reached within three frames of
    // the first warm one (frames 0 and 1 compile and are not observed); stepping one
    // rung per 8 frames took until frame 42.
    let reached: u32 = steps
        .iter()
        .find(|l| l.contains(&format!("quality rung {}", rungs - 1)))
        .and_then(|l| l.trim().strip_prefix("frame "))
        .and_then(|l| l.split(':').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("the cheapest rung was never printed:\n{stderr}"));
    assert!(
        reached <= 6,
        "the cheapest rung at frame {reached}:\n{stderr}"
    );
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

#[test]
fn impossible_budgets_and_frame_rates_are_refused() {
    for ms in ["0", "-5", "NaN", "inf", "1e400", "3600000"] {
        assert_fails_cleanly(
            &["render", "--frames", "4", "--budget-ms", ms],
            "--budget-ms must be a positive number of milliseconds",
        );
    }
    assert_fails_cleanly(
        &["render", "--budget-ms", "100"],
        "--budget-ms needs a sequence",
    );
    assert_fails_cleanly(
        &["render", "--frames", "1", "--budget-ms", "100"],
        "--budget-ms needs a sequence",
    );
    assert_fails_cleanly(&["render", "--budget-ms", "fast"], "--budget-ms");
    // The viewer checks its frame rate before it opens a window.
    for fps in ["-1", "NaN", "inf", "1001"] {
        assert_fails_cleanly(
            &["view", "--target-fps", fps],
            "--target-fps must be 0 (off) to 1000 frames per second",
        );
    }
}
