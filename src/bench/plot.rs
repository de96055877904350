//! Small PNG charts for the benchmark: scatter/line series on linear or log axes, with
//! a built-in 5×7 bitmap font (upper-case ASCII), so no font files are needed.

use crate::render::RgbaImage;

const WIDTH: u32 = 720;
const HEIGHT: u32 = 460;
const LEFT: i32 = 84;
const RIGHT: i32 = 24;
const TOP: i32 = 44;
const BOTTOM: i32 = 60;
const SCALE: i32 = 2; // font pixels per glyph pixel

/// One set of points.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub color: [u8; 3],
    /// Join the points (in the given order) with lines.
    pub line: bool,
}

/// A chart.
#[derive(Clone, Debug)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
    /// A point to ring (e.g. the default settings).
    pub highlight: Option<(f64, f64, String)>,
}

pub const PALETTE: [[u8; 3]; 6] = [
    [31, 119, 180],
    [214, 39, 40],
    [44, 160, 44],
    [148, 103, 189],
    [255, 127, 14],
    [23, 190, 207],
];

struct Canvas {
    image: RgbaImage,
}

impl Canvas {
    fn new() -> Self {
        Self {
            image: RgbaImage {
                width: WIDTH,
                height: HEIGHT,
                data: vec![255; (WIDTH * HEIGHT * 4) as usize],
            },
        }
    }

    fn set(&mut self, x: i32, y: i32, c: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < WIDTH && (y as u32) < HEIGHT {
            let i = ((y as u32 * WIDTH + x as u32) * 4) as usize;
            self.image.data[i..i + 3].copy_from_slice(&c);
        }
    }

    fn line(&mut self, (x0, y0): (i32, i32), (x1, y1): (i32, i32), c: [u8; 3]) {
        let (dx, dy) = ((x1 - x0).abs(), -(y1 - y0).abs());
        let (sx, sy) = (if x0 < x1 { 1 } else { -1 }, if y0 < y1 { 1 } else { -1 });
        let (mut x, mut y, mut err) = (x0, y0, dx + dy);
        loop {
            self.set(x, y, c);
            if x == x1 && y == y1 {
                break;
            }
            let e2 = 2 * err;
            if e2 >= dy {
                err += dy;
                x += sx;
            }
            if e2 <= dx {
                err += dx;
                y += sy;
            }
        }
    }

    fn square(&mut self, x: i32, y: i32, r: i32, c: [u8; 3]) {
        for yy in y - r..=y + r {
            for xx in x - r..=x + r {
                self.set(xx, yy, c);
            }
        }
    }

    fn ring(&mut self, x: i32, y: i32, r: i32, c: [u8; 3]) {
        let steps = 64;
        for k in 0..steps {
            let a = k as f64 / steps as f64 * std::f64::consts::TAU;
            let b = (k + 1) as f64 / steps as f64 * std::f64::consts::TAU;
            let p = |a: f64| {
                (
                    x + (f64::from(r) * a.cos()).round() as i32,
                    y + (f64::from(r) * a.sin()).round() as i32,
                )
            };
            self.line(p(a), p(b), c);
        }
    }

    /// Draws `text` with its top-left corner at (x, y); returns the width in pixels.
    fn text(&mut self, x: i32, y: i32, text: &str, c: [u8; 3]) -> i32 {
        for (i, row, col) in glyph_pixels(text) {
            let cx = x + i * 6 * SCALE;
            self.dot(cx + col * SCALE, y + row * SCALE, c);
        }
        Self::text_width(text)
    }

    /// A font pixel: SCALE × SCALE screen pixels.
    fn dot(&mut self, x: i32, y: i32, c: [u8; 3]) {
        for dy in 0..SCALE {
            for dx in 0..SCALE {
                self.set(x + dx, y + dy, c);
            }
        }
    }

    fn text_width(text: &str) -> i32 {
        text.chars().count() as i32 * 6 * SCALE
    }

    /// Text rotated a quarter turn counter-clockwise, centred on (x, y).
    fn vertical_text(&mut self, x: i32, y: i32, text: &str, c: [u8; 3]) {
        let bottom = y + Self::text_width(text) / 2;
        for (i, row, col) in glyph_pixels(text) {
            let cy = bottom - i * 6 * SCALE;
            self.dot(x + row * SCALE, cy - col * SCALE, c);
        }
    }
}

