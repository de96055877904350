//! USD's curve bases evaluated to polylines: linear, and the cubic Bézier, B-spline
//! and Catmull–Rom bases, non-periodic or pinned (USD's `wrap`), with the per-vertex
//! data (widths, colours) carried the way USD interpolates each kind.

use glam::Vec3;

use super::CUBIC_SAMPLES;

/// What a curve's values must do to be evaluated: points and scalars alike.
pub trait Blend:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<f32, Output = Self>
{
}

impl<T> Blend for T where
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<f32, Output = T>
{
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Linear,
    Bezier,
    BSpline { pinned: bool },
    CatmullRom { pinned: bool },
}

/// Where one curve lies in a curves prim's arrays.
#[derive(Clone, Copy, Debug)]
pub struct CurveAt {
    /// The curve's index in the prim.
    pub index: usize,
    /// Its first control point, and how many it has.
    pub first: usize,
    pub count: usize,
    /// Where its `varying` values start.
    pub varying_at: usize,
}

impl Shape {
    pub fn new(curve_type: &str, basis: &str, wrap: &str) -> Result<Self, String> {
        let pinned = wrap == "pinned";
        if !matches!(wrap, "nonperiodic" | "pinned") {
            return Err(format!("unknown `wrap` \"{wrap}\""));
        }
        Ok(match (curve_type, basis) {
            ("linear", _) => Self::Linear,
            ("cubic", "bezier") => Self::Bezier,
            ("cubic", "bspline") => Self::BSpline { pinned },
            ("cubic", "catmullRom") => Self::CatmullRom { pinned },
            ("cubic", other) => return Err(format!("unknown cubic `basis` \"{other}\"")),
            (other, _) => return Err(format!("unknown curve `type` \"{other}\"")),
        })
    }

    pub fn is_cubic(&self) -> bool {
        *self != Self::Linear
    }

    /// How many segments a curve of `count` control points has.
    pub fn segments(&self, count: usize) -> Result<usize, String> {
        let cubic_min = |min: usize| {
            if count < min {
                Err(format!(
                    "a cubic curve of {count} control points (at least {min})"
                ))
            } else {
                Ok(())
            }
        };
        match self {
            Self::Linear => Ok(count - 1),
            Self::Bezier => {
                cubic_min(4)?;
                if (count - 1) % 3 != 0 {
                    return Err(format!(
                        "a Bézier curve of {count} control points (3n + 1 make n segments)"
                    ));
                }
                Ok((count - 1) / 3)
            }
            Self::BSpline { pinned: true } | Self::CatmullRom { pinned: true } => Ok(count - 1),
            Self::BSpline { .. } | Self::CatmullRom { .. } => {
                cubic_min(4)?;
                Ok(count - 3)
            }
        }
    }

    /// The control points with a pinned curve's phantom ends added.
    fn extended<T: Blend>(&self, cvs: &[T]) -> Vec<T> {
        match self {
            Self::BSpline { pinned: true } | Self::CatmullRom { pinned: true } => {
                let n = cvs.len();
                let mut v = Vec::with_capacity(n + 2);
                v.push(cvs[0] * 2.0 - cvs[1]);
                v.extend_from_slice(cvs);
                v.push(cvs[n - 1] * 2.0 - cvs[n - 2]);
                v
            }
            _ => cvs.to_vec(),
        }
    }

    /// The curve through `cvs` as a polyline (a linear curve is returned as it is).
    pub fn evaluate(&self, cvs: &[Vec3]) -> Result<Vec<Vec3>, String> {
        self.evaluate_any(cvs)
    }

    fn evaluate_any<T: Blend>(&self, cvs: &[T]) -> Result<Vec<T>, String> {
        let segments = self.segments(cvs.len())?;
        if *self == Self::Linear {
            return Ok(cvs.to_vec());
        }
        let p = self.extended(cvs);
        let step = if *self == Self::Bezier { 3 } else { 1 };
        let mut out = Vec::with_capacity(segments * CUBIC_SAMPLES + 1);
        for s in 0..segments {
            let q = &p[s * step..s * step + 4];
            for k in 0..CUBIC_SAMPLES {
                out.push(self.at(q, k as f32 / CUBIC_SAMPLES as f32));
            }
        }
        let q = &p[(segments - 1) * step..(segments - 1) * step + 4];
        out.push(self.at(q, 1.0));
        Ok(out)
    }

