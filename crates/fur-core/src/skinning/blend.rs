//! The skin's blend of bones around the rest body, for collision: which bones, with
//! which weights, move the skin nearest each grid point of the rest field, so a strand
//! vertex can be carried back to the rest pose through the same blend that moved the
//! skin beside it (`Collider::push_out_skinned` in src/sim/collide.rs, `blend_back` in
//! `shaders/simulate.comp`).
//!
//! A strand's root pose is rigid; where the skin bends between two bones (a paw folding
//! against its leg), the skin near a hair's tip moves with a different blend than its
//! root, and the rest field carried by the root pose misplaces it. Linear blend
//! skinning maps a rest point `r` with the skin's weights `w` to `Σ wₖ Kₖ r`; a strand
//! vertex near that skin is carried back by the inverse of the same blended matrix.
//! Each grid point keeps the two heaviest bones of its skin, their weights scaled to
//! sum to one: where skin bends, it bends between two bones, and each bone read costs
//! the kernel three gathers (docs/benchmark.md measured the same depths with two as
//! with four, at less cost).

use glam::{Mat4, Vec3, Vec4};

use crate::error::{Error, Result};
use crate::geometry::{Real, Sdf, V3};
use crate::scene::Rig;

/// One grid point's blend, packed as the kernel reads it (a `uvec2`): the heaviest and
/// the second heaviest joint's indices (16 bits each), then the heaviest's share of
/// their two weights as f32 bits (the second's is one minus it). All zero: no skin
/// within reach, the root pose carries the vertex.
pub type Packed = [u32; 2];

/// The two joint indices and the heaviest's share of a packed blend.
pub fn unpack(p: Packed) -> ([u32; 2], f32) {
    ([p[0] & 0xffff, p[0] >> 16], f32::from_bits(p[1]))
}

/// How far from the rest surface a grid point's blend is kept, for hair of
/// `hair_length`: a strand vertex lies within a hair's length of its root, and the root
/// pose carries it back within about that of the rest surface.
pub fn band(hair_length: f32) -> f32 {
    0.5 * hair_length
}

/// Packs the two heaviest of a vertex's four influences (ties: the earlier), the
/// heaviest's weight as its share of the two. A vertex with no weight packs as zero.
fn pack(joints: [u16; 4], weights: [f32; 4]) -> Packed {
    let mut order = [0usize, 1, 2, 3];
    order.sort_by(|&a, &b| weights[b].total_cmp(&weights[a]).then(a.cmp(&b)));
    let [first, second] = [order[0], order[1]];
    let (w0, w1) = (weights[first].max(0.0), weights[second].max(0.0));
    if w0 <= 0.0 {
        return [0, 0];
    }
    let share = w0 / (w0 + w1);
    let second = if w1 > 0.0 {
        joints[second]
    } else {
        joints[first]
    };
    [
        u32::from(joints[first]) | u32::from(second) << 16,
        share.to_bits(),
    ]
}

/// Blend grid points per field cell along each axis: the skin's weights change within a
/// field cell where the skin bends (a paw's edge).
pub const REFINE: u32 = 2;

/// The blend grid's points along x, y, z over `field`'s box: [`REFINE`] per field cell.
pub fn dims(field: &Sdf) -> [u32; 3] {
    field.dims.map(|n| (n - 1) * REFINE + 1)
}

/// Bytes the blend grid over `field` takes on the device: 8 per point, two points along
/// x to a 16-byte texel.
pub fn bytes(field: &Sdf) -> usize {
    let [nx, ny, nz] = dims(field);
    nx.div_ceil(2) as usize * ny as usize * nz as usize * 16
}

