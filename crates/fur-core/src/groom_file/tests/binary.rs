//! cyHair and TressFX, read as laid out by hand and refused when malformed.

use glam::Vec3;

use super::super::*;

fn le32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn lef(out: &mut Vec<u8>, v: f32) {
    out.extend_from_slice(&v.to_le_bytes());
}

/// Two hairs of 2 and 1 segments, laid out by hand from the format's description
/// (not by fur's writer): header, segments, points, thickness, colours.
fn cyhair_by_hand() -> Vec<u8> {
    let mut b = b"HAIR".to_vec();
    le32(&mut b, 2); // hairs
    le32(&mut b, 5); // points
    le32(&mut b, 1 | 2 | 4 | 16); // segments, points, thickness, colours
    le32(&mut b, 7); // default segments (unused: the array is there)
    for v in [0.5, 0.0, 0.1, 0.2, 0.3] {
        lef(&mut b, v);
    }
    b.resize(128, 0);
    b.extend_from_slice(&2u16.to_le_bytes());
    b.extend_from_slice(&1u16.to_le_bytes());
    for i in 0..5 {
        for v in [i as f32, 2.0 * i as f32, -1.0] {
            lef(&mut b, v);
        }
    }
    for i in 0..5 {
        lef(&mut b, 0.01 * (i + 1) as f32);
    }
    for i in 0..5 {
        for v in [0.1 * i as f32, 0.5, 1.0] {
            lef(&mut b, v);
        }
    }
    b
}

#[test]
fn cyhair_is_read_as_laid_out_and_written_back_the_same() {
    let g = parse_cyhair(&cyhair_by_hand()).unwrap();
    assert_eq!(g.counts, vec![3, 2]);
    assert_eq!(g.points[4], Vec3::new(4.0, 8.0, -1.0));
    assert!(g.notes.is_empty(), "no transparency array: {:?}", g.notes);
    assert_eq!(g.widths.as_ref().unwrap()[2], 0.03);
    assert_eq!(
        g.colors.as_ref().unwrap()[3],
        Vec3::new(0.1 * 3.0, 0.5, 1.0)
    );
    g.validate().unwrap();
    let written = write_cyhair(&g, "test").unwrap();
    assert_eq!(parse_cyhair(&written).unwrap(), g);
    // The same bytes as the hand layout, apart from the header's defaults and text.
    assert_eq!(written[128..], cyhair_by_hand()[128..]);
}

/// Three hairs of 300, 1 and 2 segments (a count with a high byte, an odd number of
/// hairs), the header's default thickness instead of an array, and a transparency
/// array before the colours, laid out by hand.
#[test]
fn cyhair_segments_transparency_and_default_thickness_are_read_as_laid_out() {
    let segments = [300u16, 1, 2];
    let points: u32 = segments.iter().map(|&s| u32::from(s) + 1).sum();
    let mut b = b"HAIR".to_vec();
    le32(&mut b, 3);
    le32(&mut b, points);
    le32(&mut b, 1 | 2 | 8 | 16); // segments, points, transparency, colours
    le32(&mut b, 7);
    lef(&mut b, 0.25); // default thickness
    b.resize(128, 0);
    for s in segments {
        b.extend_from_slice(&s.to_le_bytes());
    }
    for i in 0..points {
        for v in [i as f32, 1.0, 2.0] {
            lef(&mut b, v);
        }
    }
    for _ in 0..points {
        lef(&mut b, 0.5); // transparency, skipped
    }
    for i in 0..points {
        for v in [0.001 * i as f32, 0.25, 0.75] {
            lef(&mut b, v);
        }
    }
    let g = parse_cyhair(&b).unwrap();
    assert_eq!(g.counts, vec![301, 2, 3]);
    assert_eq!(g.points[305], Vec3::new(305.0, 1.0, 2.0));
    assert_eq!(g.widths, Some(vec![0.25; points as usize]));
    assert_eq!(
        g.colors.as_ref().unwrap()[305],
        Vec3::new(0.305, 0.25, 0.75)
    );
    assert_eq!(g.notes.len(), 1, "{:?}", g.notes);
    // One byte short of the arrays is refused.
    assert!(parse_cyhair(&b[..b.len() - 1]).is_err());
}