    fn at<T: Blend>(&self, q: &[T], t: f32) -> T {
        let s = 1.0 - t;
        let w = match self {
            Self::Bezier => [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t],
            Self::BSpline { .. } => [
                s * s * s / 6.0,
                (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
                (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
                t * t * t / 6.0,
            ],
            Self::CatmullRom { .. } => [
                0.5 * (-t + 2.0 * t * t - t * t * t),
                0.5 * (2.0 - 5.0 * t * t + 3.0 * t * t * t),
                0.5 * (t + 4.0 * t * t - 3.0 * t * t * t),
                0.5 * (-t * t + t * t * t),
            ],
            Self::Linear => [s, t, 0.0, 0.0],
        };
        q[0] * w[0] + q[1] * w[1] + q[2] * w[2] + q[3] * w[3]
    }

    /// Where each curve's `varying` values start: one value per segment end.
    pub fn varying_starts(&self, counts: &[usize]) -> Result<Vec<usize>, String> {
        let mut at = 0;
        counts
            .iter()
            .map(|&c| {
                let s = at;
                at += self.segments(c)? + 1;
                Ok(s)
            })
            .collect()
    }

    /// How many values a primvar of `interpolation` must have, exactly, on a prim of
    /// curves of `counts` control points (USD's rule: one for `constant`, one per curve
    /// for `uniform`, one per control point for `vertex`, one per segment end for
    /// `varying` and `faceVarying`).
    pub fn values_needed(&self, interpolation: &str, counts: &[usize]) -> Result<usize, String> {
        Ok(match interpolation {
            "constant" => 1,
            "uniform" => counts.len(),
            "vertex" => counts.iter().sum(),
            "varying" | "faceVarying" => counts
                .iter()
                .map(|&c| self.segments(c).map(|s| s + 1))
                .sum::<Result<usize, String>>()?,
            other => return Err(format!("an unknown interpolation \"{other}\"")),
        })
    }

    /// A curve's values of a primvar (`values` for the whole prim, with USD's
    /// `interpolation`) at each vertex of its polyline, the curve lying at `curve` in
    /// the prim's arrays.
    pub fn per_vertex(
        &self,
        values: &[f32],
        interpolation: &str,
        curve: CurveAt,
        what: &str,
    ) -> Result<Vec<f32>, String> {
        let CurveAt {
            index: c,
            first: start,
            count,
            varying_at,
        } = curve;
        let segments = self.segments(count)?;
        let vertices = if self.is_cubic() {
            segments * CUBIC_SAMPLES + 1
        } else {
            count
        };
        let short = |needed: usize| {
            format!(
                "`{what}` ({interpolation}) has {} values, too few for curve {c} (needs {needed})",
                values.len()
            )
        };
        match interpolation {
            "constant" => values
                .first()
                .map(|&v| vec![v; vertices])
                .ok_or_else(|| short(1)),
            "uniform" => values
                .get(c)
                .map(|&v| vec![v; vertices])
                .ok_or_else(|| short(c + 1)),
            "vertex" => {
                let cvs = values
                    .get(start..start + count)
                    .ok_or_else(|| short(start + count))?;
                let lifted: Vec<Vec3> = cvs.iter().map(|&v| Vec3::new(v, 0.0, 0.0)).collect();
                Ok(self.evaluate_any(&lifted)?.iter().map(|v| v.x).collect())
            }
            "varying" | "faceVarying" => {
                let ends = values
                    .get(varying_at..varying_at + segments + 1)
                    .ok_or_else(|| short(varying_at + segments + 1))?;
                if !self.is_cubic() {
                    return Ok(ends.to_vec());
                }
                let mut out = Vec::with_capacity(vertices);
                for s in 0..segments {
                    for k in 0..CUBIC_SAMPLES {
                        let t = k as f32 / CUBIC_SAMPLES as f32;
                        out.push(ends[s] * (1.0 - t) + ends[s + 1] * t);
                    }
                }
                out.push(ends[segments]);
                Ok(out)
            }
            other => Err(format!("`{what}` has an unknown interpolation \"{other}\"")),
        }
    }
}