/// The lit pixels of `text` in the 5×7 font: (character index, row, column).
fn glyph_pixels(text: &str) -> impl Iterator<Item = (i32, i32, i32)> + '_ {
    text.chars().enumerate().flat_map(|(i, ch)| {
        let rows = glyph(ch.to_ascii_uppercase());
        (0..7).flat_map(move |row| {
            (0..5)
                .filter(move |col| rows[row] & (0x10 >> col) != 0)
                .map(move |col| (i as i32, row as i32, col))
        })
    })
}

/// Maps data to pixels along one axis.
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Axis {
    fn new(values: impl Iterator<Item = f64>, log: bool) -> Self {
        let finite: Vec<f64> = values
            .filter(|v| v.is_finite() && (!log || *v > 0.0))
            .collect();
        let (mut lo, mut hi) = finite
            .iter()
            .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        if finite.is_empty() {
            (lo, hi) = (1.0, 10.0);
        }
        if log {
            (lo, hi) = (lo.log10().floor(), hi.log10().ceil());
            if hi <= lo {
                hi = lo + 1.0;
            }
        } else {
            let pad = ((hi - lo) * 0.08).max(hi.abs() * 0.05).max(1e-12);
            (lo, hi) = (
                (lo - pad).min(if lo >= 0.0 { 0.0 } else { lo - pad }),
                hi + pad,
            );
        }
        Self { lo, hi, log }
    }

    fn fraction(&self, v: f64) -> f64 {
        let v = if self.log { v.max(1e-300).log10() } else { v };
        (v - self.lo) / (self.hi - self.lo)
    }

    /// Tick positions and labels.
    fn ticks(&self) -> Vec<(f64, String)> {
        if self.log {
            (self.lo as i32..=self.hi as i32)
                .map(|e| (10f64.powi(e), format_number(10f64.powi(e))))
                .collect()
        } else {
            let span = self.hi - self.lo;
            let raw = span / 5.0;
            let magnitude = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * magnitude)
                .find(|s| *s >= raw)
                .unwrap_or(magnitude * 10.0);
            let mut t = (self.lo / step).ceil() * step;
            let mut out = Vec::new();
            while t <= self.hi + step * 1e-9 {
                out.push((t, format_number(t)));
                t += step;
            }
            out
        }
    }
}

