//! The colour keys of the stage views that colour by a number (`density`: the inner
//! tessellation level; `simulation`: the displacement from rest; `tiles`: the segments
//! a tile lists), drawn into a
//! rendered image's lower-left corner so a PNG explains itself. The viewer shows the
//! same keys in its panel ([`Legend`] describes both).

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use glam::Vec3;

use fur_core::colour::linear_to_srgb8;
use fur_core::render::stage::{
    displacement_colour, legend_entries, legend_levels, level_colour, tile_colour,
    DISPLACEMENT_FULL_SCALE, EMPTY_TILE, TILE_ENTRIES_FULL_SCALE,
};
use fur_core::render::{FrameSettings, RgbaImage, Stage};

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
    pub swatches: Vec<(Swatch, String)>,
}

impl Legend {
    /// The key of the stage `settings` show on a device whose largest tessellation
    /// level is `max_level`; None for the views without one.
    pub fn of(settings: &FrameSettings, max_level: f32) -> Option<Legend> {
        match settings.show {
            Stage::Density => {
                let top = max_level.max(2.0).log2();
                Some(Legend {
                    title: "inner tessellation level",
                    colour: Box::new(move |t| level_colour((t * top).exp2(), max_level)),
                    ticks: legend_levels(max_level)
                        .into_iter()
                        .map(|l| ((l as f32).log2() / top, l.to_string()))
                        .collect(),
                    swatches: vec![(Swatch::Hatched, "culled".into())],
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
                swatches: std::iter::once((
                    Swatch::Colour(Vec3::ONE),
                    "pushed by collision".into(),
                ))
                .chain(settings.arrows.step().map(|step| {
                    // The arrows' bright end (shaders/arrows.vert).
                    let magenta = Vec3::new(1.0, 0.2, 1.0);
                    let label = format!("{} ×{}", step.key(), settings.arrow_scale);
                    (Swatch::Colour(magenta), label)
                }))
                .collect(),
            }),
            Stage::Tiles => {
                let top = TILE_ENTRIES_FULL_SCALE.log2();
                Some(Legend {
                    title: "segments a tile lists",
                    colour: Box::new(move |t| tile_colour((t * top).exp2().round() as u32)),
                    ticks: legend_entries()
                        .into_iter()
                        .map(|n| ((n as f32).log2() / top, n.to_string()))
                        .collect(),
                    swatches: vec![(Swatch::Colour(Vec3::splat(EMPTY_TILE)), "none".into())],
                })
            }
            _ => None,
        }
    }

    /// Draws the key into `image`'s lower-left corner, scaled to its height, and
    /// returns where its colour bar went (x, y, width, height); nothing when the image
    /// is too small to hold it legibly.
    pub fn draw(&self, image: &mut RgbaImage) -> Option<(i32, i32, i32, i32)> {
        let (font, text_px, margin) = key_font(image.height);
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
            return None;
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
        let bar = (left, y, bar_w, bar_h);
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
        Some(bar)
    }
}

/// The font a key is written in on an image `height` pixels tall, scaled to it, its
/// size in pixels, and the key's margin.
pub(crate) fn key_font(height: u32) -> (ab_glyph::PxScaleFont<FontRef<'static>>, f32, i32) {
    let font = FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT)
        .expect("the embedded font parses");
    let text_px = (height as f32 / 28.0).clamp(10.0, 18.0);
    let margin = (text_px * 0.6).round() as i32;
    let scale = PxScale::from(text_px);
    (ab_glyph::PxScaleFont { font, scale }, text_px, margin)
}

pub(crate) fn text_width<F: Font>(font: &ab_glyph::PxScaleFont<F>, text: &str) -> i32 {
    text.chars()
        .map(|c| font.h_advance(font.glyph_id(c)))
        .sum::<f32>()
        .ceil() as i32
}

/// Drawing into an sRGB image with linear colours.
pub(crate) struct Canvas<'a> {
    pub image: &'a mut RgbaImage,
}

