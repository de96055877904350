//! How far the device's simulation may be from the CPU reference's over one frame, both
//! in f32 running the same steps in the same order, derived from the rounding that
//! Vulkan allows rather than from what one driver happened to give.
//!
//! Vulkan's precision rules (the spec's "Precision and Operation of SPIR-V
//! Instructions"): addition, subtraction and multiplication are correctly rounded (½ ulp),
//! but a compiler may fuse `a * b + c` into one rounding or reorder a sum of products
//! (a dot product, a matrix-vector product); division is within 2.5 ulp, `inversesqrt`
//! within 2 ulp, and `sqrt`, `length` and `normalize` inherit from it. The CPU twin rounds
//! every operation once (½ ulp). So an operation on the two sides may differ by
//! `ULPS_PER_OP` ulps of the value it produces: 1 for ±, × (½ + ½) and for a fused or
//! reordered product sum, per term; 3 for a division or a square root (2.5 + ½).
//!
//! A frame's error is bounded to first order by adding each operation's allowance,
//! measured in ulps of the size of what it rounds: a position's coordinates (the reach R
//! of the scene), or a correction the size of a segment (s). Constraint weights are at
//! most 1, so a correction does not amplify the error it carries. [`frame_budget`]
//! counts the operations of each step of `shaders/simulate.comp` per substep.

use fur_core::sim::SimParams;

/// The unit in the last place of an f32 of magnitude `x` (its exponent's ulp).
pub fn ulp(x: f32) -> f32 {
    f32::EPSILON * 2f32.powi(x.abs().max(f32::MIN_POSITIVE).log2().floor() as i32)
}

/// The largest coordinate of `positions`: the size of what position arithmetic rounds.
pub fn reach(positions: &[glam::Vec3]) -> f32 {
    positions
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f32, f32::max)
}

/// The body a frame is simulated on, for [`frame_budget`].
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Body {
    Rigid,
    /// A skinned body: the strands ride their root poses, and collision also carries
    /// vertices through capsules and (with the skin's blend) the inverse blended matrix.
    Skinned {
        blend: bool,
    },
}

/// Ulps of the value an operation produces by which the device and the CPU twin may
/// differ (see the module's doc): operations are counted in units of ± and ×, with each
/// division or square root counted as three.
const ULPS_PER_OP: f32 = 1.0;

/// Operations per substep that round a position-sized value (ulps of the reach R).
fn position_ops(params: &SimParams, body: Body) -> f32 {
    // A point carried by a 4×4 transform: per coordinate, a 4-term sum of products (7).
    let transform = 7.0;
    let carried = match body {
        Body::Rigid => transform,
        // H (R (x − r) + q): a subtraction, a 3-term product sum (5), an addition, H.
        Body::Skinned { .. } => 1.0 + 5.0 + 1.0 + transform,
    };
    // Riding the root pose (skinned): into the head's frame, the turn, back out.
    let ride = match body {
        Body::Rigid => 0.0,
        Body::Skinned { .. } => transform + carried,
    };
    let integrate = 4.0; // x + (x − p) · r + g h²
    let global = carried + 3.0; // x + (target − x) · S_G
    let local = 2.0 * params.local_iterations as f32; // each correction added to both ends
    let length = 4.0 * params.length_iterations as f32; // two constraints per vertex, ± each
    let wind = 2.0;
    let collision = if params.collision {
        // Into the field's frame, out again, the push added; per projection.
        let projections = match body {
            Body::Rigid => 3.0,
            Body::Skinned { .. } => 1.0,
        };
        let carry_back = match body {
            Body::Skinned { blend: true } => 2.0 * carried + 3.0 * 5.0, // blended inverse
            _ => 0.0,
        };
        projections * (2.0 * transform + 2.0) + carry_back
    } else {
        0.0
    };
    ride + integrate + global + local + length + wind + collision
}

/// Operations per substep that round a correction at most a segment long (ulps of the
/// segment length s), for a strand of `vertices`.
fn correction_ops(params: &SimParams, body: Body, vertices: u32) -> f32 {
    let v = vertices as f32;
    // Local shape: the frame walks root to tip, turned onto each corrected segment (a
    // cross product, a normalisation: 2 + 3 + 3·3 ≈ 14) and applied to the rest vector
    // (5); the frame at vertex i carries i turns.
    let local = params.local_iterations as f32 * (14.0 * v + 5.0);
    // Edge length: a difference, a length (5 + 3), a division (3), a scale (3); twice per
    // vertex per iteration.
    let length = params.length_iterations as f32 * 2.0 * (3.0 + 8.0 + 3.0 + 3.0);
    // Wind: the segment's direction (normalize, 5 + 3), a cone test, the push (4).
    let wind = 12.0;
    let collision = if params.collision {
        // The field: 8 samples blended trilinearly (7 lerps of 3), its gradient (3 × 7),
        // the normal normalised (8), the push and friction (10); per projection.
        let per_projection = 21.0 + 21.0 + 8.0 + 10.0;
        match body {
            Body::Rigid => 3.0 * per_projection,
            // One projection onto the field, then onto the nearest capsules (a segment's
            // closest point: a dot, a division, a clamp, a length: ~20 each, 4 capsules).
            Body::Skinned { .. } => per_projection + 4.0 * 20.0,
        }
    } else {
        0.0
    };
    local + length + wind + collision
}

/// How far the device's positions may be from the CPU twin's after one frame started from
/// the same state: every substep's operations, each within [`ULPS_PER_OP`] of the size it
/// rounds (the scene's reach, or the segment length). A skinned body adds the skinning of
/// the roots the strands ride (the joints' blend and the root frame, both sides from the
/// same clip time): [`skinning_ops`] at the reach.
pub fn frame_budget(
    params: &SimParams,
    body: Body,
    vertices: u32,
    reach: f32,
    segment: f32,
) -> f32 {
    let substeps = params.substeps as f32;
    let skinning = match body {
        Body::Rigid => 0.0,
        Body::Skinned { .. } => skinning_ops() * ulp(reach),
    };
    ULPS_PER_OP
        * (substeps
            * (position_ops(params, body) * ulp(reach)
                + correction_ops(params, body, vertices) * ulp(segment))
            + skinning)
}

/// Operations that round a skinned root pose: four joint matrices blended (4 × 12
/// products summed, per entry 7), the point carried (7), the frame from the skinned
/// normal and tangent (two normalisations and a cross product: 2 × 8 + 3).
fn skinning_ops() -> f32 {
    7.0 + 7.0 + 19.0
}

/// The budget is tied to the arithmetic, not to a driver: checked by hand for the
/// simplest case (a rigid body, one substep, no constraints, no collision).
pub fn check_the_budget_by_hand() {
    let params = SimParams {
        substeps: 1,
        local_iterations: 0,
        length_iterations: 0,
        collision: false,
        ..SimParams::default()
    };
    // Integrate 4 + global (7 + 3) + wind 2 = 16 ulps of the reach; wind's 12 ulps of s.
    let budget = frame_budget(&params, Body::Rigid, 17, 1.0, 0.5);
    let expected = 16.0 * f32::EPSILON + 12.0 * f32::EPSILON / 2.0;
    assert!(
        (budget - expected).abs() <= 1e-3 * expected,
        "budget {budget:e}, by hand {expected:e}"
    );
    assert_eq!(ulp(1.0), f32::EPSILON);
    assert_eq!(ulp(0.75), f32::EPSILON / 2.0);
    assert_eq!(ulp(-3.0), 2.0 * f32::EPSILON);
}
