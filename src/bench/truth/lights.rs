//! The truth section's light by light: each fur variant lit by the sun alone and by
//! the sky alone (the uniform environment), drawn and path-traced the same way. Light
//! adds, so the two references sum to the full one and so do the two drawings; what
//! each light's drawing makes of its own reference says which light the distance
//! comes from, and how bright and what colour each light leaves the fur.

use std::fmt::Write as _;
use std::path::Path;

use glam::Vec3;

use super::scales::box_means;
use super::{cached_trace, export, Sampling};
use crate::bench::metrics::Frames;
use crate::bench::quality::{Look, Shot};
use crate::bench::Bench;
use crate::export::compare::{covered, errors, linear};
use crate::export::reference::{LinearImage, Reference};
use fur_core::render::{LightingModel, RgbaImage};
use fur_gpu::error::Result;
use fur_gpu::render::BACKGROUND;

/// The two lights, each alone: the sun (the distant light) and the sky.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Light {
    Sun,
    Sky,
}

impl Light {
    pub(super) const BOTH: [Light; 2] = [Light::Sun, Light::Sky];

    fn name(self) -> &'static str {
        match self {
            Light::Sun => "sun",
            Light::Sky => "sky",
        }
    }

    /// `look` lit by this light alone: the other one off.
    fn alone(self, look: &Look) -> Look {
        let mut look = look.clone();
        match self {
            Light::Sun => look.lighting.ambient = 0.0,
            Light::Sky => look.lighting.intensity = 0.0,
        }
        look
    }
}

/// One fur variant under one light: each model's ꟻLIP against that light's reference,
/// and the Marschner drawing's brightness against it, channel by channel, over all the
/// fur and over its darkest fifth.
pub(super) struct LightRow {
    variant: &'static str,
    light: Light,
    kajiya_kay: f64,
    marschner: f64,
    all: Vec3,
    darkest: Vec3,
}

/// Pixels whose mean over a box of this many on each side picks the darkest fifth.
const BLUR: usize = 4;

