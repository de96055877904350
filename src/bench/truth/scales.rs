//! The truth section's distance by scale: each fur's drawing with its light matched to
//! the reference's over every pixel's neighbourhood (the drawing times the reference's
//! mean there over its own, channel by channel). Matching keeps what differs at scales
//! finer than the neighbourhood (the strands, the edges, the reference's noise) and
//! removes what differs at coarser ones: the brightness and colour that a lighting
//! model's smooth shading gives each part of the body. So the matched distance says
//! how close any lighting of these strands could come at that scale, and the raw
//! distance less the matched one, how much of it the lighting leaves at coarser scales.

use std::fmt::Write as _;

use glam::Vec3;

use crate::bench::Bench;
use crate::export::compare::{covered, errors, linear, to_srgb8};
use crate::export::reference::LinearImage;
use fur_core::render::{LightingModel, RgbaImage};
use fur_gpu::error::Result;

/// The neighbourhoods' sides as fractions of the image's width, coarsest first: 33, 17
/// and 9 pixels at the truth section's 320×180, about a third, a sixth and a tenth of
/// the blob's width.
pub(super) const FRACTIONS: [(f32, &str); 3] = [
    (1.0 / 10.0, "matched_tenth_flip"),
    (1.0 / 20.0, "matched_twentieth_flip"),
    (1.0 / 36.0, "matched_thirty_sixth_flip"),
];

/// The side, in pixels, of the neighbourhood `fraction` of an image `width` wide: the
/// nearest odd number, at least 3.
pub(super) fn side(width: u32, fraction: f32) -> usize {
    let half = (width as f32 * fraction * 0.5).round().max(1.0) as usize;
    2 * half + 1
}

/// One drawing's distance, raw and matched at each of [`FRACTIONS`] (`sides` pixels).
pub(super) struct ScaleRow {
    variant: &'static str,
    model: LightingModel,
    flip: f64,
    matched: [f64; FRACTIONS.len()],
    sides: [usize; FRACTIONS.len()],
}

impl Bench<'_> {
    /// The distance by scale of each of `drawings` (a lighting model's drawing of fur
    /// variant `variant`, case `name`, and its ꟻLIP against `truth`, as measured); the
    /// rows also go to the CSV.
    pub(super) fn scale_rows(
        &mut self,
        name: &str,
        variant: &'static str,
        drawings: &[(LightingModel, &RgbaImage, f64)],
        truth: &LinearImage,
    ) -> Result<Vec<ScaleRow>> {
        let mut rows = Vec::new();
        for &(model, image, flip) in drawings {
            let drawn = linear(image);
            let mut matched = [0.0; FRACTIONS.len()];
            let sides = FRACTIONS.map(|(f, _)| side(truth.width, f));
            for (m, &side) in matched.iter_mut().zip(&sides) {
                let image = LinearImage {
                    width: truth.width,
                    height: truth.height,
                    pixels: light_matched(&drawn, truth, side),
                };
                *m = errors(&to_srgb8(&image), truth)?.0;
            }
            let case = format!("{name}: {} by scale", model.label());
            self.row("truth", case.clone(), "flip", flip, "0..1");
            for (m, (_, metric)) in matched.iter().zip(FRACTIONS) {
                self.row("truth", case.clone(), metric, *m, "0..1");
            }
            rows.push(ScaleRow {
                variant,
                model,
                flip,
                matched,
                sides,
            });
        }
        Ok(rows)
    }

    /// The distance-by-scale table of every variant.
    pub(super) fn scale_table(&mut self, rows: &[ScaleRow]) {
        let Some(first) = rows.first() else {
            return;
        };
        let sides: Vec<String> = first.sides.iter().map(|s| format!("{s}×{s}")).collect();
        let _ = writeln!(
            self.md,
            "Distance by scale: each drawing (without a shadow map) against its reference, \
             raw and with its light matched to the reference's over every pixel's \
             neighbourhood (a tenth, a twentieth and a thirty-sixth of the image's width a \
             side; over the pixels the fur or the body covers in either image: the \
             drawing times the reference's mean there over its own, red, green and blue \
             apart). Matching removes what differs at scales coarser than the \
             neighbourhood, the light the model gives each part of the body, and keeps the \
             rest: the strands, the edges and the reference's noise. So the matched ꟻLIP \
             is as close as any lighting of these strands comes at that scale.\n\n| fur | \
             drawing | ꟻLIP | matched over {} |\n| --- | --- | --- |{}",
            sides.join(" | "),
            " --- |".repeat(sides.len())
        );
        for r in rows {
            let cells: Vec<String> = r.matched.iter().map(|m| format!("{m:.4}")).collect();
            let _ = writeln!(
                self.md,
                "| {} | {} | {:.4} | {} |",
                r.variant,
                r.model.label(),
                r.flip,
                cells.join(" | ")
            );
        }
        self.md.push('\n');
    }
}