#[test]
fn cyhair_without_segments_takes_the_default_and_without_thickness_has_no_widths() {
    let mut b = b"HAIR".to_vec();
    for v in [2, 6, 2, 2] {
        le32(&mut b, v);
    }
    b.resize(128, 0);
    for i in 0..18 {
        lef(&mut b, i as f32);
    }
    let g = parse_cyhair(&b).unwrap();
    assert_eq!(g.counts, vec![3, 3]);
    assert_eq!(g.widths, None);
    assert_eq!(g.colors, None);
}

#[test]
fn bad_cyhair_files_are_refused_before_allocating() {
    let good = cyhair_by_hand();
    let err = |b: &[u8]| parse_cyhair(b).unwrap_err();
    assert!(err(&good[..100]).contains("shorter than a cyHair header"));
    assert!(err(&good[..good.len() - 1]).contains("the file has"));
    let mut bad = good.clone();
    bad[0] = b'X';
    assert!(err(&bad).contains("HAIR"));
    // A header promising four billion hairs in a small file: refused from the sizes.
    let mut huge = good.clone();
    huge[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    huge[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(err(&huge).contains("promises"));
    let mut sums = good.clone();
    sums[8..12].copy_from_slice(&4u32.to_le_bytes());
    assert!(err(&sums).contains("add up to 5"));
    let mut none = good.clone();
    none[12..16].copy_from_slice(&1u32.to_le_bytes());
    assert!(err(&none).contains("no points array"));
    // No segments array: the header's default count must be 1..65534.
    for default in [0u32, 65_535] {
        let mut b = good.clone();
        b[12..16].copy_from_slice(&2u32.to_le_bytes());
        b[16..20].copy_from_slice(&default.to_le_bytes());
        assert!(
            err(&b).contains("default segment count"),
            "default {default}"
        );
    }
}

/// Two strands of 4 vertices, laid out as TressFX's header describes.
pub(super) fn tfx_by_hand(colours: bool) -> Vec<u8> {
    let mut b = Vec::new();
    lef(&mut b, 4.0);
    le32(&mut b, 2);
    le32(&mut b, 4);
    le32(&mut b, 160); // positions
    le32(&mut b, 0);
    le32(&mut b, 0);
    le32(&mut b, 0);
    le32(&mut b, if colours { 160 + 8 * 16 } else { 0 });
    b.resize(160, 0);
    for i in 0..8 {
        let inverse_mass = if i % 4 == 0 { 0.0 } else { 1.0 };
        for v in [i as f32, 0.5, -(i as f32), inverse_mass] {
            lef(&mut b, v);
        }
    }
    if colours {
        for i in 0..8 {
            for v in [0.25, i as f32 / 8.0, 0.75, 1.0] {
                lef(&mut b, v);
            }
        }
    }
    b
}

#[test]
fn tfx_is_read_as_laid_out() {
    let g = parse_tfx(&tfx_by_hand(true)).unwrap();
    assert_eq!(g.counts, vec![4, 4]);
    assert_eq!(g.points[5], Vec3::new(5.0, 0.5, -5.0));
    assert_eq!(g.colors.as_ref().unwrap()[4], Vec3::new(0.25, 0.5, 0.75));
    assert_eq!(g.widths, None);
    assert_eq!(parse_tfx(&tfx_by_hand(false)).unwrap().colors, None);
}

#[test]
fn bad_tfx_files_are_refused_before_allocating() {
    let good = tfx_by_hand(true);
    let err = |b: &[u8]| parse_tfx(b).unwrap_err();
    assert!(err(&good[..150]).contains("shorter"));
    assert!(err(&good[..good.len() - 4]).contains("colours"));
    let mut huge = good.clone();
    huge[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(err(&huge).contains("positions"));
    let mut one = good.clone();
    one[8..12].copy_from_slice(&1u32.to_le_bytes());
    assert!(err(&one).contains("vertices per strand"));
    for bad in [f32::NAN, f32::INFINITY, 0.0, -1.0] {
        let mut version = good.clone();
        version[0..4].copy_from_slice(&bad.to_le_bytes());
        assert!(err(&version).contains("version"), "version {bad}");
    }
    // Positions cut short by a vertex (no colours): 8 × 16 bytes are needed, 7 × 16
    // are there; ending exactly at the file's end is whole.
    let plain = tfx_by_hand(false);
    assert!(err(&plain[..plain.len() - 16]).contains("positions"));
    assert_eq!(parse_tfx(&plain).unwrap().points.len(), 8);
    // Positions that start inside the header.
    let mut early = plain;
    early[12..16].copy_from_slice(&159u32.to_le_bytes());
    assert!(err(&early).contains("positions"));
}
