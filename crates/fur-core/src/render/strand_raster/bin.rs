//! Which screen tiles a segment can touch: the rows of tiles its widened axis crosses,
//! and in each row the columns between the ends of the part of the axis inside it.
//! Exact to within the widening, so a long diagonal segment is not charged for the
//! empty corners of its bounding box.

/// The tiles (column, row) the segment `a`–`b` can cover when widened by `radius`
/// pixels on every side, inside a grid of `columns` × `rows` tiles of `tile` pixels.
/// Calls `visit` once per tile, row by row.
pub fn tiles_touched(
    a: [f32; 2],
    b: [f32; 2],
    radius: f32,
    tile: u32,
    columns: u32,
    rows: u32,
    mut visit: impl FnMut(u32, u32),
) {
    let size = tile as f32;
    let y_lo = a[1].min(b[1]) - radius;
    let y_hi = a[1].max(b[1]) + radius;
    if !(y_lo.is_finite() && y_hi.is_finite() && a[0].is_finite() && b[0].is_finite()) {
        return;
    }
    let first_row = (y_lo / size).floor().max(0.0);
    let last_row = (y_hi / size).floor().min(rows as f32 - 1.0);
    if first_row > last_row {
        return;
    }
    for row in first_row as u32..=last_row as u32 {
        // The part of the axis within this row's band, widened vertically.
        let band = (row as f32 * size - radius, (row + 1) as f32 * size + radius);
        let (x0, x1) = axis_x_range(a, b, band.0, band.1);
        let first_col = ((x0 - radius) / size).floor().max(0.0);
        let last_col = ((x1 + radius) / size).floor().min(columns as f32 - 1.0);
        if first_col > last_col {
            continue;
        }
        for column in first_col as u32..=last_col as u32 {
            visit(column, row);
        }
    }
}

/// The x-range of the segment `a`–`b` clipped to `lo ≤ y ≤ hi`.
fn axis_x_range(a: [f32; 2], b: [f32; 2], lo: f32, hi: f32) -> (f32, f32) {
    let dy = b[1] - a[1];
    if dy.abs() < 1e-6 {
        return (a[0].min(b[0]), a[0].max(b[0]));
    }
    let at = |y: f32| {
        let t = ((y - a[1]) / dy).clamp(0.0, 1.0);
        a[0] + (b[0] - a[0]) * t
    };
    let (p, q) = (at(lo), at(hi));
    (p.min(q), p.max(q))
}