/// `drawn` (linear, the size of `truth`) with its light matched to `truth`'s over each
/// pixel's `side`×`side` neighbourhood, channel by channel, where the fur or the body
/// covers the pixel in either image (the background, the same in both, is left as
/// drawn and left out of the means): the drawing times the reference's sum over the
/// covered pixels there (as shown: clamped to 1) over its own; the reference's mean
/// where the drawing's is black.
pub(super) fn light_matched(drawn: &[Vec3], truth: &LinearImage, side: usize) -> Vec<Vec3> {
    let (w, h) = (truth.width as usize, truth.height as usize);
    let radius = side / 2;
    let mask: Vec<bool> = drawn
        .iter()
        .zip(&truth.pixels)
        .map(|(&d, &t)| covered(d) || covered(t))
        .collect();
    let only = |image: &[Vec3]| -> Vec<Vec3> {
        image
            .iter()
            .zip(&mask)
            .map(|(&p, &m)| if m { p } else { Vec3::ZERO })
            .collect()
    };
    // The reference as it is shown (ꟻLIP compares the shown images): its light over
    // 1, the path tracer's rare bright samples, would brighten a whole neighbourhood.
    let shown: Vec<Vec3> = truth
        .pixels
        .iter()
        .map(|p| p.clamp(Vec3::ZERO, Vec3::ONE))
        .collect();
    let own = box_means(&only(drawn), w, h, radius);
    let theirs = box_means(&only(&shown), w, h, radius);
    drawn
        .iter()
        .zip(&mask)
        .zip(own.iter().zip(&theirs))
        .map(|((&d, &m), (&o, &t))| {
            if !m {
                return d;
            }
            let scaled = d * t / o.max(Vec3::splat(1e-12));
            Vec3::select(o.cmpgt(Vec3::splat(1e-9)), scaled, t)
        })
        .collect()
}