impl Bench<'_> {
    /// `own` (the variant's look, drawn by `shot`) lit by each light alone, exported
    /// and path-traced (the full `truth`'s fur pixels pick where brightness is
    /// compared), and drawn under each lighting model without a shadow map, as the
    /// term table draws; `marschner` is the full frame drawn so.
    pub(super) fn light_by_light(
        &mut self,
        variant: &'static str,
        name: &str,
        shot: &Shot,
        own: &Look,
        (truth, marschner): (&LinearImage, &RgbaImage),
        (reference, dir, sampling): (&Reference, &Path, Sampling),
    ) -> Result<Vec<LightRow>> {
        let fur = fur_pixels(truth);
        let darkest = darkest_fifth(truth, &fur);
        let full_drawn = linear(marschner);
        // The two lights' drawings and references, summed as they come.
        let mut drawn_sum = vec![Vec3::ZERO; full_drawn.len()];
        let mut traced_sum = vec![Vec3::ZERO; truth.pixels.len()];
        let mut rows = Vec::new();
        for light in Light::BOTH {
            let look = light.alone(own);
            let file = dir.join(format!("{name}-{}.usda", light.name()));
            let (_, usda, text, _) = export(shot, &look, &file)?;
            let alone = cached_trace(reference, &usda, &text, sampling, 0, None)?.image;
            // The export is the full frame's but for a light, and is written again on
            // each run before its reference is looked up: not worth its tens of MB kept.
            let _ = std::fs::remove_file(&usda);
            let mut flips = [0.0; 2];
            let mut marschner = None;
            for (i, model) in [LightingModel::KajiyaKay, LightingModel::Marschner]
                .into_iter()
                .enumerate()
            {
                let mut drawn_look = look.clone();
                drawn_look.lighting.model = model;
                drawn_look.lighting.shadows.enabled = false;
                let drawn = shot.draw_look(&drawn_look, Frames::STILL)?;
                flips[i] = errors(&drawn.image, &alone)?.0;
                if model == LightingModel::Marschner {
                    marschner = Some(linear(&drawn.image));
                }
            }
            let drawn = marschner.unwrap_or_default();
            add(&mut drawn_sum, &drawn);
            add(&mut traced_sum, &alone.pixels);
            let row = LightRow {
                variant,
                light,
                kajiya_kay: flips[0],
                marschner: flips[1],
                all: brightness(&drawn, &alone.pixels, &fur),
                darkest: brightness(&drawn, &alone.pixels, &darkest),
            };
            let case = format!("{name}: {} alone", light.name());
            self.row(
                "truth",
                case.clone(),
                "kajiya_kay_flip",
                row.kajiya_kay,
                "0..1",
            );
            self.row(
                "truth",
                case.clone(),
                "marschner_flip",
                row.marschner,
                "0..1",
            );
            for (what, ratio) in [("brightness", row.all), ("darkest_brightness", row.darkest)] {
                self.row(
                    "truth",
                    case.clone(),
                    what,
                    f64::from(ratio.element_sum() / 3.0),
                    "ratio",
                );
            }
            (self.progress)(&case);
            rows.push(row);
        }
        // Light adds: what the two lights' images have over the full one is the
        // background counted twice where no hair covers it, between none and all of it.
        for (what, sum, whole) in [
            ("drawing", &drawn_sum, &full_drawn),
            ("reference", &traced_sum, &truth.pixels),
        ] {
            let residual = sum_residual(sum, whole, BACKGROUND, &fur);
            self.row(
                "truth",
                format!("{name}: lights summed"),
                what,
                residual,
                "background",
            );
        }
        Ok(rows)
    }

    /// The light-by-light table of every variant.
    pub(super) fn light_table(&mut self, rows: &[LightRow]) {
        let _ = writeln!(
            self.md,
            "Light by light: each fur lit by the sun alone and by the sky alone (the \
             uniform environment), drawn and path-traced the same way (light adds: the two \
             sum to the full frame), each drawing against its light's reference (ꟻLIP); \
             and the Marschner drawing's brightness against that reference, red, green \
             and blue (the drawing's mean over the fur's pixels over the reference's; 1: \
             as bright), over all the fur and over its darkest fifth (by the full \
             reference's light, each pixel's {0}×{0} neighbourhood).\n\n| fur | light | \
             Kajiya–Kay ꟻLIP | Marschner ꟻLIP | Marschner's brightness | in the darkest \
             fifth |\n| --- | --- | --- | --- | --- | --- |",
            2 * BLUR + 1
        );
        let rgb = |v: Vec3| format!("{:.2}, {:.2}, {:.2}", v.x, v.y, v.z);
        for r in rows {
            let _ = writeln!(
                self.md,
                "| {} | {} | {:.4} | {:.4} | {} | {} |",
                r.variant,
                r.light.name(),
                r.kajiya_kay,
                r.marschner,
                rgb(r.all),
                rgb(r.darkest)
            );
        }
        self.md.push('\n');
    }
}

/// The pixels the fur (or the body) covers in `truth`.
fn fur_pixels(truth: &LinearImage) -> Vec<usize> {
    (0..truth.pixels.len())
        .filter(|&i| covered(truth.pixels[i]))
        .collect()
}

/// Of `pixels`, the fifth darkest by the mean light of `truth` over each one's
/// neighbourhood (the path tracer's noise averaged out).
fn darkest_fifth(truth: &LinearImage, pixels: &[usize]) -> Vec<usize> {
    let (w, h) = (truth.width as usize, truth.height as usize);
    let means = box_means(&truth.pixels, w, h, BLUR);
    let mut lit: Vec<(f32, usize)> = pixels
        .iter()
        .filter_map(|&i| Some((means.get(i)?.element_sum(), i)))
        .collect();
    lit.sort_by(|a, b| a.0.total_cmp(&b.0));
    lit.truncate(lit.len().div_ceil(5));
    lit.into_iter().map(|(_, i)| i).collect()
}

