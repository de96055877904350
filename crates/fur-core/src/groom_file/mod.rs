//! Groom files: guide curves an artist made elsewhere, read from USD (`.usda`,
//! `.usdc`, `.usdz`), Cem Yuksel's cyHair (`.hair`) and TressFX (`.tfx`), and master
//! hairs written back out as USD text or cyHair.
//!
//! Every reader is bounded: the file is read through [`crate::files::read_bounded`]
//! (at most [`MAX_GROOM_BYTES`]); fur's own readers (cyHair, TressFX) check every count
//! a header states against the bytes that are there before anything is allocated for
//! it, and USD, decoded by the `openusd` crate, is decoded in a child process under
//! stated limits ([`usd_limits`], [`crate::isolate`]), so that no file can abort,
//! overflow the stack of or panic the reading process. Every error names the file and
//! what is wrong with it, in one line.

mod cyhair;
mod tfx;
mod usd;
mod wire;

use std::path::Path;

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};

pub use cyhair::{parse_cyhair, write_cyhair};
pub use tfx::parse_tfx;
pub use usd::{
    check_nesting, decode_usd, parse_usd, parse_usd_measured, usd_limits, usdc_from_text,
    write_usda, write_usdc, CUBIC_SAMPLES, MAX_DEPTH, MAX_NOTES, MAX_PRIMS, MAX_TEXT_NESTING,
    USD_MEMORY_BASE, USD_MEMORY_PER_BYTE, USD_SECONDS_BASE, USD_SECONDS_PER_MIB,
    USD_WALL_SLACK_SECONDS,
};

/// The largest groom file read.
pub const MAX_GROOM_BYTES: u64 = 1 << 30;

/// The most vertices one guide curve may have after reading (a cubic curve is
/// evaluated to a polyline first).
pub const MAX_CURVE_VERTICES: usize = 1 << 16;

/// Guide curves: polylines, curve after curve, with their optional widths and colours.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Guides {
    /// Vertices of each curve (each at least 2).
    pub counts: Vec<u32>,
    /// Every curve's vertices, root first, curve after curve.
    pub points: Vec<Vec3>,
    /// Per vertex: the curve's width (diameter) there, when the file gives widths.
    pub widths: Option<Vec<f32>>,
    /// Per vertex: the curve's colour there (linear RGB), when the file gives colours.
    pub colors: Option<Vec<Vec3>>,
    /// What reading changed, said once each (a cubic basis evaluated to a polyline, a
    /// time sample taken for a default): the caller shows these to the user.
    pub notes: Vec<String>,
}

impl Guides {
    /// How many curves.
    pub fn count(&self) -> usize {
        self.counts.len()
    }

    /// Where each curve starts in `points`.
    pub fn starts(&self) -> Vec<usize> {
        let mut at = 0;
        self.counts
            .iter()
            .map(|&c| {
                let s = at;
                at += c as usize;
                s
            })
            .collect()
    }

    /// The vertices of every curve, in order.
    pub fn curves(&self) -> impl Iterator<Item = &[Vec3]> {
        let mut at = 0;
        self.counts.iter().map(move |&c| {
            let s = at;
            at += c as usize;
            &self.points[s..at]
        })
    }

    /// Moves every point by `m` (widths are scaled by its mean scale).
    pub fn transform(&mut self, m: Mat4) {
        for p in &mut self.points {
            *p = m.transform_point3(*p);
        }
        if let Some(widths) = &mut self.widths {
            let scale = m.to_scale_rotation_translation().0;
            let s = (scale.x * scale.y * scale.z).abs().cbrt();
            widths.iter_mut().for_each(|w| *w *= s);
        }
    }

    /// Appends `other`'s curves (their widths and colours where both have them; a
    /// side that lacks them drops them for all).
    pub fn append(&mut self, other: Guides) {
        let mine = self.points.len();
        self.widths = match (self.widths.take(), other.widths) {
            (Some(mut a), Some(b)) => {
                a.extend(b);
                Some(a)
            }
            (None, b) if mine == 0 => b,
            _ => None,
        };
        self.colors = match (self.colors.take(), other.colors) {
            (Some(mut a), Some(b)) => {
                a.extend(b);
                Some(a)
            }
            (None, b) if mine == 0 => b,
            _ => None,
        };
        self.counts.extend(other.counts);
        self.points.extend(other.points);
        for n in other.notes {
            if !self.notes.contains(&n) {
                self.notes.push(n);
            }
        }
    }