/// The index of the blend grid point nearest to `p` (x fastest, then y, then z); None
/// outside the grid. The kernel's `blend_back` picks it with the same arithmetic.
pub fn nearest<T: Real>(field: &Sdf, p: V3<T>) -> Option<usize> {
    let inv = T::from_f32(1.0 / field.cell) * T::from_f32(REFINE as f32);
    let o = V3::<T>::from_vec3(field.origin);
    let g = [(p.0 - o.0) * inv, (p.1 - o.1) * inv, (p.2 - o.2) * inv];
    let [nx, ny, nz] = dims(field);
    let inside = g
        .iter()
        .zip([nx, ny, nz])
        .all(|(&x, n)| x >= T::ZERO && x <= T::from_f32((n - 1) as f32));
    if !inside {
        return None;
    }
    let c = g.map(|x| (x + T::HALF).to_f64().floor() as u32);
    Some((c[0] + nx * (c[1] + ny * c[2])) as usize)
}

/// Per blend grid point over `field` (see [`dims`]), the blend of the rest-posed skin
/// vertex (`rest`, vertex-aligned with `rig`) nearest to it, for the points within
/// `band` of the surface; zero elsewhere. A bucket grid of the vertices keeps this to
/// the points near each.
pub fn grid(rig: &Rig, rest: &[Vec3], field: &Sdf, band: f32) -> Vec<Packed> {
    let step = field.cell / REFINE as f32;
    let bucket = (2.0 * field.cell).max(f32::MIN_POSITIVE);
    let key = |p: Vec3| ((p - field.origin) / bucket).floor().as_ivec3();
    let mut buckets: std::collections::HashMap<glam::IVec3, Vec<u32>> = Default::default();
    for (i, &p) in rest.iter().enumerate() {
        buckets.entry(key(p)).or_default().push(i as u32);
    }
    let [nx, ny, nz] = dims(field);
    let mut out = vec![[0u32; 2]; (nx * ny * nz) as usize];
    // Rings of buckets beyond which no vertex can be nearer than the band.
    let max_ring = (band / bucket).ceil() as i32 + 1;
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let at = (x + nx * (y + ny * z)) as usize;
                let p = field.origin + Vec3::new(x as f32, y as f32, z as f32) * step;
                let near = field
                    .sample::<f32>(V3::from_vec3(p))
                    .is_some_and(|(d, _)| d.abs() <= band);
                if !near {
                    continue;
                }
                let centre = key(p);
                let mut best: Option<(f32, u32)> = None;
                for ring in 0..=max_ring {
                    // A vertex in ring r lies at least (r − 1) buckets away.
                    if let Some((d, _)) = best {
                        if d < (ring - 1) as f32 * bucket {
                            break;
                        }
                    }
                    for_ring(centre, ring, |k| {
                        for &i in buckets.get(&k).map_or(&[][..], |v| v.as_slice()) {
                            let d = rest[i as usize].distance(p);
                            if best.is_none_or(|(b, j)| d < b || (d == b && i < j)) {
                                best = Some((d, i));
                            }
                        }
                    });
                }
                if let Some((_, i)) = best {
                    let i = i as usize;
                    out[at] = pack(rig.influences[i], rig.weights[i]);
                }
            }
        }
    }
    out
}

/// The most device memory the blend grid may take.
pub const MAX_BYTES: usize = 32 << 20;

/// Why the blend grid over `field` does not fit a device whose 3D images reach `max_3d`
/// texels a side (more than [`MAX_BYTES`], or a side too long), or None where it fits.
pub fn misfit(field: &Sdf, max_3d: u32) -> Option<String> {
    let bytes = self::bytes(field);
    let [nx, ny, nz] = dims(field);
    if bytes > MAX_BYTES {
        Some(format!(
            "the skin's blend over a {}×{}×{} field needs {} MiB of device memory, more than \
             the {} MiB it may take",
            field.dims[0],
            field.dims[1],
            field.dims[2],
            bytes >> 20,
            MAX_BYTES >> 20
        ))
    } else if [nx.div_ceil(2), ny, nz].iter().any(|&n| n > max_3d) {
        Some(format!(
            "the skin's blend grid ({nx}×{ny}×{nz} points, two to a texel along x) exceeds \
             this device's largest 3D image ({max_3d} texels a side)"
        ))
    } else {
        None
    }
}

