//! Error metrics and statistics the benchmark reports.

use glam::{DVec3, Vec3};

use fur_core::render::RgbaImage;

/// How many frames a measurement draws: the warm-up frames first, untimed, then the
/// measured ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frames {
    pub warm: usize,
    pub measured: usize,
}

impl Frames {
    /// One frame, for its image: no warm-up.
    pub const STILL: Frames = Frames {
        warm: 0,
        measured: 1,
    };
}

/// The median (NaN for no values). NaNs sort last.
pub fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Root-mean-square difference of the RGB channels, on a 0..1 scale.
pub fn rmse(a: &RgbaImage, b: &RgbaImage) -> f64 {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "images differ in size"
    );
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for (pa, pb) in a.data.chunks_exact(4).zip(b.data.chunks_exact(4)) {
        for c in 0..3 {
            let d = (f64::from(pa[c]) - f64::from(pb[c])) / 255.0;
            sum += d * d;
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

/// Mean and maximum distance between corresponding positions, divided by `scale`.
pub fn position_error(a: &[Vec3], b: &[DVec3], scale: f64) -> (f64, f64) {
    assert_eq!(a.len(), b.len(), "position counts differ");
    let mut sum = 0.0;
    let mut max = 0.0f64;
    for (p, q) in a.iter().zip(b) {
        let d = (p.as_dvec3() - *q).length();
        sum += d;
        max = max.max(d);
    }
    (sum / a.len().max(1) as f64 / scale, max / scale)
}

/// Largest |segment length / rest length − 1| over strands of `v` vertices.
pub fn max_stretch(positions: &[Vec3], rest_lengths: &[f64], v: usize) -> f64 {
    let mut worst = 0.0f64;
    for (strand, rest) in positions.chunks(v).zip(rest_lengths.chunks(v)) {
        for i in 1..v {
            if rest[i] > 0.0 {
                let now = f64::from((strand[i] - strand[i - 1]).length());
                worst = worst.max((now / rest[i] - 1.0).abs());
            }
        }
    }
    worst
}

pub use fur_core::render::flip;

/// Which points are on the Pareto front of (cost, error): no other point is at most as
/// costly and at most as wrong while better in one of the two.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            !points
                .iter()
                .any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(pixels: &[[u8; 4]], width: u32) -> RgbaImage {
        RgbaImage {
            width,
            height: pixels.len() as u32 / width,
            data: pixels.iter().flatten().copied().collect(),
        }
    }

    #[test]
    fn median_of_odd_even_and_empty() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn rmse_of_known_images() {
        let black = image(&[[0, 0, 0, 255]; 4], 2);
        let white = image(&[[255, 255, 255, 255]; 4], 2);
        assert_eq!(rmse(&black, &black), 0.0);
        assert!((rmse(&black, &white) - 1.0).abs() < 1e-12);
        // One of four pixels fully different: sqrt(1/4) = 0.5.
        let one = image(
            &[
                [255, 255, 255, 255],
                [0, 0, 0, 255],
                [0, 0, 0, 255],
                [0, 0, 0, 255],
            ],
            2,
        );
        assert!((rmse(&black, &one) - 0.5).abs() < 1e-12);
        // Alpha is ignored.
        let clear = image(&[[0, 0, 0, 0]; 4], 2);
        assert_eq!(rmse(&black, &clear), 0.0);
    }

    #[test]
    fn flip_is_zero_for_equal_images_and_grows_with_the_difference() {
        let grey = image(&[[128, 128, 128, 255]; 64], 8);
        let mut speck = grey.clone();
        speck.data[4 * 27..4 * 27 + 3].copy_from_slice(&[255, 255, 255]);
        let white = image(&[[255, 255, 255, 255]; 64], 8);
        assert_eq!(flip(&grey, &grey), 0.0);
        let small = flip(&grey, &speck);
        let large = flip(&grey, &white);
        assert!(
            small > 0.0 && small < large && large <= 1.0,
            "{small} {large}"
        );
    }

    #[test]
    fn position_error_and_stretch_of_known_strands() {
        let a = [Vec3::ZERO, Vec3::X, Vec3::new(3.0, 0.0, 0.0)];
        let b = [DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0)];
        let (mean, max) = position_error(&a, &b, 2.0);
        assert!((mean - 1.0 / 3.0 / 2.0).abs() < 1e-12);
        assert!((max - 0.5).abs() < 1e-12);
        // Segments of 1 and 2 against rest lengths 1 and 1: the second is stretched 100 %.
        assert!((max_stretch(&a, &[0.0, 1.0, 1.0], 3) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let points = [(1.0, 5.0), (2.0, 3.0), (3.0, 3.5), (4.0, 1.0), (4.0, 2.0)];
        assert_eq!(pareto_front(&points), vec![true, true, false, true, false]);
    }
}

/// Depths inside a closed body, accumulated over samples: the sum, the count and the
/// deepest, from exact point-to-mesh distances.
#[derive(Clone, Copy, Debug, Default)]
pub struct Depths {
    sum: f64,
    count: usize,
    max: f64,
}

impl Depths {
    /// Adds the depth of every point of `points` inside `surface` (0 outside).
    pub fn add(&mut self, surface: &fur_core::scene::Mesh, points: &[glam::Vec3]) {
        for d in fur_core::geometry::sdf::exact_distances(surface, points) {
            let depth = f64::from((-d).max(0.0));
            self.sum += depth;
            self.count += 1;
            self.max = self.max.max(depth);
        }
    }

    /// (mean, max) depth as fractions of `length`.
    pub fn relative_to(&self, length: f64) -> (f64, f64) {
        (
            self.sum / self.count.max(1) as f64 / length,
            self.max / length,
        )
    }
}
