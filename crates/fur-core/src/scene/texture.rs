//! Colour textures for the fur: loading image files (PNG, JPEG, TGA), building their
//! mip chains in linear light, a procedural tabby coat, and a CPU sampler for tests.

use std::f32::consts::TAU;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::colour::{linear_to_srgb8, srgb8_to_linear, srgb_to_linear};
use crate::error::{Error, Result};

/// The image formats [`Texture::load`] reads, for messages.
const SUPPORTED: &str = "PNG, JPEG or TGA";

/// The most memory an image's decoder may allocate.
const MAX_DECODE_BYTES: u64 = 1 << 30;

/// An RGBA8 sRGB texture with its mip chain (level 0 first, each half the size, down to
/// 1×1). Rows run top to bottom, texels left to right, 4 bytes each; alpha is linear.
#[derive(Clone, PartialEq)]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    pub levels: Vec<Vec<u8>>,
}

impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Texture({}×{}, {} levels)",
            self.width,
            self.height,
            self.levels.len()
        )
    }
}

impl Texture {
    /// The largest width or height accepted.
    pub const MAX_SIDE: u32 = 8192;

    /// Loads an sRGB image file (PNG, JPEG or TGA; 8 or 16 bits, grey or colour, with
    /// or without alpha) and builds its mip chain. Only a regular file of at most
    /// [`crate::files::MAX_TEXTURE_BYTES`] is read; the size is read from the header
    /// first, so an image too large is refused before it is decoded. Errors name the
    /// file and say what is wrong with it.
    pub fn load(path: &Path) -> Result<Texture> {
        let bytes = crate::files::read_bounded(path, crate::files::MAX_TEXTURE_BYTES, "texture")
            .map_err(|message| Error::Texture {
                path: path.to_path_buf(),
                message,
            })?;
        Self::decode(&bytes, path)
    }

