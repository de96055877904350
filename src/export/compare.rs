//! Comparing fur's drawing of a frame with the path-traced reference: the calibration
//! of conventions (where things are, how bright a lit surface is) and the error
//! measures against the truth (ꟻLIP on sRGB, RMSE in linear light).

use glam::Vec3;

use super::reference::LinearImage;
use fur_core::colour::{linear_to_srgb8, srgb8_to_linear};
use fur_core::render::RgbaImage;
use fur_gpu::error::{Error, Result};
use fur_gpu::render::BACKGROUND;

/// How far a pixel's linear colour must be from the background (summed over the
/// channels) to count as covered.
const COVERED: f32 = 0.01;

/// Whether a pixel of linear colour `p` shows something other than the background.
pub fn covered(p: Vec3) -> bool {
    (p - BACKGROUND).abs().element_sum() > COVERED
}

/// What the calibration measures between fur's image and the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    /// Pixels covered in one image and not the other.
    pub mismatched: usize,
    /// Pixels on the edge of fur's coverage (covered, with an uncovered neighbour).
    pub edge: usize,
    /// Pixels covered in fur's image.
    pub covered: usize,
    /// Distance between the two coverages' centroids, in pixels.
    pub shift_px: f64,
    /// Mean linear radiance of fur over the reference's, over the pixels both cover.
    pub ratio: f64,
}

impl Calibration {
    /// The largest centroid shift that passes, in pixels.
    pub const MAX_SHIFT_PX: f64 = 0.5;
    /// The largest difference of mean radiance that passes (2 %).
    pub const MAX_RATIO_ERROR: f64 = 0.02;

    /// Measures `fur` (8-bit sRGB) against `reference` (linear).
    pub fn measure(fur: &RgbaImage, reference: &LinearImage) -> Result<Self> {
        let fur = linear(fur);
        check_size(&fur, reference)?;
        let (w, h) = (reference.width as usize, reference.height as usize);
        let mask = |img: &[Vec3]| -> Vec<bool> { img.iter().map(|p| covered(*p)).collect() };
        let (a, b) = (mask(&fur), mask(&reference.pixels));
        let mismatched = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        let edge = (0..w * h)
            .filter(|&i| {
                let (x, y) = (i % w, i / w);
                a[i] && [(0i64, 1i64), (0, -1), (1, 0), (-1, 0)]
                    .iter()
                    .any(|(dx, dy)| {
                        let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                        nx < 0
                            || ny < 0
                            || nx >= w as i64
                            || ny >= h as i64
                            || !a[ny as usize * w + nx as usize]
                    })
            })
            .count();
        let centroid = |m: &[bool]| {
            let (mut sx, mut sy, mut n) = (0.0f64, 0.0f64, 0.0f64);
            for (i, _) in m.iter().enumerate().filter(|(_, c)| **c) {
                sx += (i % w) as f64;
                sy += (i / w) as f64;
                n += 1.0;
            }
            (sx / n.max(1.0), sy / n.max(1.0))
        };
        let (ca, cb) = (centroid(&a), centroid(&b));
        let shift_px = ((ca.0 - cb.0).powi(2) + (ca.1 - cb.1).powi(2)).sqrt();
        let (mut sum_fur, mut sum_ref) = (0.0f64, 0.0f64);
        for i in (0..w * h).filter(|&i| a[i] && b[i]) {
            sum_fur += f64::from(fur[i].element_sum());
            sum_ref += f64::from(reference.pixels[i].element_sum());
        }
        Ok(Self {
            mismatched,
            edge,
            covered: a.iter().filter(|c| **c).count(),
            shift_px,
            ratio: sum_fur / sum_ref.max(1e-12),
        })
    }

    /// Passes when the coverages agree up to half their edge, their centroids within
    /// half a pixel and the mean radiance within 2 %; the error names what failed.
    pub fn check(&self) -> std::result::Result<(), String> {
        let mut failed = Vec::new();
        if self.covered == 0 {
            failed.push("fur's image covers nothing".to_string());
        }
        if 2 * self.mismatched > self.edge {
            failed.push(format!(
                "{} pixels covered by one image only, more than half of the {} edge pixels",
                self.mismatched, self.edge
            ));
        }
        if self.shift_px > Self::MAX_SHIFT_PX {
            failed.push(format!(
                "the coverages' centroids are {:.2} px apart (at most {})",
                self.shift_px,
                Self::MAX_SHIFT_PX
            ));
        }
        if (self.ratio - 1.0).abs() > Self::MAX_RATIO_ERROR {
            failed.push(format!(
                "mean radiance fur/reference {:.4} (within {} %)",
                self.ratio,
                Self::MAX_RATIO_ERROR * 100.0
            ));
        }
        if failed.is_empty() {
            Ok(())
        } else {
            Err(failed.join("; "))
        }
    }
}

/// fur's 8-bit sRGB image as linear values.
pub fn linear(image: &RgbaImage) -> Vec<Vec3> {
    image
        .data
        .chunks_exact(4)
        .map(|p| {
            Vec3::new(
                srgb8_to_linear(p[0]),
                srgb8_to_linear(p[1]),
                srgb8_to_linear(p[2]),
            )
        })
        .collect()
}

/// The reference encoded as fur encodes its images (8-bit sRGB, opaque).
pub fn to_srgb8(reference: &LinearImage) -> RgbaImage {
    let data = reference
        .pixels
        .iter()
        .flat_map(|p| {
            [
                linear_to_srgb8(p.x),
                linear_to_srgb8(p.y),
                linear_to_srgb8(p.z),
                255,
            ]
        })
        .collect();
    RgbaImage {
        width: reference.width,
        height: reference.height,
        data,
    }
}

/// ꟻLIP (on sRGB, as both are shown) and RMSE (linear light) of `fur` against the
/// reference.
pub fn errors(fur: &RgbaImage, reference: &LinearImage) -> Result<(f64, f64)> {
    let lin = linear(fur);
    check_size(&lin, reference)?;
    let flip = fur_core::render::flip(&to_srgb8(reference), fur);
    let sum: f64 = lin
        .iter()
        .zip(&reference.pixels)
        .map(|(a, b)| f64::from((*a - *b).length_squared()))
        .sum();
    let rmse = (sum / (3.0 * lin.len().max(1) as f64)).sqrt();
    Ok((flip, rmse))
}

/// RMSE in linear light between two references (their noise).
pub fn rmse_linear(a: &LinearImage, b: &LinearImage) -> Result<f64> {
    check_size(&a.pixels, b)?;
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(x, y)| f64::from((*x - *y).length_squared()))
        .sum();
    Ok((sum / (3.0 * a.pixels.len().max(1) as f64)).sqrt())
}

fn check_size(pixels: &[Vec3], reference: &LinearImage) -> Result<()> {
    if pixels.len() != reference.pixels.len() {
        return Err(Error::parameter(format!(
            "the images differ in size: {} pixels against the reference's {}×{}",
            pixels.len(),
            reference.width,
            reference.height
        )));
    }
    Ok(())
}
