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
