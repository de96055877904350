//! Hostile grooms end to end: a binary file built to abort or panic the decoder is one
//! line of error from `fur`, and every byte flip and truncation of a file Pixar's
//! usd-core wrote loads or is refused within the decoding's memory limit.

use std::process::Command;

use fur_core::groom_file::{read_groom, Guides};
use glam::Vec3;

use super::{common, fails, fur, s, scratch};

/// A binary USD whose points array claims 2⁴⁰ points (the decoder asks for 12 TiB
/// and aborts in-process) and one claiming 2⁶² (it panics): `fur` exits 1 with one
/// line naming the file, no panic message or backtrace before it.
#[test]
fn a_hostile_binary_groom_is_one_line_of_error() {
    let dir = scratch("hostile");
    let guides = Guides {
        counts: vec![37],
        points: (0..37)
            .map(|i| Vec3::new(1.5 + i as f32, -2.25, 3.125))
            .collect(),
        ..Guides::default()
    };
    let text = fur_core::groom_file::write_usda(&guides, "test").unwrap();
    let file = fur_core::groom_file::usdc_from_text(&text).unwrap();
    let mut needle = 37u64.to_le_bytes().to_vec();
    needle.extend_from_slice(&1.5f32.to_le_bytes());
    let at = file.windows(12).position(|w| w == needle).unwrap();
    for (count, says) in [
        (1u64 << 40, "asked for 12288 GiB"),
        (1 << 62, "failed on it"),
    ] {
        let mut hostile = file.clone();
        hostile[at..at + 8].copy_from_slice(&count.to_le_bytes());
        let path = dir.join(format!("claims-{count}.usdc"));
        std::fs::write(&path, &hostile).unwrap();
        let out = fur(&["export-groom", s(&dir.join("o.usda")), "--groom", s(&path)]);
        fails(&out, &[&format!("claims-{count}.usdc"), says]);
        assert_eq!(out.status.code(), Some(1));
        let err = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{err}");
        assert!(
            !err.contains("backtrace") && !err.contains("RUST_BACKTRACE"),
            "{err}"
        );
    }
}

/// Every single-byte flip and every truncation of a small binary USD written by Pixar's
/// usd-core loads or is refused in one line, its decoding within the stated memory
/// limit (observed: the decoding process's peak).
#[test]
fn every_flip_and_truncation_of_a_usd_core_file_loads_or_is_refused() {
    if fur_core::isolate::rerun_without_backtraces(
        "hostile::every_flip_and_truncation_of_a_usd_core_file_loads_or_is_refused",
    ) {
        return;
    }
    let Some(reference) = common::reference() else {
        return;
    };
    let dir = scratch("usd_core_sweep");
    let path = dir.join("small.usdc");
    let script = r#"
import sys
from pxr import Usd, UsdGeom, Vt
st = Usd.Stage.CreateNew(sys.argv[1])
cv = UsdGeom.BasisCurves.Define(st, '/Guides')
cv.CreateTypeAttr('linear')
cv.CreateCurveVertexCountsAttr(Vt.IntArray([3, 2]))
cv.CreatePointsAttr(Vt.Vec3fArray([(0, 0, 0), (0.1, 0.2, 0.3), (0.5, 0.25, 0), (-1, 0, 1), (-1, 1, 1)]))
cv.CreateWidthsAttr(Vt.FloatArray([0.01, 0.02, 0.03, 0.04, 0.05]))
st.GetRootLayer().Save()
"#;
    let run = Command::new(reference.python())
        .args(["-c", script])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let file = std::fs::read(&path).unwrap();
    let format = fur_core::groom_file::GroomFormat::Usdc;
    assert_eq!(read_groom(&path).unwrap().counts, vec![3, 2]);
    let (mut loaded, mut refused) = (0, 0);
    let mut read = |bytes: &[u8]| match fur_core::groom_file::parse_usd_measured(bytes, format) {
        Ok((_, peak)) => {
            let limit = fur_core::groom_file::usd_limits(bytes.len()).memory;
            assert!(peak <= limit, "peak {peak} over {limit}");
            loaded += 1;
        }
        Err(e) => {
            assert_eq!(e.lines().count(), 1, "{e}");
            refused += 1;
        }
    };
    for at in 0..file.len() {
        for flip in [0xff, 0x80] {
            let mut v = file.clone();
            v[at] ^= flip;
            read(&v);
        }
    }
    for len in 0..file.len() {
        read(&file[..len]);
    }
    assert!(
        loaded > 0 && refused > 0,
        "{loaded} loaded, {refused} refused"
    );
}