/// [`grid`] for `body` and its rest `field`, for hair of `hair_length` (see [`band`]):
/// what the simulation uses. A grid over [`MAX_BYTES`] is refused, naming the limit.
pub fn for_body(body: &super::SkinnedBody, field: &Sdf, hair_length: f32) -> Result<Vec<Packed>> {
    if let Some(why) = misfit(field, u32::MAX) {
        return Err(Error::Parameter(format!(
            "{why}; lower --sdf-resolution or turn --skin-blend off"
        )));
    }
    Ok(grid(
        &body.rig,
        &body.rest_positions,
        field,
        band(hair_length),
    ))
}

/// Calls `f` with every bucket on the shell of Chebyshev radius `ring` around `c`.
fn for_ring(c: glam::IVec3, ring: i32, mut f: impl FnMut(glam::IVec3)) {
    for dz in -ring..=ring {
        for dy in -ring..=ring {
            for dx in -ring..=ring {
                if dx.abs().max(dy.abs()).max(dz.abs()) == ring {
                    f(c + glam::IVec3::new(dx, dy, dz));
                }
            }
        }
    }
}

/// Per joint, the first three rows of `Kₖ = Jₖ · Jₖ,rest⁻¹`: the joint's motion from the
/// rest pose the field was built in (`rest_inverse`) to the pose of `matrices`.
pub fn bone_rows(matrices: &[Mat4], rest_inverse: &[Mat4]) -> Vec<[Vec4; 3]> {
    matrices
        .iter()
        .zip(rest_inverse)
        .map(|(m, r)| {
            let k = *m * *r;
            [k.row(0), k.row(1), k.row(2)]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_packed_blend_keeps_the_two_heaviest_bones_scaled_to_one() {
        let (j, share) = unpack(pack([3, 65535, 9, 7], [0.2, 0.5, 0.3, 0.0]));
        assert_eq!(j, [65535, 9]);
        assert!((share - 0.625).abs() < 1e-6, "{share}");
        // One bone: both halves name it, with all the weight.
        let (j, share) = unpack(pack([4, 5, 6, 7], [0.0, 0.0, 1.0, 0.0]));
        assert_eq!((j, share), ([6, 6], 1.0));
        // Ties keep the earlier influence first.
        let (j, share) = unpack(pack([1, 2, 3, 4], [0.25; 4]));
        assert_eq!((j, share), ([1, 2], 0.5));
        // No weight: no blend.
        assert_eq!(pack([1, 2, 3, 4], [0.0; 4]), [0, 0]);
    }

    #[test]
    fn the_rows_of_a_joint_at_its_rest_pose_are_the_identity() {
        let m = Mat4::from_rotation_translation(
            glam::Quat::from_rotation_z(0.7),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let rows = bone_rows(&[m], &[m.inverse()]);
        for (k, row) in rows[0].iter().enumerate() {
            let want = Mat4::IDENTITY.row(k);
            assert!(
                (*row - want).abs().max_element() < 1e-6,
                "{row} against {want}"
            );
        }
    }

    /// The field of the plane y = 0 (distance y, gradient +y), `n` points a side over
    /// x, z ∈ [0, (n − 1) cell], y ∈ [−1, −1 + (n − 1) cell]: sampled exactly.
    fn floor(n: u32, cell: f32) -> Sdf {
        let mut values = Vec::new();
        for _z in 0..n {
            for y in 0..n {
                for _x in 0..n {
                    values.push(-1.0 + cell * y as f32);
                }
            }
        }
        Sdf {
            dims: [n; 3],
            origin: Vec3::new(0.0, -1.0, 0.0),
            cell,
            gradients: vec![Vec3::Y; values.len()],
            values,
        }
    }

    /// The blend grid's size: `REFINE` points per field cell, two points to a 16-byte
    /// texel along x; a hair's band is half its length.
    #[test]
    fn the_grid_has_two_points_a_cell_and_two_a_texel() {
        let mut field = floor(3, 0.5);
        field.dims = [3, 4, 5];
        assert_eq!(dims(&field), [5, 7, 9]);
        assert_eq!(bytes(&field), 3 * 7 * 9 * 16);
        assert_eq!(band(0.4), 0.2);
        assert_eq!(misfit(&field, 9), None);
        let side = misfit(&field, 8).expect("a side of 9 points on a device of 8");
        assert!(
            side.contains("5×7×9 points") && side.contains("(8 texels"),
            "{side}"
        );
        // Exactly the limit fits; a point more does not (2²¹ points along x, two to a
        // texel, 16 bytes a texel: 32 MiB).
        field.dims = [1 << 21, 1, 1];
        assert_eq!(bytes(&field), MAX_BYTES);
        assert_eq!(misfit(&field, u32::MAX), None);
        field.dims = [(1 << 21) + 2, 1, 1];
        assert!(misfit(&field, u32::MAX).is_some());
        // Only the sizes are read: a field too large to build is refused all the same.
        field.dims = [512, 512, 64];
        let big = misfit(&field, u32::MAX).expect("over the byte limit");
        assert!(
            big.contains("512×512×64 field needs 1015 MiB") && big.contains("32 MiB"),
            "{big}"
        );
    }

    /// The nearest blend grid point, x fastest: on a grid of 0.2 from (1, −1, 2),
    /// (1.25, −0.45, 2.05) is point (1, 3, 0); the far corner is the last point; a
    /// point outside along any axis has none.
    #[test]
    fn the_nearest_grid_point_rounds_each_coordinate() {
        let mut field = floor(3, 0.4);
        field.origin = Vec3::new(1.0, -1.0, 2.0);
        assert_eq!(dims(&field), [5, 5, 5]);
        let at = |x: f64, y: f64, z: f64| nearest(&field, V3::<f64>(x, y, z));
        assert_eq!(at(1.25, -0.45, 2.05), Some(1 + 5 * 3));
        assert_eq!(at(1.05, -0.95, 2.45), Some(5 * 5 * 2));
        assert_eq!(at(1.79, -0.21, 2.79), Some(124));
        assert_eq!(at(1.0, -1.0, 2.0), Some(0));
        for outside in [
            (0.99, -0.5, 2.5),
            (1.5, -0.19, 2.5),
            (1.5, -1.01, 2.5),
            (1.5, -0.5, 2.81),
        ] {
            assert_eq!(at(outside.0, outside.1, outside.2), None, "{outside:?}");
        }
        assert_eq!(nearest(&field, V3::<f32>(1.25, -0.45, 2.05)), Some(16));
    }

    /// The bucket search is exact however far the nearest vertex is: on a coarse field
    /// (cells of 2, buckets of 4) with a band wider than the box, every grid point holds
    /// the blend of the vertex nearest to it among 60 scattered over the box. Seen
    /// failing with the buckets keyed by a product or remainder instead of a quotient,
    /// and with the rings counted by a remainder.
    #[test]
    fn the_bucket_search_finds_the_nearest_vertex_across_buckets() {
        let field = floor(9, 2.0);
        let mut rig = crate::skinning::tests::stick();
        let hash = |k: u32| ((k.wrapping_mul(2_654_435_761) >> 8) % 1000) as f32 / 1000.0;
        let rest: Vec<Vec3> = (0..60u32)
            .map(|v| {
                Vec3::new(
                    16.0 * hash(3 * v),
                    16.0 * hash(3 * v + 1) - 1.0,
                    16.0 * hash(3 * v + 2),
                )
            })
            .collect();
        rig.influences = (0..60u16).map(|v| [v, v + 1, 0, 0]).collect();
        rig.weights = vec![[0.75, 0.25, 0.0, 0.0]; 60];
        let out = grid(&rig, &rest, &field, 20.0);
        let [nx, ny, nz] = dims(&field);
        let step = field.cell / REFINE as f32;
        let mut distinct = std::collections::HashSet::new();
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let p = field.origin + Vec3::new(x as f32, y as f32, z as f32) * step;
                    let mut best = 0;
                    for (i, q) in rest.iter().enumerate() {
                        if q.distance(p) < rest[best].distance(p) {
                            best = i;
                        }
                    }
                    let got = out[(x + nx * (y + ny * z)) as usize];
                    assert_eq!(got, pack(rig.influences[best], rig.weights[best]), "{p}");
                    distinct.insert(best);
                }
            }
        }
        assert!(
            distinct.len() > 50,
            "only {} vertices nearest anywhere",
            distinct.len()
        );
    }

    /// Each grid point within the band of the surface holds the packed blend of the
    /// rest vertex nearest to it (ties: the lower index), every other point zero: the
    /// bucket search against trying every vertex, on the stick's vertices moved to lie
    /// around the plane, and by hand at three points.
    #[test]
    fn each_grid_point_near_the_skin_holds_its_nearest_vertexs_blend() {
        let field = floor(9, 0.25);
        let mut rig = crate::skinning::tests::stick();
        // The stick's 42 vertices, squeezed into the field's box around the plane, and
        // given blends that tell them apart.
        let rest: Vec<Vec3> = rig
            .bind_positions
            .iter()
            .map(|p| Vec3::new(0.3 * p.x + 1.0, 0.25 * p.y + 0.1, 0.6 * p.z + 0.1))
            .collect();
        for (v, (joints, weights)) in rig.influences.iter_mut().zip(&mut rig.weights).enumerate() {
            *joints = [v as u16, (v + 1) as u16, 0, 0];
            *weights = [0.6, 0.4, 0.0, 0.0];
        }
        let band = 0.3;
        let out = grid(&rig, &rest, &field, band);
        let [nx, ny, nz] = dims(&field);
        assert_eq!(out.len(), (nx * ny * nz) as usize);
        let step = field.cell / REFINE as f32;
        let (mut near, mut far) = (0, 0);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let p = field.origin + Vec3::new(x as f32, y as f32, z as f32) * step;
                    let got = out[(x + nx * (y + ny * z)) as usize];
                    if p.y.abs() > band {
                        assert_eq!(got, [0, 0], "{p} is outside the band");
                        far += 1;
                        continue;
                    }
                    let mut best = 0;
                    for (i, q) in rest.iter().enumerate() {
                        if q.distance(p) < rest[best].distance(p) {
                            best = i;
                        }
                    }
                    assert_eq!(got, pack(rig.influences[best], rig.weights[best]), "{p}");
                    near += 1;
                }
            }
        }
        assert!(
            near > 500 && far > 500,
            "{near} points in the band, {far} outside"
        );
        // By hand: a blend is its vertex's two joints, the first with 0.6 of the weight.
        let centre = out[(8 + nx * (8 + ny * 8)) as usize];
        assert_eq!(unpack(centre).1, 0.6);
    }

    /// What the simulation asks for: the grid over the body's rest vertices within half
    /// a hair of the surface; a field whose grid would pass the limit is refused, naming
    /// what to lower.
    #[test]
    fn a_body_gets_the_grid_for_its_hair_or_a_refusal() {
        let rig = crate::skinning::tests::stick();
        let body =
            crate::skinning::SkinnedBody::new(&crate::skinning::tests::stick_mesh(&rig), rig);
        let field = floor(9, 0.25);
        let got = for_body(&body, &field, 0.6).unwrap();
        assert_eq!(got, grid(&body.rig, &body.rest_positions, &field, 0.3));
        assert_ne!(got, grid(&body.rig, &body.rest_positions, &field, 0.6));
        let mut huge = field.clone();
        huge.dims = [512, 512, 64];
        let refused = for_body(&body, &huge, 0.6).unwrap_err().to_string();
        assert!(refused.contains("--sdf-resolution"), "{refused}");
    }
}
