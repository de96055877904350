//! The colour keys of the stage views that colour by a number (`density`: the inner
//! tessellation level; `simulation`: the displacement from rest), drawn into a
//! rendered image's lower-left corner so a PNG explains itself. The viewer shows the
//! same keys in its panel ([`Legend`] describes both).

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use glam::Vec3;

use crate::colour::linear_to_srgb8;
use crate::render::stage::{
    displacement_colour, legend_levels, level_colour, DISPLACEMENT_FULL_SCALE,
};
use crate::render::{RgbaImage, Stage};

/// A swatch beside the scale: a colour, or the density view's grey stripes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Swatch {
    Colour(Vec3),
    Hatched,
}

/// A colour scale and what it measures.
pub struct Legend {
    pub title: &'static str,
    /// Linear colour at a position 0..=1 along the scale.
    pub colour: Box<dyn Fn(f32) -> Vec3>,
    /// Labels and their positions along the scale.
    pub ticks: Vec<(f32, String)>,
    /// Swatches after the scale, with their labels.
    pub swatches: Vec<(Swatch, &'static str)>,
}

impl Legend {
    /// The key of `stage` on a device whose largest tessellation level is
    /// `max_level`; None for the views without one.
    pub fn of(stage: Stage, max_level: f32) -> Option<Legend> {
        match stage {
            Stage::Density => {
                let top = max_level.max(2.0).log2();
                Some(Legend {
                    title: "inner tessellation level",
                    colour: Box::new(move |t| level_colour((t * top).exp2(), max_level)),
                    ticks: legend_levels(max_level)
                        .into_iter()
                        .map(|l| ((l as f32).log2() / top, l.to_string()))
                        .collect(),
                    swatches: vec![(Swatch::Hatched, "culled")],
                })
            }
            Stage::Simulation => Some(Legend {
                title: "moved from rest, % of the hair's length",
                colour: Box::new(|t| displacement_colour(t * DISPLACEMENT_FULL_SCALE)),
                ticks: (0..=5)
                    .map(|k| {
                        let t = k as f32 / 5.0;
                        let percent = t * DISPLACEMENT_FULL_SCALE * 100.0;
                        let plus = if k == 5 { "+" } else { "" };
                        (t, format!("{percent:.0}{plus}"))
                    })
                    .collect(),
                swatches: vec![(Swatch::Colour(Vec3::ONE), "pushed by collision")],
            }),
            _ => None,
        }
    }

