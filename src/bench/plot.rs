//! The benchmark's charts, drawn with `plotters` into SVG (text stays text, so no font
//! files are needed): scatter or line series on linear or logarithmic axes, with one
//! point ringed (the default settings).

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

use fur_gpu::error::{Error, Result};

const SIZE: (u32, u32) = (760, 480);

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
    /// A point to ring (e.g. the default settings), with its label.
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

/// The range covering `values` (only positive ones on a log axis), padded a little.
fn range(values: impl Iterator<Item = f64>, log: bool) -> std::ops::Range<f64> {
    let kept: Vec<f64> = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .collect();
    let lo = kept.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = kept.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() {
        return if log { 0.1..10.0 } else { 0.0..1.0 };
    }
    if log {
        (lo / 1.25)..(hi * 1.25)
    } else {
        let pad = ((hi - lo) * 0.06).max(1e-9);
        (lo - pad)..(hi + pad)
    }
}

/// A number as a short tick label.
fn format_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let e = a.log10().floor() as i32;
        let m = v / 10f64.powi(e);
        return if (m.round() - m).abs() < 1e-6 {
            format!("{}e{e}", m.round())
        } else {
            format!("{m:.1}e{e}")
        };
    }
    let text = format!("{v:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::parameter(format!("drawing a chart failed: {e}"))
}

impl Plot {
    /// The chart as an SVG document.
    pub fn render(&self) -> Result<String> {
        let all = || self.series.iter().flat_map(|s| s.points.iter());
        let x = range(all().map(|p| p.0), self.log_x);
        let y = range(all().map(|p| p.1), self.log_y);
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            root.fill(&WHITE).map_err(plot_error)?;
            match (self.log_x, self.log_y) {
                (false, false) => self.draw(&root, x, y)?,
                (true, false) => self.draw(&root, x.log_scale(), y)?,
                (false, true) => self.draw(&root, x, y.log_scale())?,
                (true, true) => self.draw(&root, x.log_scale(), y.log_scale())?,
            }
            root.present().map_err(plot_error)?;
        }
        Ok(svg)
    }

    fn draw<X, Y>(
        &self,
        root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
        x: X,
        y: Y,
    ) -> Result<()>
    where
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, ("sans-serif", 20))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(x, y)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&|v| format_number(*v))
            .y_label_formatter(&|v| format_number(*v))
            .draw()
            .map_err(plot_error)?;
        for series in &self.series {
            let [r, g, b] = series.color;
            let color = RGBColor(r, g, b);
            let points: Vec<(f64, f64)> = series
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            if series.line {
                chart
                    .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                    .map_err(plot_error)?;
            }
            chart
                .draw_series(points.iter().map(|p| Circle::new(*p, 4, color.filled())))
                .map_err(plot_error)?
                .label(&series.name)
                .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.filled()));
        }
        if let Some((x, y, label)) = &self.highlight {
            chart
                .draw_series([Circle::new((*x, *y), 9, BLACK.stroke_width(2))])
                .map_err(plot_error)?;
            chart
                .draw_series([Text::new(
                    label.clone(),
                    (*x, *y),
                    ("sans-serif", 14).into_font().color(&BLACK),
                )])
                .map_err(plot_error)?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(plot_error)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chart_is_an_svg_with_its_labels_and_points() {
        let plot = Plot {
            title: "Error against cost".into(),
            x_label: "ms".into(),
            y_label: "error".into(),
            log_x: true,
            log_y: false,
            series: vec![Series {
                name: "settings".into(),
                points: vec![(1.0, 0.5), (10.0, 0.25), (100.0, 0.125)],
                color: [255, 0, 0],
                line: true,
            }],
            highlight: Some((10.0, 0.25, "default".into())),
        };
        let svg = plot.render().unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        for text in ["Error against cost", "ms", "error", "settings", "default"] {
            assert!(svg.contains(text), "missing `{text}`");
        }
        // Three points, the legend's marker, and the ring.
        assert!(svg.matches("<circle").count() >= 5);
        // The log axis is labelled at decades.
        let labels: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| t.split("</text>").next()?.rsplit('>').next())
            .map(str::trim)
            .collect();
        for decade in ["1", "10", "100"] {
            assert!(labels.contains(&decade), "no label {decade}: {labels:?}");
        }
    }

    #[test]
    fn number_labels_are_short() {
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(2.5), "2.5");
        assert_eq!(format_number(100.0), "100");
        assert_eq!(format_number(0.001), "0.001");
        assert_eq!(format_number(1e-6), "1e-6");
        assert_eq!(format_number(2.5e7), "2.5e7");
    }
}
