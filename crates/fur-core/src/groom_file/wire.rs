//! Guides as bytes, for the reply of the process that decoded them
//! ([`crate::isolate`]): a header of counts, then the arrays, little-endian. The
//! decoder checks every length against the bytes there before it allocates.

use glam::Vec3;

use super::{f32_at, u32_at, Guides};

const MAGIC: &[u8; 4] = b"FURG";
const HEADER: usize = 4 + 8 + 8 + 4 + 4;
const WIDTHS: u32 = 1;
const COLOURS: u32 = 2;

/// `guides` as bytes.
pub fn encode(guides: &Guides) -> Vec<u8> {
    let n = guides.points.len();
    let mut out = Vec::with_capacity(HEADER + 4 * guides.counts.len() + 28 * n);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&(guides.counts.len() as u64).to_le_bytes());
    out.extend_from_slice(&(n as u64).to_le_bytes());
    let flags = if guides.widths.is_some() { WIDTHS } else { 0 }
        | if guides.colors.is_some() { COLOURS } else { 0 };
    out.extend_from_slice(&flags.to_le_bytes());
    out.extend_from_slice(&(guides.notes.len() as u32).to_le_bytes());
    for &c in &guides.counts {
        out.extend_from_slice(&c.to_le_bytes());
    }
    let floats = |out: &mut Vec<u8>, v: &mut dyn Iterator<Item = f32>| {
        for x in v {
            out.extend_from_slice(&x.to_le_bytes());
        }
    };
    floats(
        &mut out,
        &mut guides.points.iter().flat_map(|p| p.to_array()),
    );
    if let Some(w) = &guides.widths {
        floats(&mut out, &mut w.iter().copied());
    }
    if let Some(c) = &guides.colors {
        floats(&mut out, &mut c.iter().flat_map(|p| p.to_array()));
    }
    for note in &guides.notes {
        out.extend_from_slice(&(note.len() as u32).to_le_bytes());
        out.extend_from_slice(note.as_bytes());
    }
    out
}

/// The guides [`encode`] wrote.
pub fn decode(b: &[u8]) -> Result<Guides, String> {
    let bad = || "the decoding process's reply is malformed".to_string();
    if b.len() < HEADER || &b[..4] != MAGIC {
        return Err(bad());
    }
    let u64_at = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().unwrap_or([0; 8]));
    let (curves, n, flags, notes) = (u64_at(4), u64_at(12), u32_at(b, 20), u32_at(b, 24));
    let per_point = 12 + 4 * u64::from(flags & WIDTHS) + 6 * u64::from(flags & COLOURS);
    let arrays = curves
        .checked_mul(4)
        .zip(n.checked_mul(per_point))
        .and_then(|(a, p)| a.checked_add(p))
        .filter(|&need| need <= (b.len() - HEADER) as u64)
        .ok_or_else(bad)?;
    let (curves, n) = (curves as usize, n as usize);
    let mut at = HEADER;
    let counts = (0..curves).map(|i| u32_at(b, at + 4 * i)).collect();
    at += 4 * curves;
    let vec3s = |at: usize| -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let o = at + 12 * i;
                Vec3::new(f32_at(b, o), f32_at(b, o + 4), f32_at(b, o + 8))
            })
            .collect()
    };
    let points = vec3s(at);
    at += 12 * n;
    let widths = (flags & WIDTHS != 0).then(|| {
        let w = (0..n).map(|i| f32_at(b, at + 4 * i)).collect();
        at += 4 * n;
        w
    });
    let colors = (flags & COLOURS != 0).then(|| vec3s(at));
    at = HEADER + arrays as usize;
    let mut texts = Vec::new();
    for _ in 0..notes {
        let len = b
            .get(at..at + 4)
            .map(|_| u32_at(b, at) as usize)
            .ok_or_else(bad)?;
        let text = b.get(at + 4..at + 4 + len).ok_or_else(bad)?;
        texts.push(String::from_utf8_lossy(text).into_owned());
        at += 4 + len;
    }
    if at != b.len() {
        return Err(bad());
    }
    Ok(Guides {
        counts,
        points,
        widths,
        colors,
        notes: texts,
    })
}