/// The mean of `pixels` (`w`×`h`, row by row) over each pixel's square of `radius`,
/// cut at the image's edges: by a summed-area table, in f64.
pub(super) fn box_means(pixels: &[Vec3], w: usize, h: usize, radius: usize) -> Vec<Vec3> {
    let stride = w + 1;
    let mut sums = vec![[0.0f64; 3]; stride * (h + 1)];
    for y in 0..h {
        for x in 0..w {
            let p = pixels.get(y * w + x).copied().unwrap_or(Vec3::ZERO);
            let (up, left, corner) = (
                sums[y * stride + x + 1],
                sums[(y + 1) * stride + x],
                sums[y * stride + x],
            );
            let cell = &mut sums[(y + 1) * stride + x + 1];
            for c in 0..3 {
                cell[c] = f64::from(p[c]) + up[c] + left[c] - corner[c];
            }
        }
    }
    let mut means = Vec::with_capacity(w * h);
    for y in 0..h {
        let (y0, y1) = (y.saturating_sub(radius), (y + radius + 1).min(h));
        for x in 0..w {
            let (x0, x1) = (x.saturating_sub(radius), (x + radius + 1).min(w));
            let n = ((y1 - y0) * (x1 - x0)) as f64;
            let at = |yy: usize, xx: usize| sums[yy * stride + xx];
            let (a, b, c, d) = (at(y1, x1), at(y0, x1), at(y1, x0), at(y0, x0));
            let mean = |k: usize| ((a[k] - b[k] - c[k] + d[k]) / n) as f32;
            means.push(Vec3::new(mean(0), mean(1), mean(2)));
        }
    }
    means
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> Vec3) -> LinearImage {
        let pixels = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        LinearImage {
            width: w,
            height: h,
            pixels,
        }
    }

    /// The summed-area table's means are the plain means over each square, cut at the
    /// edges (an off-by-one in the table or the cut fails at the borders).
    #[test]
    fn box_means_are_the_plain_means_cut_at_the_edges() {
        let img = image(7, 5, |x, y| {
            Vec3::new((x * 3 + y) as f32, (x * y) as f32, ((x + 2 * y) % 5) as f32)
        });
        for radius in [0, 1, 2, 4] {
            let fast = box_means(&img.pixels, 7, 5, radius);
            for y in 0..5usize {
                for x in 0..7usize {
                    let mut sum = Vec3::ZERO;
                    let mut n = 0.0;
                    for yy in y.saturating_sub(radius)..(y + radius + 1).min(5) {
                        for xx in x.saturating_sub(radius)..(x + radius + 1).min(7) {
                            sum += img.pixels[yy * 7 + xx];
                            n += 1.0;
                        }
                    }
                    let want = sum / n;
                    let got = fast[y * 7 + x];
                    assert!((got - want).abs().max_element() < 1e-4, "{x},{y} r{radius}");
                }
            }
        }
    }

    /// A drawing off by a colour everywhere is matched back to the reference exactly,
    /// channel by channel (matching the grey brightness alone, or the wrong way round,
    /// leaves the colour cast).
    #[test]
    fn a_colour_cast_is_matched_away() {
        let truth = image(40, 30, |x, y| {
            Vec3::new(
                0.1 + 0.02 * (x % 7) as f32,
                0.05 + 0.01 * (y % 5) as f32,
                0.3,
            )
        });
        let cast = Vec3::new(0.5, 1.0, 2.0);
        let drawn: Vec<Vec3> = truth.pixels.iter().map(|&p| p * cast).collect();
        for side in [33, 17, 9] {
            let matched = light_matched(&drawn, &truth, side);
            for (m, t) in matched.iter().zip(&truth.pixels) {
                assert!((*m - *t).abs().max_element() < 1e-5, "{side}: {m} vs {t}");
            }
        }
    }

    /// The sides are the nearest odd numbers to their fractions of the width.
    #[test]
    fn sides_scale_with_the_width() {
        let at = |width| FRACTIONS.map(|(f, _)| side(width, f));
        assert_eq!(at(320), [33, 17, 9]);
        assert_eq!(at(96), [11, 5, 3]);
        assert_eq!(at(8), [3, 3, 3]);
    }

    /// The background is left as drawn and out of the means: a drawing twice as bright
    /// as the reference on the fur is matched there and nowhere else (matching over
    /// every pixel would darken the background around the fur and leave the fur's
    /// edge too bright).
    #[test]
    fn the_background_is_left_as_drawn() {
        let fur = |x: u32, y: u32| (8..24).contains(&x) && (6..18).contains(&y);
        let bg = fur_gpu::render::BACKGROUND;
        let truth = image(32, 24, |x, y| if fur(x, y) { Vec3::splat(0.2) } else { bg });
        let drawn: Vec<Vec3> = truth
            .pixels
            .iter()
            .map(|&p| if p == bg { bg } else { p * 2.0 })
            .collect();
        let matched = light_matched(&drawn, &truth, 17);
        for (i, (m, t)) in matched.iter().zip(&truth.pixels).enumerate() {
            assert!(
                (*m - *t).abs().max_element() < 1e-5,
                "pixel {i}: {m} vs {t}"
            );
        }
    }

    /// The reference is matched as it is shown: one path-traced sample far over 1
    /// (shown as 1) does not brighten its whole neighbourhood.
    #[test]
    fn a_bright_sample_is_matched_as_shown() {
        let truth = image(40, 30, |x, y| {
            Vec3::splat(if (x, y) == (20, 15) { 50.0 } else { 0.2 })
        });
        let drawn: Vec<Vec3> = truth.pixels.iter().map(|p| p.min(Vec3::ONE)).collect();
        let matched = light_matched(&drawn, &truth, 17);
        for (i, m) in matched.iter().enumerate() {
            if i != 15 * 40 + 20 {
                assert!(
                    (*m - Vec3::splat(0.2)).abs().max_element() < 0.01,
                    "pixel {i}: {m}"
                );
            }
        }
    }

    /// Structure finer than the neighbourhood stays: a pixel checkerboard over the
    /// reference keeps (nearly) all its difference from it, while a drawing that is
    /// wrong only by a smooth ramp of light keeps (nearly) none of it.
    #[test]
    fn fine_structure_stays_and_a_smooth_error_goes() {
        let truth = image(64, 48, |_, _| Vec3::splat(0.2));
        let checker: Vec<Vec3> = (0..48)
            .flat_map(|y| (0..64).map(move |x| (x, y)))
            .map(|(x, y)| Vec3::splat(if (x + y) % 2 == 0 { 0.3 } else { 0.1 }))
            .collect();
        let ramp: Vec<Vec3> = (0..48)
            .flat_map(|_| (0..64).map(|x| Vec3::splat(0.2 * (0.5 + x as f32 / 63.0))))
            .collect();
        let off = |image: &[Vec3]| -> f32 {
            image
                .iter()
                .zip(&truth.pixels)
                .map(|(a, b)| (*a - *b).abs().element_sum())
                .sum::<f32>()
                / image.len() as f32
        };
        let kept = off(&light_matched(&checker, &truth, 9)) / off(&checker);
        assert!(kept > 0.9, "the checkerboard kept {kept} of its difference");
        let left = off(&light_matched(&ramp, &truth, 9)) / off(&ramp);
        assert!(left < 0.05, "the ramp kept {left} of its difference");
    }
}