impl Canvas<'_> {
    /// Blends `colour(x, y)` (linear, relative to the rectangle) over the rectangle
    /// with `opacity`, in linear light.
    pub fn fill(
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

    pub fn blend(&mut self, x: i32, y: i32, colour: Vec3, opacity: f32) {
        let (width, height) = (self.image.width as i32, self.image.height as i32);
        if x < 0 || y < 0 || x >= width || y >= height {
            return;
        }
        let i = ((y * width + x) * 4) as usize;
        let lut = fur_core::colour::srgb8_lut();
        for c in 0..3 {
            let below = lut[self.image.data[i + c] as usize];
            let mixed = below + (colour[c] - below) * opacity;
            self.image.data[i + c] = linear_to_srgb8(mixed);
        }
        self.image.data[i + 3] = 255;
    }

    /// White text with its top-left corner at (x, y).
    pub fn text<F: Font>(&mut self, font: &ab_glyph::PxScaleFont<F>, text: &str, x: i32, y: i32) {
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// An image of one dull colour.
    pub(crate) fn blank(width: u32, height: u32) -> RgbaImage {
        RgbaImage {
            width,
            height,
            data: [10, 20, 30, 255].repeat((width * height) as usize),
        }
    }

    /// The density key's bar shows each labelled level in the colour the density view
    /// paints it (`level_colour`), its labels are drawn in white, and an image too small
    /// for a legible key is left alone.
    #[test]
    fn the_density_key_shows_the_views_colours_at_its_ticks() {
        let settings = FrameSettings {
            show: Stage::Density,
            ..Default::default()
        };
        let legend = Legend::of(&settings, 64.0).expect("the density view has a key");
        let mut image = blank(480, 270);
        let (x, y, w, h) = legend.draw(&mut image).expect("room for the key");
        // Along the bar, pixel i shows the level 2^(6 i / (w − 1)) (log₂ 64 = 6) in the
        // view's colour, and each label's tick sits at its level.
        for i in 0..w {
            let level = (6.0 * i as f32 / (w - 1) as f32).exp2();
            let p = image.pixel((x + i) as u32, (y + h / 2) as u32);
            let want = level_colour(level, 64.0).to_array().map(linear_to_srgb8);
            assert!(
                (0..3).all(|c| p[c].abs_diff(want[c]) <= 1),
                "pixel {i} (level {level}): {p:?}, want {want:?}"
            );
        }
        let levels = legend_levels(64.0);
        assert_eq!(legend.ticks.len(), levels.len());
        for ((t, label), level) in legend.ticks.iter().zip(levels) {
            assert_eq!(label, &level.to_string());
            assert!(
                ((t * 6.0).exp2() / level as f32 - 1.0).abs() < 1e-5,
                "{label} at {t}"
            );
        }
        let white = image
            .data
            .chunks_exact(4)
            .filter(|p| p[..3].iter().all(|&c| c > 160))
            .count();
        assert!(white > 100, "{white} light text pixels");
        let mut small = blank(60, 40);
        assert_eq!(legend.draw(&mut small), None);
        assert_eq!(small, blank(60, 40));
        let lit = FrameSettings::default();
        assert!(Legend::of(&lit, 64.0).is_none(), "the lit view has no key");
    }

    /// The simulation key names the arrows' step and scale when they are drawn.
    #[test]
    fn the_simulation_key_names_the_arrows() {
        let mut settings = FrameSettings {
            show: Stage::Simulation,
            ..Default::default()
        };
        let labels = |s: &FrameSettings| -> Vec<String> {
            Legend::of(s, 64.0)
                .unwrap()
                .swatches
                .into_iter()
                .map(|(_, l)| l)
                .collect()
        };
        assert_eq!(labels(&settings), ["pushed by collision"]);
        settings.arrows = fur_core::render::stage::Arrows::Step(fur_core::sim::SimStep::Length);
        settings.arrow_scale = 50.0;
        assert_eq!(labels(&settings), ["pushed by collision", "length ×50"]);
    }
}
