//! How much of a pixel a strand segment covers: the exact area, in closed form.
//!
//! A segment is a quadrilateral: its axis from `a` to `b` (pixels), its width across,
//! tapering linearly from `a`'s to `b`'s. A pixel is a unit square. The pixel's share
//! is the area of the quadrilateral inside the square, found as fonts are rasterised
//! exactly: each edge, clipped to the pixel's rows, adds the signed area between it and
//! the pixel's right side, clamped to the pixel's columns; the four sum to the area.
//! Exact for every angle and width, so the shares of all pixels sum to the segment's
//! area (a strand neither brightens nor darkens as it turns), and a strand under a
//! pixel wide covers its pixels by its width: thin hairs fade instead of flickering.

/// Where a pixel lies against a segment, and how much of it the segment covers.
#[derive(Clone, Copy, Debug)]
pub struct Footprint {
    /// The pixel's area inside the segment, 0 to 1.
    pub coverage: f32,
    /// The parameter (0 at `a`, 1 at `b`) of the axis point nearest the pixel's
    /// centre, clamped to the segment: where its depth, colour and width are read.
    pub t: f32,
}

/// The mean of `x` clamped to `[lo, hi]` as `x` runs evenly from `p` to `q`.
fn mean_clamped(p: f32, q: f32, lo: f32, hi: f32) -> f32 {
    let (u, v) = (p.min(q), p.max(q));
    let span = v - u;
    if span < 1e-6 {
        return (0.5 * (p + q)).clamp(lo, hi);
    }
    let below = (lo.min(v) - u).max(0.0);
    let above = (v - hi.max(u)).max(0.0);
    let (m, n) = (u.max(lo), v.min(hi));
    let inside = if n > m { 0.5 * (n * n - m * m) } else { 0.0 };
    (lo * below + inside + hi * above) / span
}

/// The signed area between the edge `p`→`q` and the right side `x = x1` of the pixel
/// `[x0, x1] × [y0, y1]`, within the pixel's rows, with x clamped to its columns.
fn edge_area(p: [f32; 2], q: [f32; 2], x0: f32, x1: f32, y0: f32, y1: f32) -> f32 {
    let dy = q[1] - p[1];
    if dy == 0.0 {
        return 0.0;
    }
    let ya = y0.max(p[1].min(q[1]));
    let yb = y1.min(p[1].max(q[1]));
    if yb <= ya {
        return 0.0;
    }
    let slope = (q[0] - p[0]) / dy;
    let x_at = |y: f32| p[0] + (y - p[1]) * slope;
    let mean = mean_clamped(x_at(ya), x_at(yb), x0, x1);
    dy.signum() * (yb - ya) * (x1 - mean)
}

/// The coverage of the pixel centred at `centre` by the segment `a`–`b` of widths
/// `width_a`, `width_b` (all in pixels). A segment shorter than a thousandth of a
/// pixel covers nothing (its neighbours along the strand cover its pixels).
pub fn footprint(
    centre: [f32; 2],
    a: [f32; 2],
    b: [f32; 2],
    width_a: f32,
    width_b: f32,
) -> Footprint {
    let d = [b[0] - a[0], b[1] - a[1]];
    let length = (d[0] * d[0] + d[1] * d[1]).sqrt();
    // NaN lengths (from non-finite ends) fail the comparison and cover nothing.
    if length.is_nan() || length < 1e-3 {
        return Footprint {
            coverage: 0.0,
            t: 0.0,
        };
    }
    let u = [d[0] / length, d[1] / length];
    let n = [-u[1], u[0]];
    let p = [centre[0] - a[0], centre[1] - a[1]];
    let s = p[0] * u[0] + p[1] * u[1];
    let across = p[0] * n[0] + p[1] * n[1];
    let t = (s / length).clamp(0.0, 1.0);
    // A pixel's corners lie within half a diagonal of its centre.
    let reach = std::f32::consts::FRAC_1_SQRT_2;
    let half = 0.5 * width_a.max(width_b);
    if across.abs() >= half + reach || s <= -reach || s >= length + reach {
        return Footprint { coverage: 0.0, t };
    }
    // The quadrilateral relative to the pixel's centre, counter-clockwise or clockwise
    // (the sum's sign says which; its size is the area).
    let corner = |from: [f32; 2], w: f32, side: f32| {
        [
            from[0] - centre[0] + side * 0.5 * w * n[0],
            from[1] - centre[1] + side * 0.5 * w * n[1],
        ]
    };
    let quad = [
        corner(a, width_a, -1.0),
        corner(b, width_b, -1.0),
        corner(b, width_b, 1.0),
        corner(a, width_a, 1.0),
    ];
    let mut area = 0.0;
    for i in 0..4 {
        area += edge_area(quad[i], quad[(i + 1) % 4], -0.5, 0.5, -0.5, 0.5);
    }
    Footprint {
        coverage: area.abs().min(1.0),
        t,
    }
}
