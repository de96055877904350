//! Cem Yuksel's cyHair format (`.hair`, the format of his public hair models): a
//! 128-byte header, then the arrays its flags name, in this order: segments per hair
//! (u16), points (3 × f32), thickness (f32), transparency (f32), colour (3 × f32);
//! little-endian. A hair without its own segment count has the header's default, and
//! without a thickness array every point has the header's default thickness (none
//! when that is 0); the header's default colour is not taken for a file without a
//! colour array.

use glam::Vec3;

use super::{f32_at, u32_at, Guides};

const HEADER: usize = 128;
const SEGMENTS: u32 = 1;
const POINTS: u32 = 2;
const THICKNESS: u32 = 4;
const TRANSPARENCY: u32 = 8;
const COLORS: u32 = 16;
const INFO: usize = 88;

/// Reads a cyHair file's bytes.
pub fn parse_cyhair(b: &[u8]) -> Result<Guides, String> {
    if b.len() < HEADER {
        return Err(format!(
            "it is {} bytes, shorter than a cyHair header ({HEADER})",
            b.len()
        ));
    }
    if &b[0..4] != b"HAIR" {
        return Err("it does not start with `HAIR`: not a cyHair file".into());
    }
    let hairs = u32_at(b, 4) as u64;
    let points = u32_at(b, 8) as u64;
    let arrays = u32_at(b, 12);
    let default_segments = u32_at(b, 16);
    let default_thickness = f32_at(b, 20);
    if hairs == 0 {
        return Err("its header says it holds no hairs".into());
    }
    if arrays & POINTS == 0 {
        return Err("it has no points array (flag 2 unset)".into());
    }
    let sizes = [
        (SEGMENTS, hairs * 2),
        (POINTS, points * 12),
        (THICKNESS, points * 4),
        (TRANSPARENCY, points * 4),
        (COLORS, points * 12),
    ];
    let needed: u64 = HEADER as u64
        + sizes
            .iter()
            .filter(|(flag, _)| arrays & flag != 0)
            .map(|(_, n)| n)
            .sum::<u64>();
    if needed > b.len() as u64 {
        return Err(format!(
            "its header promises {hairs} hairs and {points} points ({needed} bytes with its \
             arrays) but the file has {} bytes",
            b.len()
        ));
    }
    // Every hair has at least 2 points, and the points are there (checked above):
    // the hairs are bounded by the file's bytes before one count is allocated.
    if hairs > points / 2 {
        return Err(format!(
            "its header promises {hairs} hairs but only {points} points (each hair has 2 or more)"
        ));
    }
    let mut at = HEADER;
    let counts: Vec<u32> = if arrays & SEGMENTS != 0 {
        let c = (0..hairs as usize)
            .map(|i| u32::from(u16::from_le_bytes([b[at + 2 * i], b[at + 2 * i + 1]])) + 1)
            .collect();
        at += hairs as usize * 2;
        c
    } else {
        if default_segments == 0 || default_segments >= u32::from(u16::MAX) {
            return Err(format!(
                "it has no segments array and its default segment count is {default_segments}"
            ));
        }
        if (u64::from(default_segments) + 1) * hairs != points {
            return Err(format!(
                "it has no segments array, and {hairs} hairs of its default {default_segments} \
                 segments are not its {points} points"
            ));
        }
        vec![default_segments + 1; hairs as usize]
    };
    let total: u64 = counts.iter().map(|&c| u64::from(c)).sum();
    if total != points {
        return Err(format!(
            "its hairs' segments add up to {total} points but its header says {points}"
        ));
    }
    let n = points as usize;
    let read_vec3 = |at: usize| -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let o = at + 12 * i;
                Vec3::new(f32_at(b, o), f32_at(b, o + 4), f32_at(b, o + 8))
            })
            .collect()
    };
    let positions = read_vec3(at);
    at += n * 12;
    let widths = if arrays & THICKNESS != 0 {
        let w = (0..n).map(|i| f32_at(b, at + 4 * i)).collect();
        at += n * 4;
        Some(w)
    } else {
        (default_thickness > 0.0).then(|| vec![default_thickness; n])
    };
    if arrays & TRANSPARENCY != 0 {
        at += n * 4;
    }
    let colors = (arrays & COLORS != 0).then(|| read_vec3(at));
    let mut notes = Vec::new();
    if arrays & TRANSPARENCY != 0 {
        notes.push("the cyHair transparency array is not used".to_string());
    }
    Ok(Guides {
        counts,
        points: positions,
        widths,
        colors,
        notes,
    })
}

/// `guides` as cyHair bytes: segments, points, and thickness and colour when the
/// guides have them; `info` goes into the header's text (cut to 87 bytes).
pub fn write_cyhair(guides: &Guides, info: &str) -> Result<Vec<u8>, String> {
    if let Some(i) = guides.counts.iter().position(|&c| c > u32::from(u16::MAX)) {
        return Err(format!(
            "curve {i} has {} vertices; cyHair holds at most {}",
            guides.counts[i],
            u16::MAX
        ));
    }
    let hairs = u32::try_from(guides.count()).map_err(|_| "too many curves for cyHair")?;
    let points = u32::try_from(guides.points.len()).map_err(|_| "too many points for cyHair")?;
    let mut arrays = SEGMENTS | POINTS;
    if guides.widths.is_some() {
        arrays |= THICKNESS;
    }
    if guides.colors.is_some() {
        arrays |= COLORS;
    }
    let mut out = Vec::with_capacity(HEADER + guides.points.len() * 28);
    out.extend_from_slice(b"HAIR");
    for v in [hairs, points, arrays, 0] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    // Default thickness 0 (none), transparency 0, colour white: a reader takes the
    // arrays, not these, for every hair.
    for v in [0.0f32, 0.0, 1.0, 1.0, 1.0] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    let mut text = [0u8; INFO];
    let info = info.as_bytes();
    let n = info.len().min(INFO - 1);
    text[..n].copy_from_slice(&info[..n]);
    out.extend_from_slice(&text);
    debug_assert_eq!(out.len(), HEADER);
    for &c in &guides.counts {
        out.extend_from_slice(&((c - 1) as u16).to_le_bytes());
    }
    let vec3s = |out: &mut Vec<u8>, v: &[Vec3]| {
        for p in v {
            for x in p.to_array() {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
    };
    vec3s(&mut out, &guides.points);
    if let Some(w) = &guides.widths {
        for x in w {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    if let Some(c) = &guides.colors {
        vec3s(&mut out, c);
    }
    Ok(out)
}