    /// Decodes an image held in memory (see [`Texture::load`]); `name` is the file (or
    /// the model and image) named in errors.
    pub fn decode(bytes: &[u8], name: &Path) -> Result<Texture> {
        let error = |message: String| Error::Texture {
            path: name.to_path_buf(),
            message,
        };
        let open = || {
            // The content names the format; the file name's extension is the fallback
            // (TGA has no signature).
            let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes));
            if let Ok(format) = image::ImageFormat::from_path(name) {
                reader.set_format(format);
            }
            let reader = reader
                .with_guessed_format()
                .map_err(|e| error(e.to_string()))?;
            match reader.format() {
                Some(format) if format.reading_enabled() => Ok(reader),
                Some(format) => Err(error(format!(
                    "{} images are not supported; use {SUPPORTED}",
                    format!("{format:?}").to_uppercase()
                ))),
                None => Err(error(format!(
                    "not an image in a supported format ({SUPPORTED})"
                ))),
            }
        };
        let unreadable = |e: image::ImageError| {
            error(format!(
                "not a readable image ({e}); supported formats: {SUPPORTED}"
            ))
        };
        let (width, height) = open()?.into_dimensions().map_err(unreadable)?;
        check_size(width, height).map_err(error)?;
        let mut reader = open()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(Self::MAX_SIDE);
        limits.max_image_height = Some(Self::MAX_SIDE);
        limits.max_alloc = Some(MAX_DECODE_BYTES);
        reader.limits(limits);
        let rgba = reader.decode().map_err(unreadable)?.into_rgba8();
        let (width, height) = rgba.dimensions();
        check_size(width, height).map_err(error)?;
        Ok(Self::with_mips(width, height, rgba.into_raw()))
    }

    /// A texture from `width × height` RGBA8 sRGB texels (rows top to bottom), with its
    /// mip chain built. Fails when a side is 0 or above [`Texture::MAX_SIDE`], or when
    /// `rgba` does not hold exactly 4 bytes per texel.
    pub fn from_rgba(width: u32, height: u32, rgba: Vec<u8>) -> Result<Texture> {
        check_size(width, height).map_err(|m| Error::Parameter(format!("texture: {m}")))?;
        let expected = 4 * u64::from(width) * u64::from(height);
        if rgba.len() as u64 != expected {
            return Err(Error::Parameter(format!(
                "texture: {width}×{height} RGBA8 texels take {expected} bytes, not {}",
                rgba.len()
            )));
        }
        Ok(Self::with_mips(width, height, rgba))
    }

    /// A procedural ginger tabby coat (no files needed): warm ginger with darker brown
    /// stripes of constant v, wavy and broken up by noise, a cream belly towards v = 1
    /// and a fine per-texel grain. Made for latitude-longitude UVs (a sphere or the
    /// blob): the stripes run around the body. It repeats seamlessly in u. Sides are
    /// clamped to 1..=[`Texture::MAX_SIDE`]; the same size gives the same texture.
    pub fn tabby(width: u32, height: u32) -> Texture {
        let (width, height) = (
            width.clamp(1, Self::MAX_SIDE),
            height.clamp(1, Self::MAX_SIDE),
        );
        let ginger = srgb_colour(0.87, 0.55, 0.26);
        let brown = srgb_colour(0.42, 0.22, 0.09);
        let cream = srgb_colour(0.96, 0.89, 0.76);
        const STRIPES: f32 = 11.0;
        let mut rgba = Vec::with_capacity(4 * width as usize * height as usize);
        for y in 0..height {
            let v = (y as f32 + 0.5) / height as f32;
            for x in 0..width {
                let u = (x as f32 + 0.5) / width as f32;
                let wobble = value_noise(u, v, 6, 4.0, 1);
                let phase = v * STRIPES + 0.25 * (TAU * 2.0 * u).sin() + 0.6 * (wobble - 0.5);
                let band = 0.5 + 0.5 * (TAU * phase).cos();
                let broken = smoothstep(0.25, 0.6, value_noise(u, v, 24, 16.0, 2));
                let belly = smoothstep(0.72, 0.92, v + 0.1 * (wobble - 0.5));
                let stripe = smoothstep(0.55, 0.8, band) * broken * (1.0 - belly);
                let grain = 0.93 + 0.14 * hash(x, y, 3);
                let colour = ginger.lerp(brown, 0.85 * stripe).lerp(cream, belly) * grain;
                rgba.extend(colour.to_array().map(linear_to_srgb8));
                rgba.push(255);
            }
        }
        Self::with_mips(width, height, rgba)
    }

    /// The size of mip `level`: each side halved per level, at least 1.
    pub fn level_size(&self, level: usize) -> (u32, u32) {
        let shift = u32::try_from(level).unwrap_or(u32::MAX);
        let side = |s: u32| s.checked_shr(shift).unwrap_or(0).max(1);
        (side(self.width), side(self.height))
    }

    /// The colour at `uv` (u right, v down; (0, 0) is the top-left corner): level 0,
    /// nearest texel, repeating outside [0, 1]. Returns LINEAR colour (sRGB decoded):
    /// the CPU twin of the renderer's sampler for tests.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let texel = |t: f32, size: u32| {
            ((t * size as f32).floor() as i64).rem_euclid(i64::from(size)) as usize
        };
        let (x, y) = (texel(uv.x, self.width), texel(uv.y, self.height));
        let i = 4 * (y * self.width as usize + x);
        match self.levels.first().and_then(|l| l.get(i..i + 3)) {
            Some(p) => Vec3::new(
                srgb8_to_linear(p[0]),
                srgb8_to_linear(p[1]),
                srgb8_to_linear(p[2]),
            ),
            None => Vec3::ZERO,
        }
    }

    /// Builds the mip chain over valid level-0 texels.
    fn with_mips(width: u32, height: u32, rgba: Vec<u8>) -> Texture {
        let mut levels = vec![rgba];
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let (next, nw, nh) =
                crate::colour::half_size(levels.last().map_or(&[][..], |l| l), w, h);
            levels.push(next);
            (w, h) = (nw, nh);
        }
        Texture {
            width,
            height,
            levels,
        }
    }
}

