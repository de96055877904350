//! `--groom-mode draw`: each guide of a groom is drawn as it is, one hair per guide, on
//! rigid and skinned bodies; `fur export-groom` gives the guides back.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use fur_core::groom_file::{read_groom, Guides};
use glam::Vec3;

fn fur(args: &[&str]) -> Output {
    common::fur(args)
}

fn scratch(name: &str) -> PathBuf {
    common::scratch("groom_draw", name)
}

fn ok(out: &Output) -> String {
    common::succeeded(out)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn length(c: &[Vec3]) -> f32 {
    c.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Guides a little curled (so that an interpolated or jittered hair could not pass
/// for one), rooted at every third vertex of the blob's own groom.
fn curled_guides(own: &Guides) -> Guides {
    let mut out = Guides {
        counts: Vec::new(),
        points: Vec::new(),
        widths: None,
        colors: None,
        notes: Vec::new(),
    };
    for (g, curve) in own.curves().enumerate().filter(|(g, _)| g % 3 == 0) {
        let tip = curve[curve.len() - 1] - curve[0];
        let side = tip.any_orthonormal_vector() * 0.15 * tip.length();
        let turn = g as f32 * 0.7;
        out.counts.push(9);
        out.points.extend((0..9).map(|k| {
            let t = k as f32 / 8.0;
            curve[0] + tip * t + side * (turn + 6.0 * t).sin() * t
        }));
    }
    out
}

/// Every guide is drawn once and exactly as it is: the frame's hairs as the geometry
/// stage emits them (`fur export-frame`) are the guides, resampled to the segment
/// count, each within 1e-5 of its length (no interpolation, no jitter).
#[test]
fn each_guide_is_drawn_once_as_it_is() {
    let dir = scratch("drawn");
    let own = dir.join("blob.hair");
    ok(&fur(&["export-groom", s(&own), "--model", "blob"]));
    let guides = curled_guides(&read_groom(&own).unwrap());
    let path = dir.join("curled.hair");
    fur_core::groom_file::write_groom(&path, &guides, "test").unwrap();
    let frame = dir.join("frame.usda");
    // The groom drawn as it is, small, validation on: the export and the renders below.
    let drawing = |command: &[&str], more: &[&str], out: &Path| {
        let mut args = command.to_vec();
        args.extend([
            "--groom",
            s(&path),
            "--groom-mode",
            "draw",
            "--segments",
            "8",
            "--width",
            "96",
            "--height",
            "54",
            "--validate",
            "--out",
            s(out),
        ]);
        args.extend_from_slice(more);
        ok(&fur(&args))
    };
    let out = drawing(
        &["export-frame", s(&frame)],
        &["--motion", "still"],
        &dir.join("frame.png"),
    );
    let drawn = read_groom(&frame).unwrap();
    assert_eq!(drawn.count(), guides.count(), "{out}");
    // Each drawn hair against the guide rooted nearest it.
    let mut matched = vec![false; guides.count()];
    for hair in drawn.curves() {
        let (g, guide) = guides
            .curves()
            .enumerate()
            .min_by(|a, b| {
                a.1[0]
                    .distance(hair[0])
                    .total_cmp(&b.1[0].distance(hair[0]))
            })
            .unwrap();
        assert!(!matched[g], "guide {g} drawn twice");
        matched[g] = true;
        let expected = fur_core::scene::resample(guide, 8);
        let shift = hair[0] - expected[0];
        let worst = hair
            .iter()
            .zip(&expected)
            .map(|(p, q)| p.distance(*q + shift))
            .fold(0.0, f32::max);
        assert!(
            worst <= 1e-5 * length(guide),
            "guide {g}: off by {worst} of a hair {} long",
            length(guide)
        );
        // The root moved onto the surface: the blob's own roots are on it already.
        assert!(shift.length() < 1e-5, "guide {g}'s root moved by {shift}");
    }
    // Both strand rasterisers draw the same hairs and segments of the drawn groom.
    let counts = |raster: &str| {
        let image = dir.join(format!("{raster}.png"));
        let out = drawing(&["render"], &["--raster", raster], &image);
        let at = out
            .find(" hairs drawn in ")
            .expect("the hairs drawn are reported");
        let hairs = out[..at].rsplit(' ').next().unwrap().to_string();
        let segments = out[at..].split(' ').nth(4).unwrap().to_string();
        (hairs, segments)
    };
    let (hardware, compute) = (counts("hardware"), counts("compute"));
    assert_eq!(
        hardware, compute,
        "hairs and segments, hardware against compute"
    );
    assert!(hardware.0.parse::<usize>().unwrap() > 0, "{hardware:?}");
}

/// On the walking critter the drawn guides are the master hairs the skin carries:
/// written at rest they are the groom read in (a round trip), and at a frame of the
/// walk their roots are where the blended groom's are (the same vertices, skinned),
/// one hair per guide, validation on.
#[test]
fn a_drawn_groom_walks_with_the_skin() {
    let dir = scratch("walk");
    let own = dir.join("critter.hair");
    ok(&fur(&["export-groom", s(&own), "--model", "critter"]));
    let guides = read_groom(&own).unwrap();
    let draw = ["--groom", s(&own), "--groom-mode", "draw"];
    let back = dir.join("back.usda");
    let mut args = vec!["export-groom", s(&back), "--model", "critter"];
    args.extend(draw);
    ok(&fur(&args));
    let again = read_groom(&back).unwrap();
    assert_eq!(again.counts, guides.counts);
    let longest = guides.curves().map(length).fold(0.0, f32::max);
    for (a, b) in guides.curves().zip(again.curves()) {
        let worst = a
            .iter()
            .zip(b)
            .map(|(p, q)| p.distance(*q))
            .fold(0.0, f32::max);
        assert!(
            worst <= 1e-5 * longest,
            "round trip off by {worst} (longest hair {longest})"
        );
    }
    // The seed's wind varies with the strand's index (eq. 7–8), which a guide's master
    // hair does not share with the vertex it came from: compared without wind.
    let walked = |name: &str, extra: &[&str]| -> Guides {
        let out = dir.join(name);
        let mut args = vec![
            "export-groom",
            s(&out),
            "--model",
            "critter",
            "--frames",
            "6",
            "--wind",
            "0,0,0",
            "--validate",
        ];
        args.extend(extra);
        ok(&fur(&args));
        read_groom(&out).unwrap()
    };
    let blended = walked("blended.usda", &["--groom", s(&own)]);
    let drawn = walked("drawn.usda", &draw);
    assert_eq!(drawn.counts, guides.counts);
    let (mut worst, mut same, mut all) = (0.0f32, 0, 0);
    for (a, b) in blended.curves().zip(drawn.curves()) {
        assert!(
            a[0].distance(b[0]) < 1e-5 * longest,
            "a drawn root is off the skinned surface: {} against {}",
            b[0],
            a[0]
        );
        for (p, q) in a.iter().zip(b) {
            worst = worst.max(p.distance(*q));
            same += usize::from(p.distance(*q) <= 1e-5 * longest);
            all += 1;
        }
    }
    println!(
        "after 6 frames of the walk: {same} of {all} vertices of the drawn guides within 1e-5 \
         of the blended groom's, the farthest {worst} (longest hair {longest})"
    );
    // The rest differ where collision does: the body's capsules are fitted to the skin's
    // vertices, which the guides' roots join.
    assert!(same * 100 >= all * 99 && worst <= 0.01 * longest);
    let mut args = vec![
        "render",
        "--model",
        "critter",
        "--width",
        "96",
        "--height",
        "54",
        "--validate",
        "--out",
    ];
    let frame = dir.join("frame.png");
    args.push(s(&frame));
    args.extend(draw);
    let out = ok(&fur(&args));
    assert_eq!(common::hairs_drawn(&out), guides.count() as u64, "{out}");
}

/// Draw mode without a groom file is refused by name, as is a mode that does not exist.
#[test]
fn draw_mode_needs_a_groom_file() {
    let out = fur(&[
        "render",
        "--groom-mode",
        "draw",
        "--width",
        "16",
        "--height",
        "16",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("give one (--groom FILE"),
        "{err}"
    );
    let out = fur(&["render", "--groom-mode", "paint"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("paint"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