fn format_number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.0e}")
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 1.0 {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

impl Plot {
    pub fn render(&self) -> RgbaImage {
        let mut c = Canvas::new();
        let all = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let xa = Axis::new(all().map(|p| p.0), self.log_x);
        let ya = Axis::new(all().map(|p| p.1), self.log_y);
        let (x0, x1) = (LEFT, WIDTH as i32 - RIGHT);
        let (y0, y1) = (HEIGHT as i32 - BOTTOM, TOP);
        let px = |x: f64| x0 + ((x1 - x0) as f64 * xa.fraction(x)).round() as i32;
        let py = |y: f64| y0 + ((y1 - y0) as f64 * ya.fraction(y)).round() as i32;
        let grey = [200, 200, 200];
        let black = [30, 30, 30];
        for (t, label) in xa.ticks() {
            let x = px(t);
            c.line((x, y0), (x, y1), grey);
            c.text(x - Canvas::text_width(&label) / 2, y0 + 8, &label, black);
        }
        for (t, label) in ya.ticks() {
            let y = py(t);
            c.line((x0, y), (x1, y), grey);
            c.text(x0 - 8 - Canvas::text_width(&label), y - 7, &label, black);
        }
        c.line((x0, y0), (x1, y0), black);
        c.line((x0, y0), (x0, y1), black);
        c.line((x1, y0), (x1, y1), black);
        c.line((x0, y1), (x1, y1), black);
        c.text(
            (WIDTH as i32 - Canvas::text_width(&self.title)) / 2,
            12,
            &self.title,
            black,
        );
        c.text(
            (x0 + x1 - Canvas::text_width(&self.x_label)) / 2,
            HEIGHT as i32 - 26,
            &self.x_label,
            black,
        );
        c.vertical_text(8, (y0 + y1) / 2, &self.y_label, black);
        for s in &self.series {
            let points: Vec<(i32, i32)> = s
                .points
                .iter()
                .filter(|(x, y)| {
                    x.is_finite()
                        && y.is_finite()
                        && (!self.log_x || *x > 0.0)
                        && (!self.log_y || *y > 0.0)
                })
                .map(|&(x, y)| (px(x), py(y)))
                .collect();
            if s.line {
                for w in points.windows(2) {
                    c.line(w[0], w[1], s.color);
                }
            }
            for &(x, y) in &points {
                c.square(x, y, 3, s.color);
            }
        }
        if let Some((x, y, label)) = &self.highlight {
            let (hx, hy) = (px(*x), py(*y));
            c.ring(hx, hy, 9, black);
            c.ring(hx, hy, 10, black);
            c.text(hx + 14, hy - 7, label, black);
        }
        // Legend, top right inside the frame.
        let mut ly = y1 + 8;
        for s in &self.series {
            let w = Canvas::text_width(&s.name);
            let lx = x1 - 12 - w;
            c.square(lx - 12, ly + 6, 4, s.color);
            c.text(lx, ly, &s.name, black);
            ly += 20;
        }
        c.image
    }
}

/// Rows of a 5×7 glyph, most significant of the low 5 bits leftmost.
fn glyph(ch: char) -> [u8; 7] {
    match ch {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        'A' => [0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'B' => [0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E],
        'C' => [0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E],
        'D' => [0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C],
        'E' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F],
        'F' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10],
        'G' => [0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F],
        'H' => [0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'I' => [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E],
        'J' => [0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C],
        'K' => [0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11],
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F],
        'M' => [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11],
        'N' => [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11],
        'O' => [0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'P' => [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10],
        'Q' => [0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D],
        'R' => [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11],
        'S' => [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E],
        'T' => [0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04],
        'U' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'V' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04],
        'W' => [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A],
        'X' => [0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11],
        'Y' => [0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04],
        'Z' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F],
        '.' => [0, 0, 0, 0, 0, 0x0C, 0x0C],
        ',' => [0, 0, 0, 0, 0x0C, 0x04, 0x08],
        '-' => [0, 0, 0, 0x1F, 0, 0, 0],
        '+' => [0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0],
        '(' => [0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02],
        ')' => [0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08],
        '/' => [0, 0x01, 0x02, 0x04, 0x08, 0x10, 0],
        '%' => [0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03],
        ':' => [0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0],
        '=' => [0, 0, 0x1F, 0, 0x1F, 0, 0],
        '_' => [0, 0, 0, 0, 0, 0, 0x1F],
        '*' => [0, 0x04, 0x15, 0x0E, 0x15, 0x04, 0],
        '<' => [0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02],
        '>' => [0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08],
        _ => [0; 7],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plot_draws_its_points_where_the_axes_put_them() {
        let plot = Plot {
            title: "T".into(),
            x_label: "X".into(),
            y_label: "Y".into(),
            log_x: true,
            log_y: false,
            series: vec![Series {
                name: "S".into(),
                points: vec![(1.0, 0.0), (100.0, 1.0)],
                color: [255, 0, 0],
                line: true,
            }],
            highlight: None,
        };
        let image = plot.render();
        let red = |x: u32, y: u32| image.pixel(x, y)[..3] == [255, 0, 0];
        // The log axis spans exactly 10^0..10^2: the first point sits on the left edge.
        let left = LEFT as u32;
        let count = (0..HEIGHT).filter(|&y| red(left, y)).count();
        assert!(count > 0, "no point on the left edge");
        // Something red near the right edge too (the second point).
        let right = (WIDTH as i32 - RIGHT) as u32;
        assert!((0..HEIGHT).any(|y| red(right, y)));
    }

    #[test]
    fn number_labels_are_short() {
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(2.5), "2.5");
        assert_eq!(format_number(100.0), "100");
        assert_eq!(format_number(0.001), "0.001");
        assert_eq!(format_number(1e-6), "1e-6");
    }
}
