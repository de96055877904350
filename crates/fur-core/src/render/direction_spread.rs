//! How far the directions of a coat's neighbouring hairs differ: the mean squared angle
//! between the segments of different hairs that lie near each other. The Marschner
//! model's multiple scattering widens by it ([`super::Fibre::direction_spread`],
//! [`super::dual_scattering::node`]); this measures it on drawn hairs, so the default
//! can be checked against the hairs it lights (`tests/truth`, and the truth benchmark
//! reports it per scene).

use std::collections::HashMap;

use glam::{IVec3, Vec3};

/// Segments measured at most (every k-th of the coat's, in order); their neighbours
/// are all the segments near them.
const SAMPLED: usize = 4096;

/// The mean squared angle (rad²) between the directions of neighbouring segments of
/// different hairs, each hair `per_strand` consecutive points of `points`: two
/// segments are neighbours when their midpoints lie within the coat's median segment
/// length of each other. Directions are unsigned (a hair and its reverse are
/// parallel), so an angle is at most π/2 and the spread at most π²/4. `None` when no
/// segment has a neighbour (one hair, or none) or a hair has fewer than two points.
pub fn direction_spread(points: &[Vec3], per_strand: usize) -> Option<f64> {
    if per_strand < 2 {
        return None;
    }
    let mut segments = Vec::new();
    for (hair, strand) in points.chunks_exact(per_strand).enumerate() {
        for pair in strand.windows(2) {
            let d = pair[1] - pair[0];
            let length = d.length();
            if length > 0.0 && length.is_finite() {
                segments.push((hair, 0.5 * (pair[0] + pair[1]), d / length, length));
            }
        }
    }
    let mut lengths: Vec<f32> = segments.iter().map(|s| s.3).collect();
    if lengths.is_empty() {
        return None;
    }
    let middle = lengths.len() / 2;
    let (_, &mut radius, _) = lengths.select_nth_unstable_by(middle, f32::total_cmp);
    // Clamped far inside i32, so that a neighbouring cell's index cannot overflow.
    let cell = |p: Vec3| {
        (p / radius)
            .floor()
            .clamp(Vec3::splat(-1e9), Vec3::splat(1e9))
            .as_ivec3()
    };
    let mut grid: HashMap<IVec3, Vec<usize>> = HashMap::new();
    for (i, s) in segments.iter().enumerate() {
        grid.entry(cell(s.1)).or_default().push(i);
    }
    // A step that shares no factor with the segments a hair has, so that the samples
    // fall at every place along the hairs, not at the same few.
    let mut step = segments.len().div_ceil(SAMPLED).max(1);
    while step > 1 && gcd(step, per_strand - 1) != 1 {
        step += 1;
    }
    let (mut sum, mut pairs) = (0.0f64, 0u64);
    for &(hair, mid, dir, _) in segments.iter().step_by(step) {
        let at = cell(mid);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(near) = grid.get(&(at + IVec3::new(dx, dy, dz))) else {
                        continue;
                    };
                    for &j in near {
                        let (other, m, d, _) = segments[j];
                        if other != hair && m.distance(mid) <= radius {
                            let angle = f64::from(dir.dot(d).abs().min(1.0)).acos();
                            sum += angle * angle;
                            pairs += 1;
                        }
                    }
                }
            }
        }
    }
    (pairs > 0).then(|| sum / pairs as f64)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hairs side by side, `per_strand` points each, the i-th leaning by `lean(i)`
    /// radians in the x–y plane.
    fn coat(hairs: usize, lean: impl Fn(usize) -> f32) -> Vec<Vec3> {
        let mut points = Vec::new();
        for i in 0..hairs {
            let root = Vec3::new(0.07 * i as f32, 0.0, 0.0);
            let dir = Vec3::new(lean(i).sin(), lean(i).cos(), 0.0);
            points.extend((0..8).map(|k| root + 0.1 * k as f32 * dir));
        }
        points
    }

    /// Parallel hairs spread by nothing; hairs leaning alternately by ±a spread by
    /// (2a)² (every neighbour pair differs by 2a; each hair's own segments are not
    /// its neighbours, or the spread would be diluted towards 0); a hair reversed is
    /// parallel; one hair or none has no spread. Seen failing against signed
    /// directions (the reversed hairs measured π²) and against counting a hair's own
    /// segments as neighbours.
    #[test]
    fn the_spread_is_the_mean_squared_angle_between_neighbouring_hairs() {
        let parallel = coat(20, |_| 0.0);
        assert_eq!(direction_spread(&parallel, 8), Some(0.0));
        let a = 0.1f32;
        let zigzag = coat(20, |i| if i % 2 == 0 { a } else { -a });
        let s = direction_spread(&zigzag, 8).unwrap();
        let expected = f64::from(2.0 * a).powi(2);
        assert!((s - expected).abs() < 0.02 * expected, "{s} vs {expected}");
        let mut reversed = parallel.clone();
        for hair in reversed.chunks_exact_mut(8).step_by(2) {
            hair.reverse();
        }
        assert!(direction_spread(&reversed, 8).unwrap() < 1e-6);
        assert_eq!(direction_spread(&coat(1, |_| 0.3), 8), None);
        assert_eq!(direction_spread(&[], 8), None);
        assert_eq!(direction_spread(&parallel, 1), None);
    }

    /// A coat too large to measure whole is sampled all along its hairs: hairs whose
    /// tips alone lean measure the spread of their tips' share of the segments. Seen
    /// failing with a sampling step that was a multiple of the segments a hair has
    /// (every sample a root segment: no spread).
    #[test]
    fn a_sampled_coat_is_measured_all_along_its_hairs() {
        // 4,800 hairs of 8 segments (9 points): 38,400 segments, a step of 10 → 11.
        let mut points = Vec::new();
        for i in 0..4800 {
            let root = Vec3::new(0.07 * (i % 80) as f32, 0.0, 0.07 * (i / 80) as f32);
            let lean = if i % 2 == 0 { 0.1f32 } else { -0.1 };
            for k in 0..9 {
                // The last segment leans; the rest stand straight.
                let up = Vec3::new(0.0, 0.1 * k.min(8) as f32, 0.0);
                let tip = if k == 8 {
                    Vec3::new(0.1 * lean.sin(), 0.1 * lean.cos() - 0.1, 0.0)
                } else {
                    Vec3::ZERO
                };
                points.push(root + up + tip);
            }
        }
        let s = direction_spread(&points, 9).unwrap();
        assert!(s > 0.001, "the tips' lean is not measured: {s}");
    }
}
