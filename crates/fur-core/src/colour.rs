//! sRGB ↔ linear light, the one place fur converts colours: texture bytes to the values
//! the shaders light, images averaged in linear light (the supersampled reference, the
//! texture's mip levels), and the generated textures' bytes.

use std::sync::OnceLock;

/// An sRGB-encoded value in [0, 1] to linear light (the sRGB transfer function).
pub fn srgb_to_linear(s: f32) -> f32 {
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// sRGB-encoded byte → linear light, for all 256 bytes (for loops over many pixels:
/// take the table once, index it per sample).
pub fn srgb8_lut() -> &'static [f32; 256] {
    static LUT: OnceLock<[f32; 256]> = OnceLock::new();
    LUT.get_or_init(|| std::array::from_fn(|c| srgb_to_linear(c as f32 / 255.0)))
}

/// An sRGB-encoded byte to linear light.
pub fn srgb8_to_linear(byte: u8) -> f32 {
    srgb8_lut()[byte as usize]
}

/// Linear light to an sRGB-encoded byte: clamped to [0, 1] (NaN as 0), rounded.
pub fn linear_to_srgb8(l: f32) -> u8 {
    let l = if l.is_nan() { 0.0 } else { l.clamp(0.0, 1.0) };
    let s = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The next mip level of a `width × height` RGBA8 sRGB image: half its size (at least
/// 1), by [`resample`].
pub fn half_size(src: &[u8], width: u32, height: u32) -> (Vec<u8>, u32, u32) {
    let to = Size {
        width: (width / 2).max(1),
        height: (height / 2).max(1),
    };
    (
        resample(src, Size { width, height }, to),
        to.width,
        to.height,
    )
}

/// An image's width and height, pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

/// A size written as `(width, height)`.
impl From<(u32, u32)> for Size {
    fn from(pair: (u32, u32)) -> Self {
        Size {
            width: pair.0,
            height: pair.1,
        }
    }
}

/// An RGBA8 sRGB image of size `from` at size `to` (not larger): a box filter in
/// linear light over the source pixels each new pixel covers, weighted by their
/// overlap (for a side divided exactly, the plain average of each block; otherwise the
/// boundary pixels are shared, so none is dropped). Alpha is averaged as stored.
pub fn resample(src: &[u8], from: Size, to: Size) -> Vec<u8> {
    let (width, height, dw, dh) = (from.width, from.height, to.width, to.height);
    let (xs, ys) = (box_taps(width, dw), box_taps(height, dh));
    let lut = srgb8_lut();
    let mut out = Vec::with_capacity(4 * dw as usize * dh as usize);
    let mut row = vec![[0.0f32; 4]; dw as usize];
    for y_taps in &ys {
        row.iter_mut().for_each(|t| *t = [0.0; 4]);
        for &(sy, wy) in y_taps {
            let start = 4 * sy * width as usize;
            let Some(src_row) = src.get(start..start + 4 * width as usize) else {
                continue;
            };
            for (acc, x_taps) in row.iter_mut().zip(&xs) {
                for &(sx, wx) in x_taps {
                    let p = &src_row[4 * sx..4 * sx + 4];
                    let w = wy * wx;
                    for c in 0..3 {
                        acc[c] += w * lut[p[c] as usize];
                    }
                    acc[3] += w * f32::from(p[3]);
                }
            }
        }
        for acc in &row {
            out.extend([acc[0], acc[1], acc[2]].map(linear_to_srgb8));
            out.push(acc[3].round().clamp(0.0, 255.0) as u8);
        }
    }
    out
}

/// For each of `dst` texels along a side of `src`, the source texels it covers and
/// their weights (summing to 1).
fn box_taps(src: u32, dst: u32) -> Vec<Vec<(usize, f32)>> {
    let scale = f64::from(src) / f64::from(dst);
    (0..dst)
        .map(|i| {
            let (lo, hi) = (f64::from(i) * scale, f64::from(i + 1) * scale);
            (lo.floor() as usize..(hi.ceil() as usize).min(src as usize))
                .filter_map(|k| {
                    let overlap = hi.min(k as f64 + 1.0) - lo.max(k as f64);
                    (overlap > 1e-9).then_some((k, (overlap / scale) as f32))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_byte_survives_a_round_trip_through_linear_light() {
        for byte in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb8_to_linear(byte)), byte);
        }
    }

    #[test]
    fn the_transfer_function_at_known_points() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // Mid-grey: sRGB 0.5 is 21.4 % linear light; the linear part below 0.04045.
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        assert!((srgb_to_linear(0.04) - 0.04 / 12.92).abs() < 1e-9);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(2.0), 255);
        assert_eq!(linear_to_srgb8(0.2), 124); // 255 × (1.055 · 0.2^(1/2.4) − 0.055) = 123.55
    }
}