    /// Draws the key into `image`'s lower-left corner, scaled to its height (nothing
    /// when the image is too small to hold it legibly).
    pub fn draw(&self, image: &mut RgbaImage) {
        let font = FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT)
            .expect("the embedded font parses");
        let text_px = (image.height as f32 / 28.0).clamp(10.0, 18.0);
        let font = font.as_scaled(PxScale::from(text_px));
        let margin = (text_px * 0.6).round() as i32;
        let bar_w = (image.width as f32 * 0.3).clamp(120.0, 320.0) as i32;
        let bar_h = (text_px * 0.8).round() as i32;
        let line = font.height().ceil() as i32;
        let swatch_w: i32 = self
            .swatches
            .iter()
            .map(|(_, label)| bar_h + 4 + text_width(&font, label) + margin)
            .sum();
        let panel_w = bar_w.max(text_width(&font, self.title)).max(swatch_w) + 2 * margin;
        let panel_h = line * 2
            + bar_h
            + 4
            + margin * 2
            + if self.swatches.is_empty() {
                0
            } else {
                line + 4
            };
        if panel_w + 2 * margin > image.width as i32 || panel_h + 2 * margin > image.height as i32 {
            return;
        }
        let x0 = margin;
        let y0 = image.height as i32 - margin - panel_h;
        let mut canvas = Canvas { image };
        canvas.fill(x0, y0, panel_w, panel_h, |_, _| Vec3::splat(0.0), 0.7);
        let (left, mut y) = (x0 + margin, y0 + margin);
        canvas.text(&font, self.title, left, y);
        y += line;
        canvas.fill(
            left,
            y,
            bar_w,
            bar_h,
            |x, _| (self.colour)(x as f32 / (bar_w - 1) as f32),
            1.0,
        );
        y += bar_h + 4;
        // Labels that would run into the one before are left out (their tick stays).
        let mut free_from = i32::MIN;
        for (t, label) in &self.ticks {
            let x = left + (t * (bar_w - 1) as f32).round() as i32;
            canvas.fill(x, y - 4, 1, 3, |_, _| Vec3::ONE, 1.0);
            let w = text_width(&font, label);
            let lx = (x - w / 2).clamp(left, left + bar_w - w);
            if lx >= free_from {
                canvas.text(&font, label, lx, y);
                free_from = lx + w + (text_px * 0.4) as i32;
            }
        }
        y += line + 4;
        let mut x = left;
        for (swatch, label) in &self.swatches {
            match *swatch {
                Swatch::Colour(c) => canvas.fill(x, y, bar_h, bar_h, |_, _| c, 1.0),
                Swatch::Hatched => canvas.fill(
                    x,
                    y,
                    bar_h,
                    bar_h,
                    |px, py| Vec3::splat(if (px + py) / 4 % 2 == 1 { 0.3 } else { 0.1 }),
                    1.0,
                ),
            }
            canvas.text(&font, label, x + bar_h + 4, y + (bar_h - line) / 2);
            x += bar_h + 4 + text_width(&font, label) + margin;
        }
    }
}

fn text_width<F: Font>(font: &ab_glyph::PxScaleFont<F>, text: &str) -> i32 {
    text.chars()
        .map(|c| font.h_advance(font.glyph_id(c)))
        .sum::<f32>()
        .ceil() as i32
}

/// Drawing into an sRGB image with linear colours.
struct Canvas<'a> {
    image: &'a mut RgbaImage,
}

impl Canvas<'_> {
    /// Blends `colour(x, y)` (linear, relative to the rectangle) over the rectangle
    /// with `opacity`, in linear light.
    fn fill(
        &mut self,
        x0: i32,
        y0: i32,
        w: i32,
        h: i32,
        colour: impl Fn(i32, i32) -> Vec3,
        opacity: f32,
    ) {
        for y in 0..h {
            for x in 0..w {
                self.blend(x0 + x, y0 + y, colour(x, y), opacity);
            }
        }
    }

    fn blend(&mut self, x: i32, y: i32, colour: Vec3, opacity: f32) {
        let (width, height) = (self.image.width as i32, self.image.height as i32);
        if x < 0 || y < 0 || x >= width || y >= height {
            return;
        }
        let i = ((y * width + x) * 4) as usize;
        let lut = crate::colour::srgb8_lut();
        for c in 0..3 {
            let below = lut[self.image.data[i + c] as usize];
            let mixed = below + (colour[c] - below) * opacity;
            self.image.data[i + c] = linear_to_srgb8(mixed);
        }
        self.image.data[i + 3] = 255;
    }

    /// White text with its top-left corner at (x, y).
    fn text<F: Font>(&mut self, font: &ab_glyph::PxScaleFont<F>, text: &str, x: i32, y: i32) {
        let mut pen = x as f32;
        let baseline = y as f32 + font.ascent();
        for c in text.chars() {
            let id = font.glyph_id(c);
            let glyph = id.with_scale_and_position(font.scale(), ab_glyph::point(pen, baseline));
            pen += font.h_advance(id);
            if let Some(outline) = font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                outline.draw(|gx, gy, coverage| {
                    let px = bounds.min.x as i32 + gx as i32;
                    let py = bounds.min.y as i32 + gy as i32;
                    self.blend(px, py, Vec3::ONE, coverage.clamp(0.0, 1.0));
                });
            }
        }
    }
}