/// The mean of `drawn` over `pixels` against the mean of `reference`, channel by
/// channel (0 where the reference is black there).
fn brightness(drawn: &[Vec3], reference: &[Vec3], pixels: &[usize]) -> Vec3 {
    let sum = |image: &[Vec3]| {
        pixels
            .iter()
            .filter_map(|&i| image.get(i))
            .fold(Vec3::ZERO, |a, &p| a + p)
    };
    let (d, r) = (sum(drawn), sum(reference));
    Vec3::select(
        r.cmpgt(Vec3::ZERO),
        d / r.max(Vec3::splat(1e-12)),
        Vec3::ZERO,
    )
}

fn add(sum: &mut [Vec3], image: &[Vec3]) {
    for (s, p) in sum.iter_mut().zip(image) {
        *s += *p;
    }
}

/// The mean over `pixels` of what `sum` (two lights' images) has over `whole` (both
/// lights at once), in units of the background's light: 0 where hair covers every
/// pixel, 1 where none does; outside that, the lights do not add.
fn sum_residual(sum: &[Vec3], whole: &[Vec3], background: Vec3, pixels: &[usize]) -> f64 {
    let n = pixels.len().max(1) as f64;
    let over: f64 = pixels
        .iter()
        .filter_map(|&i| Some(f64::from((*sum.get(i)? - *whole.get(i)?).element_sum())))
        .sum();
    over / n / f64::from(background.element_sum().max(1e-6))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hair of coverage `a` lit `hair` over the background `bg`, as a drawing blends it.
    fn blend(a: f32, hair: Vec3, bg: Vec3) -> Vec3 {
        a * hair + (1.0 - a) * bg
    }

    #[test]
    fn two_lights_sum_to_the_whole_but_for_the_background_left_uncovered() {
        let bg = Vec3::new(0.02, 0.025, 0.035);
        let (sun, sky) = (Vec3::new(0.3, 0.2, 0.1), Vec3::new(0.05, 0.04, 0.03));
        let cover = [1.0, 1.0, 0.5, 0.0];
        let image =
            |light: Vec3| -> Vec<Vec3> { cover.iter().map(|&a| blend(a, light, bg)).collect() };
        let (alone_sun, alone_sky, whole) = (image(sun), image(sky), image(sun + sky));
        let mut sum = vec![Vec3::ZERO; cover.len()];
        add(&mut sum, &alone_sun);
        add(&mut sum, &alone_sky);
        let all: Vec<usize> = (0..cover.len()).collect();
        // Half a pixel and a whole one uncovered of four: 1.5 / 4 of the background.
        let residual = sum_residual(&sum, &whole, bg, &all);
        assert!((residual - 0.375).abs() < 1e-5, "{residual}");
        // Fully covered pixels: nothing over.
        assert!(sum_residual(&sum, &whole, bg, &[0, 1]).abs() < 1e-5);
        // The sky left on in the sun's image: far more than the background.
        let mut wrong = vec![Vec3::ZERO; cover.len()];
        add(&mut wrong, &whole);
        add(&mut wrong, &alone_sky);
        assert!(sum_residual(&wrong, &whole, bg, &[0, 1]) > 1.5);
    }

    #[test]
    fn brightness_is_the_ratio_of_means_channel_by_channel() {
        let reference = [Vec3::new(0.2, 0.1, 0.0), Vec3::new(0.2, 0.3, 0.0)];
        let drawn = [Vec3::new(0.4, 0.1, 0.5), Vec3::new(0.0, 0.1, 0.5)];
        let ratio = brightness(&drawn, &reference, &[0, 1]);
        assert!(
            (ratio - Vec3::new(1.0, 0.5, 0.0)).abs().max_element() < 1e-6,
            "{ratio}"
        );
        let lit = LinearImage {
            width: 10,
            height: 1,
            pixels: (0..10).map(|i| Vec3::splat(i as f32)).collect(),
        };
        let all: Vec<usize> = (0..10).collect();
        // The darkest fifth of ten pixels: the two darkest neighbourhoods.
        let mut darkest = darkest_fifth(&lit, &all);
        darkest.sort_unstable();
        assert_eq!(darkest, vec![0, 1]);
    }
}
