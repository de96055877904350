//! AMD TressFX's `.tfx` (the layout of GPUOpen-Effects/TressFX's
//! `TressFXTFXFileHeader`): a 160-byte little-endian header — version (f32), strand
//! count, vertices per strand (every strand has the same), then byte offsets of the
//! vertex positions (4 × f32 per vertex, the inverse mass in w), the strand and vertex
//! texture coordinates, the strand thickness and the vertex colours (4 × f32), an
//! offset of 0 meaning "absent", and 32 reserved words.

use glam::Vec3;

use super::{f32_at, u32_at, Guides};

const HEADER: usize = 160;

/// Reads a TressFX file's bytes. TressFX's strand thickness is a ratio of the
/// renderer's hair width, not a width: it is not read, so the guides carry no widths.
pub fn parse_tfx(b: &[u8]) -> Result<Guides, String> {
    if b.len() < HEADER {
        return Err(format!(
            "it is {} bytes, shorter than a TressFX header ({HEADER})",
            b.len()
        ));
    }
    let version = f32_at(b, 0);
    let strands = u32_at(b, 4) as u64;
    let per_strand = u32_at(b, 8) as u64;
    let positions_at = u32_at(b, 12) as u64;
    let colors_at = u32_at(b, 28) as u64;
    if !(version.is_finite() && version > 0.0) {
        return Err(format!(
            "its version field is {version}: not a TressFX file"
        ));
    }
    if strands == 0 {
        return Err("its header says it holds no strands".into());
    }
    if !(2..=super::MAX_CURVE_VERTICES as u64).contains(&per_strand) {
        return Err(format!(
            "its header says {per_strand} vertices per strand (2..={} read)",
            super::MAX_CURVE_VERTICES
        ));
    }
    let vertices = strands * per_strand;
    let check = |name: &str, at: u64, bytes: u64| -> Result<(), String> {
        if at < HEADER as u64 || at + bytes > b.len() as u64 {
            return Err(format!(
                "its {name} ({bytes} bytes at offset {at}, for {strands} strands of \
                 {per_strand} vertices) lie outside the file's {} bytes",
                b.len()
            ));
        }
        Ok(())
    };
    check("positions", positions_at, vertices * 16)?;
    if colors_at != 0 {
        check("colours", colors_at, vertices * 16)?;
    }
    let read = |at: u64| -> Vec<Vec3> {
        (0..vertices as usize)
            .map(|i| {
                let o = at as usize + 16 * i;
                Vec3::new(f32_at(b, o), f32_at(b, o + 4), f32_at(b, o + 8))
            })
            .collect()
    };
    Ok(Guides {
        counts: vec![per_strand as u32; strands as usize],
        points: read(positions_at),
        widths: None,
        colors: (colors_at != 0).then(|| read(colors_at)),
        notes: Vec::new(),
    })
}
