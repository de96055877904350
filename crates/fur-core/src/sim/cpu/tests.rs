//! The wind's push, worked out by hand.

use super::*;

/// The wind's push on a vertex is the part of the wind across the hair there: along
/// the segment to the next vertex, or from the previous one at the tip; none on a
/// segment of no length. On the bent strand (0, 0, 0), (0, 1, 0), (1, 2, 0) a wind
/// along x pushes the root fully, the middle and the tip by (½, −½, 0). Seen failing
/// with the tangent taken from the wrong neighbour and with either difference summed.
#[test]
fn the_wind_pushes_across_the_hair() {
    let x = [
        V3::<f64>(0.0, 0.0, 0.0),
        V3::<f64>(0.0, 1.0, 0.0),
        V3::<f64>(1.0, 2.0, 0.0),
    ];
    let w = V3::<f64>(1.0, 0.0, 0.0);
    let close = |a: V3<f64>, b: V3<f64>| (a - b).max_abs() < 1e-12;
    assert!(close(wind_push(&x, 0, w), V3(1.0, 0.0, 0.0)));
    assert!(close(wind_push(&x, 1, w), V3(0.5, -0.5, 0.0)));
    assert!(close(wind_push(&x, 2, w), V3(0.5, -0.5, 0.0)));
    let folded = [x[0], x[0], x[2]];
    assert_eq!(wind_push(&folded, 0, w), V3::ZERO);
}