/// Why a `width × height` image cannot be a texture, if it cannot.
fn check_size(width: u32, height: u32) -> std::result::Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("the image is empty ({width}×{height} pixels)"));
    }
    let max = Texture::MAX_SIDE;
    if width > max || height > max {
        return Err(format!(
            "the image is {width}×{height} pixels, larger than the limit of {max} pixels on \
             a side; scale it down"
        ));
    }
    Ok(())
}

/// A linear colour from sRGB components in [0, 1].
fn srgb_colour(r: f32, g: f32, b: f32) -> Vec3 {
    Vec3::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A hash of a lattice point and a seed, in [0, 1).
fn hash(x: u32, y: u32, seed: u32) -> f32 {
    super::hash_unit(
        x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ seed.wrapping_mul(0xcb1a_b31f),
    )
}

/// Smooth value noise in [0, 1] at (u, v) on a lattice of `cells_u` cells across u
/// (wrapping, so it repeats seamlessly in u) and `cells_v` per unit of v.
fn value_noise(u: f32, v: f32, cells_u: u32, cells_v: f32, seed: u32) -> f32 {
    let (x, y) = (u * cells_u as f32, v * cells_v);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (smoothstep(0.0, 1.0, x - x0), smoothstep(0.0, 1.0, y - y0));
    let cell = |dx: i64, dy: i64| {
        let ix = (x0 as i64 + dx).rem_euclid(i64::from(cells_u)) as u32;
        let iy = (y0 as i64 + dy) as u32;
        hash(ix, iy, seed)
    };
    let top = cell(0, 0) + (cell(1, 0) - cell(0, 0)) * fx;
    let bottom = cell(0, 1) + (cell(1, 1) - cell(0, 1)) * fx;
    top + (bottom - top) * fy
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid(width: u32, height: u32, texel: [u8; 4]) -> Texture {
        Texture::from_rgba(width, height, texel.repeat((width * height) as usize)).unwrap()
    }

    #[test]
    fn the_mip_chain_halves_down_to_one_texel() {
        let t = solid(5, 3, [10, 20, 30, 255]);
        let sizes: Vec<_> = (0..t.levels.len()).map(|l| t.level_size(l)).collect();
        assert_eq!(sizes, [(5, 3), (2, 1), (1, 1)]);
        for (level, data) in t.levels.iter().enumerate() {
            let (w, h) = t.level_size(level);
            assert_eq!(data.len(), (4 * w * h) as usize);
        }
        assert_eq!(solid(1, 1, [0; 4]).levels.len(), 1);
        assert_eq!(solid(8, 1, [0; 4]).levels.len(), 4);
        assert_eq!(t.level_size(1000), (1, 1));
    }

    #[test]
    fn a_uniform_colour_stays_uniform_at_every_level() {
        let texel = [200, 37, 90, 128];
        let t = solid(13, 6, texel);
        for level in &t.levels {
            assert!(level.chunks_exact(4).all(|p| p == texel), "{level:?}");
        }
    }

    #[test]
    fn a_checker_averages_to_its_linear_light_mean() {
        let (a, b) = ([0u8, 0, 0, 255], [255u8, 255, 255, 255]);
        let (c, d) = ([220u8, 40, 10, 0], [30u8, 180, 250, 255]);
        let mean = |p: [u8; 4], q: [u8; 4], c: usize| {
            linear_to_srgb8(0.5 * (srgb8_to_linear(p[c]) + srgb8_to_linear(q[c])))
        };
        for (p, q) in [(a, b), (c, d)] {
            for side in [2u32, 4, 8] {
                let rgba: Vec<u8> = (0..side * side)
                    .flat_map(|i| if (i % side + i / side) % 2 == 0 { p } else { q })
                    .collect();
                let t = Texture::from_rgba(side, side, rgba).unwrap();
                let last = t.levels.last().unwrap();
                for c in 0..3 {
                    let expected = mean(p, q, c);
                    assert!(
                        last[c].abs_diff(expected) <= 1,
                        "{side}: {last:?} {expected}"
                    );
                }
                assert!(last[3].abs_diff(((u32::from(p[3]) + u32::from(q[3])) / 2) as u8) <= 1);
            }
        }
        // Mid-grey in linear light is far brighter than the byte average 128.
        let t = Texture::from_rgba(2, 1, [a, b].concat()).unwrap();
        assert_eq!(t.levels[1][0], 188);
    }

    #[test]
    fn bad_sizes_and_lengths_are_refused() {
        assert!(Texture::from_rgba(0, 4, Vec::new()).is_err());
        assert!(Texture::from_rgba(Texture::MAX_SIDE + 1, 1, vec![0; 4 * 8193]).is_err());
        let short = Texture::from_rgba(2, 2, vec![0; 15])
            .unwrap_err()
            .to_string();
        assert!(short.contains("16 bytes"), "{short}");
    }

    #[test]
    fn the_tabby_is_deterministic_and_striped_along_v() {
        let (w, h) = (64u32, 64u32);
        let t = Texture::tabby(w, h);
        assert_eq!(t, Texture::tabby(w, h));
        assert_eq!(t.levels[0].len(), (4 * w * h) as usize);
        let level = &t.levels[0];
        assert!(level.chunks_exact(4).any(|p| p != &level[..4]));
        // Stripes of constant v: rows differ from each other far more than columns do.
        let luma = |x: u32, y: u32| {
            let i = 4 * (y * w + x) as usize;
            level[i..i + 3].iter().map(|&c| f32::from(c)).sum::<f32>()
        };
        let variance = |means: Vec<f32>| {
            let m = means.iter().sum::<f32>() / means.len() as f32;
            means.iter().map(|x| (x - m) * (x - m)).sum::<f32>() / means.len() as f32
        };
        let rows = variance((0..h).map(|y| (0..w).map(|x| luma(x, y)).sum()).collect());
        let columns = variance((0..w).map(|x| (0..h).map(|y| luma(x, y)).sum()).collect());
        assert!(rows > 4.0 * columns, "rows {rows}, columns {columns}");
        // Repeats seamlessly in u: the first and last columns are alike.
        let edge: f32 = (0..h).map(|y| (luma(0, y) - luma(w - 1, y)).abs()).sum();
        let inner: f32 = (0..h).map(|y| (luma(0, y) - luma(w / 2, y)).abs()).sum();
        assert!(edge < inner, "edge {edge}, inner {inner}");
        assert_eq!(Texture::tabby(0, 0).level_size(0), (1, 1));
    }

    #[test]
    fn sampling_repeats_and_decodes_srgb() {
        let rgba = [
            [255, 0, 0, 255],
            [0, 255, 0, 255],
            [0, 0, 255, 255],
            [128, 128, 128, 255],
        ];
        let t = Texture::from_rgba(2, 2, rgba.concat()).unwrap();
        assert_eq!(t.sample(Vec2::new(0.25, 0.25)), Vec3::X);
        assert_eq!(t.sample(Vec2::new(0.75, 0.25)), Vec3::Y);
        assert_eq!(t.sample(Vec2::new(0.25, 0.75)), Vec3::Z);
        for (a, b) in [((0.25, 0.25), (1.25, -0.75)), ((0.75, 0.75), (-0.25, 2.75))] {
            assert_eq!(t.sample(Vec2::new(a.0, a.1)), t.sample(Vec2::new(b.0, b.1)));
        }
        let grey = t.sample(Vec2::new(0.75, 0.75)).x;
        assert!((grey - 0.2158).abs() < 1e-3, "{grey}");
        assert_eq!(t.sample(Vec2::NAN), Vec3::X);
    }
}