    /// Checks what every reader promises: at least one curve, each of 2 or more
    /// vertices, counts that add up, finite numbers, per-vertex arrays of the right
    /// length. The error says what is wrong (the caller names the file).
    pub fn validate(&self) -> std::result::Result<(), String> {
        if self.counts.is_empty() {
            return Err("it holds no curves".into());
        }
        if let Some(i) = self.counts.iter().position(|&c| c < 2) {
            return Err(format!(
                "curve {i} has {} vertex(es); a guide needs at least 2",
                self.counts[i]
            ));
        }
        let total: u64 = self.counts.iter().map(|&c| u64::from(c)).sum();
        if total != self.points.len() as u64 {
            return Err(format!(
                "its curves' vertex counts add up to {total} but it has {} points",
                self.points.len()
            ));
        }
        if let Some(i) = self.points.iter().position(|p| !p.is_finite()) {
            return Err(format!("point {i} is not a finite number"));
        }
        if let Some(w) = &self.widths {
            if w.len() != self.points.len() {
                return Err(format!(
                    "{} widths for {} points",
                    w.len(),
                    self.points.len()
                ));
            }
            if let Some(i) = w.iter().position(|w| !(w.is_finite() && *w >= 0.0)) {
                return Err(format!("width {i} is {}, not a finite width ≥ 0", w[i]));
            }
        }
        if let Some(c) = &self.colors {
            if c.len() != self.points.len() {
                return Err(format!(
                    "{} colours for {} points",
                    c.len(),
                    self.points.len()
                ));
            }
            if let Some(i) = c.iter().position(|c| !c.is_finite()) {
                return Err(format!("colour {i} is not a finite number"));
            }
        }
        Ok(())
    }
}

/// A groom file's encoding, from its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroomFormat {
    /// USD text.
    Usda,
    /// USD binary (the crate format).
    Usdc,
    /// USD zip package: its first layer.
    Usdz,
    /// Cem Yuksel's cyHair.
    CyHair,
    /// AMD TressFX.
    Tfx,
}

impl GroomFormat {
    /// The format `path`'s extension names; the error lists the ones fur knows.
    pub fn of(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        Ok(match ext.as_deref() {
            Some("usda") => Self::Usda,
            Some("usdc") => Self::Usdc,
            // `.usd` may hold either encoding: the reader looks at the bytes.
            Some("usd") => Self::Usdc,
            Some("usdz") => Self::Usdz,
            Some("hair") => Self::CyHair,
            Some("tfx") => Self::Tfx,
            _ => {
                return Err(groom_error(
                    path,
                    "unknown groom format (expected .usda, .usdc, .usd, .usdz, .hair or .tfx)",
                ))
            }
        })
    }
}

/// The little-endian u32 at byte `at` of `b` (callers check the length first).
fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// The little-endian f32 at byte `at` of `b`.
fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_bits(u32_at(b, at))
}

fn groom_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Groom {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Reads the guide curves of the groom file at `path` (its format from the extension).
pub fn read_groom(path: &Path) -> Result<Guides> {
    let format = GroomFormat::of(path)?;
    let bytes = crate::files::read_bounded(path, MAX_GROOM_BYTES, "groom")
        .map_err(|m| groom_error(path, m))?;
    let guides = match format {
        GroomFormat::CyHair => parse_cyhair(&bytes),
        GroomFormat::Tfx => parse_tfx(&bytes),
        GroomFormat::Usda | GroomFormat::Usdc | GroomFormat::Usdz => parse_usd(&bytes, format),
    }
    .map_err(|m| groom_error(path, m))?;
    guides.validate().map_err(|m| groom_error(path, m))?;
    Ok(guides)
}

/// Writes `guides` to `path` as USD text (`.usda`), binary USD (`.usdc`) or cyHair
/// (`.hair`), through
/// [`crate::files::write_output`]; `generator` names the program in the file.
pub fn write_groom(path: &Path, guides: &Guides, generator: &str) -> Result<()> {
    guides
        .validate()
        .map_err(|m| Error::Parameter(format!("the groom to write is not valid: {m}")))?;
    let bytes = match GroomFormat::of(path)? {
        GroomFormat::Usda => write_usda(guides, generator)
            .map_err(|m| Error::Parameter(format!("writing USD text: {m}")))?
            .into_bytes(),
        GroomFormat::CyHair => write_cyhair(guides, generator)
            .map_err(|m| Error::Parameter(format!("writing cyHair: {m}")))?,
        GroomFormat::Usdc => usd::groom_layer(guides, generator)
            .and_then(|layer| usd::write_usdc(&layer))
            .map_err(|m| Error::Parameter(format!("writing binary USD: {m}")))?,
        GroomFormat::Usdz => {
            return Err(Error::Parameter(format!(
                "{}: fur writes USD as text (.usda) or binary (.usdc); a .usdz package is \
                 read, not written (`usdzip OUT.usdz IN.usdc` makes one)",
                path.display()
            )))
        }
        GroomFormat::Tfx => {
            return Err(Error::Parameter(format!(
                "{}: TressFX files are read, not written; write .usda, .usdc or .hair",
                path.display()
            )))
        }
    };
    crate::files::write_output(path, &bytes, "groom")
}

#[cfg(test)]
mod tests;
