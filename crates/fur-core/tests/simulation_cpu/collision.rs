//! The collision step on hand-made fields and capsules, with results written down.

use super::*;

/// The field of the half-space y < 0 (distance y, gradient +y) on a grid over [−2, 2]³:
/// sampled exactly, so the collision step's result can be written down.
fn floor_field() -> Sdf {
    let n = 17u32;
    let cell = 0.25f32;
    let mut values = Vec::new();
    for _z in 0..n {
        for y in 0..n {
            for _x in 0..n {
                values.push(-2.0 + cell * y as f32);
            }
        }
    }
    Sdf {
        dims: [n; 3],
        origin: Vec3::splat(-2.0),
        cell,
        gradients: vec![Vec3::Y; values.len()],
        values,
    }
}

/// Two straight upright strands, 0.4 and 0.2 long (four segments each), rooted at
/// (0, 0.5, 0) and (0.5, 0.5, 0.5).
fn upright_strands() -> Strands {
    let mut positions = Vec::new();
    for (root, segment) in [(Vec3::new(0.0, 0.5, 0.0), 0.1), (Vec3::splat(0.5), 0.05)] {
        for k in 0..5 {
            positions.push(root + Vec3::Y * (segment * k as f32));
        }
    }
    Strands {
        vertices_per_strand: 5,
        positions,
    }
}

/// Parameters under which a substep moves nothing but by collision: no gravity, no
/// constraint, no wind, no friction.
fn collision_only(margin: f32) -> SimParams {
    SimParams {
        gravity: Vec3::ZERO,
        global_stiffness: 0.0,
        local_stiffness: 0.0,
        local_iterations: 0,
        length_iterations: 0,
        collision: true,
        collision_margin: margin,
        friction: 0.0,
        ..SimParams::default()
    }
}

/// The collision margin is the fraction `collision_margin` of each strand's own rest
/// length: vertices below it (inside the body or too close to it) end exactly on it
/// (0.25 × 0.4 = 0.1 for one strand, 0.25 × 0.2 = 0.05 for the other), straight out
/// along the field's gradient; a vertex farther out does not move.
#[test]
fn collision_pushes_vertices_to_a_margin_of_each_strands_own_length() {
    let strands = upright_strands();
    let mut sim = CpuSim::<f64>::new(&strands, collision_only(0.25), DMat4::IDENTITY)
        .with_sdf(Arc::new(floor_field()));
    // Strand by strand, vertices 1 to 4: inside, inside, within the margin, far out.
    let placed = |x: f64, z: f64| {
        [
            (0.1, -0.3, 0.0),
            (0.2, -0.02, 0.1),
            (-0.1, 0.04, 0.2),
            (0.3, 0.3, -0.1),
        ]
        .map(|(dx, y, dz)| V3(x + dx, y, z + dz))
    };
    let v = 5;
    for (s, (x, z)) in [(0.0, 0.0), (0.5, 0.5)].into_iter().enumerate() {
        for (k, p) in placed(x, z).into_iter().enumerate() {
            sim.current[s * v + 1 + k] = p;
            sim.previous[s * v + 1 + k] = p;
        }
    }
    sim.step_frame(still);
    for (s, ((x, z), margin)) in [((0.0, 0.0), 0.1), ((0.5, 0.5), 0.05)]
        .into_iter()
        .enumerate()
    {
        for (k, p) in placed(x, z).into_iter().enumerate() {
            let want = if k == 3 { p } else { V3(p.0, margin, p.2) };
            let got = sim.current[s * v + 1 + k];
            assert!(
                // The strands' lengths are sums of f32 segments.
                (got - want).length() < 1e-6,
                "strand {s}, vertex {}: {got:?}, not {want:?}",
                k + 1
            );
        }
    }
}

/// Axis along z through (0.65, 0.5), radius 0.2: its surface is 0.45 from the root of the
/// first upright strand, between the strand's length less its margin and its length
/// plus it.
const CAPSULE: [glam::Vec4; 2] = [
    glam::Vec4::new(0.65, 0.5, -1.0, 0.2),
    // No child capsule.
    glam::Vec4::new(0.65, 0.5, 1.0, -1.0),
];

/// The first upright strand alone (0.4 long), laid along −x but for its tip, 0.05 from
/// [`CAPSULE`]'s axis, over a floor field far below, stepped one frame on the body
/// `held` with only collision (margin 0.25 of the length): its positions before, and
/// after.
fn capsule_step(held: impl Fn(&Strands) -> Posed) -> (Vec<V3<f64>>, Vec<V3<f64>>) {
    let strands = Strands {
        vertices_per_strand: 5,
        positions: upright_strands().positions[..5].to_vec(),
    };
    let mut sim = CpuSim::<f64>::new(&strands, collision_only(0.25), DMat4::IDENTITY)
        .with_sdf(Arc::new(floor_field()));
    let placed = [
        V3(-0.1, 0.5, 0.0),
        V3(-0.2, 0.5, 0.0),
        V3(-0.3, 0.5, 0.0),
        V3(0.7, 0.5, 0.0),
    ];
    for (k, p) in placed.into_iter().enumerate() {
        sim.current[1 + k] = p;
        sim.previous[1 + k] = p;
    }
    let before = sim.current.clone();
    let held = held(&strands);
    sim.step_frame_posed(still, |_| held.clone());
    (before, sim.current)
}

/// On a skinned body, a strand collides with a bone's capsule whose surface lies within
/// its length plus its margin of its root: a capsule 0.45 from the root of a strand 0.4
/// long with a margin of 0.1 pushes a vertex inside it out radially to 0.1 off its
/// surface; the distance field (far below) moves nothing.
#[test]
fn a_capsule_within_reach_of_the_root_pushes_vertices_out() {
    let (before, after) = capsule_step(|strands| posed(held_roots(strands), vec![CAPSULE]));
    for (i, (got, was)) in after.iter().zip(&before).enumerate() {
        let want = if i == 4 {
            // Out along +x to the radius plus the margin (in f32, as the capsule is).
            V3(f64::from(0.65f32) + f64::from(0.2f32) + 0.1, 0.5, 0.0)
        } else {
            *was
        };
        assert!(
            (*got - want).length() < 1e-7,
            "vertex {i}: {got:?}, not {want:?}"
        );
    }
}

/// A capsule counts only as far as its bone moved relative to the strand's root pose
/// (the rest field carried by that pose holds the rest): [`CAPSULE`], with the strand's
/// tip vertex inside it, leaves the strand alone where it sits at its bind-pose place,
/// and pushes the tip out to 4/5 of its radius plus the margin when it moved by a fifth
/// of the strand's length (4/5 of the way to its full radius, reached at a quarter).
#[test]
fn a_capsule_counts_as_far_as_its_bone_moved_relative_to_the_root() {
    let length = 0.4;
    // The bind-pose capsule, carried by the held roots (the identity), lies `shift` along
    // +x of where the capsule is now (along its own axis would not move it).
    let tip = |shift: f32| {
        let rest = vec![CAPSULE.map(|p| p + glam::Vec4::new(shift, 0.0, 0.0, 0.0))];
        capsule_step(|strands| posed_from(held_roots(strands), vec![CAPSULE], rest.clone())).1[4]
    };
    let unmoved = tip(0.0);
    assert!(
        (unmoved - V3(0.7, 0.5, 0.0)).length() < 1e-7,
        "a capsule where the root pose carries it pushed the tip to {unmoved:?}"
    );
    let most = tip(0.2 * length as f32);
    // 4/5 of the radius plus the margin (0.25 × 0.4) off the axis at x = 0.65.
    let want = f64::from(0.65f32) + 0.8 * f64::from(0.2f32) + 0.25 * length;
    assert!(
        (most.0 - want).abs() < 1e-6 && (most.1 - 0.5).abs() < 1e-7,
        "capsule moved by a fifth of the length: tip at {most:?}, not x = {want}"
    );
}

/// The skin at a capsule's far end bends with its child bone, so the child's motion
/// counts for it: [`CAPSULE`] where the root pose carries it, its tip vertex inside,
/// pushes the tip out to its full radius plus the margin once its child (a capsule out
/// of the strand's reach) moved by half the strand's length, and leaves it alone
/// without that link.
#[test]
fn a_capsule_counts_as_far_as_its_child_bone_moved() {
    let far = [
        glam::Vec4::new(50.0, 0.5, -1.0, 0.2),
        glam::Vec4::new(50.0, 0.5, 1.0, -1.0),
    ];
    let moved = far.map(|p| p + glam::Vec4::new(0.2, 0.0, 0.0, 0.0));
    let tip = |child: f32| {
        let mut capsule = CAPSULE;
        capsule[1].w = child;
        let (posed, rest) = (vec![capsule, moved], vec![capsule, far]);
        capsule_step(|strands| posed_from(held_roots(strands), posed.clone(), rest.clone())).1[4]
    };
    let linked = tip(1.0);
    let want = f64::from(0.65f32) + f64::from(0.2f32) + 0.1;
    assert!(
        (linked.0 - want).abs() < 1e-6 && (linked.1 - 0.5).abs() < 1e-7,
        "the child moved: tip at {linked:?}, not x = {want}"
    );
    let alone = tip(-1.0);
    assert!(
        (alone - V3(0.7, 0.5, 0.0)).length() < 1e-7,
        "without the child the tip moved to {alone:?}"
    );
}

/// A capsule pushes a vertex `s` along the hair from its root no farther from its axis
/// than the root's distance plus `s`, as far as the vertex can get while attached: with
/// the root 0.15 inside a capsule of radius 0.3, the first vertex (0.1 along) goes out
/// to 0.15 + 0.1 plus the margin, the second (0.2 along) to the full radius plus the
/// margin, and the tip, out of reach, stays.
#[test]
fn a_capsule_holding_the_root_pushes_the_first_vertices_only_as_far_as_they_reach() {
    let capsule = [
        glam::Vec4::new(-0.15, 0.5, -1.0, 0.3),
        glam::Vec4::new(-0.15, 0.5, 1.0, -1.0),
    ];
    let (before, after) = capsule_step(|strands| posed(held_roots(strands), vec![capsule]));
    let axis = f64::from(-0.15f32);
    let first = axis + (-axis + 0.1) + 0.1;
    let full = axis - f64::from(0.3f32) - 0.1;
    for (i, want) in [(1, first), (2, full), (3, full), (4, before[4].0)] {
        assert!(
            (after[i].0 - want).abs() < 1e-6 && (after[i].1 - 0.5).abs() < 1e-7,
            "vertex {i} at {:?}, not x = {want}",
            after[i]
        );
    }
}

/// Parameters under which a substep moves nothing but by the local shape constraint,
/// at `stiffness` with `passes` walks.
fn local_only(stiffness: f32, passes: u32) -> SimParams {
    SimParams {
        gravity: Vec3::ZERO,
        global_stiffness: 0.0,
        local_stiffness: stiffness,
        local_iterations: passes,
        length_iterations: 0,
        collision: false,
        // No velocity is kept from one substep to the next.
        damping: 1.0,
        ..SimParams::default()
    }
}

/// A turned and moved head: 0.7 rad about (1, 2, 2)/3, then (0.3, −0.2, 0.5).
fn turned_head() -> DMat4 {
    DMat4::from_rotation_translation(
        glam::DQuat::from_axis_angle(glam::DVec3::new(1.0, 2.0, 2.0) / 3.0, 0.7),
        glam::DVec3::new(0.3, -0.2, 0.5),
    )
}

/// The local shape constraint alone, at full stiffness and walked often enough (and
/// with no velocity kept), returns bent strands pushed out of shape to their rest shape carried by the (turned
/// and moved) head, each segment in its parent's frame as at rest; the roots do not
/// move.
#[test]
fn the_local_constraint_restores_the_rest_shape_in_the_heads_frame() {
    let strands = bent_strands();
    let head = turned_head();
    let mut sim = CpuSim::<f64>::new(&strands, local_only(1.0, 64), head);
    let v = 5;
    for (i, (x, p)) in sim.current.iter_mut().zip(&mut sim.previous).enumerate() {
        if i % v != 0 {
            let k = i as f64;
            *x = *x
                + V3(
                    0.03 * k.sin(),
                    0.05 * (k * 1.3).cos(),
                    -0.04 * (k * 0.7).sin(),
                );
            *p = *x;
        }
    }
    // The walk converges geometrically (by about 0.87 a pass here): 640 passes.
    for _ in 0..10 {
        sim.step_frame(|_| head);
    }
    // Down to the rounding of the head transform, held in f32.
    let head32 = head.as_mat4().as_dmat4();
    for (i, x) in sim.current.iter().enumerate() {
        let want = head32.transform_point3(strands.positions[i].as_dvec3());
        let error = (dvec(*x) - want).length();
        assert!(
            error < 1e-7,
            "strand {}, vertex {}: {error} from its rest position",
            i / v,
            i % v
        );
    }
}

/// One walk at half stiffness over a strand of one segment moves its tip exactly
/// halfway from where it is to its rest position carried by the head.
#[test]
fn half_local_stiffness_moves_a_segment_halfway_to_rest() {
    let rest = [Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.15, 0.3, 0.25)];
    let strands = Strands {
        vertices_per_strand: 2,
        positions: rest.to_vec(),
    };
    let head = turned_head();
    let mut sim = CpuSim::<f64>::new(&strands, local_only(0.5, 1), head);
    let pushed = sim.current[1] + V3(0.02, -0.03, 0.01);
    sim.current[1] = pushed;
    sim.previous[1] = pushed;
    sim.step_frame(|_| head);
    let head32 = head.as_mat4().as_dmat4();
    let at_rest = head32.transform_point3(rest[1].as_dvec3());
    let want = 0.5 * (dvec(pushed) + at_rest);
    let error = (dvec(sim.current[1]) - want).length();
    // Within the rounding of the head transform, held in f32.
    assert!(error < 1e-8, "{error}");
    let root = head32.transform_point3(rest[0].as_dvec3());
    assert!((dvec(sim.current[0]) - root).length() < 1e-12);
}

/// The local shape constraint keeps each segment's shape relative to its parent: a
/// straight strand turned rigidly by 90° about its root (so its shape is intact, only
/// its direction is off) is pulled back by one walk at half stiffness with its segments
/// still nearly in line (every bend under 20°; each segment follows its parent's new
/// direction), not each segment turned on its own towards its rest direction (which
/// bends it by some 40°).
#[test]
fn the_local_constraint_keeps_shape_relative_to_the_parent_segment() {
    let strands = Strands {
        vertices_per_strand: 4,
        positions: (0..4).map(|k| Vec3::X * (0.1 * k as f32)).collect(),
    };
    let mut sim = CpuSim::<f64>::new(&strands, local_only(0.5, 1), DMat4::IDENTITY);
    for k in 1..4 {
        sim.current[k] = V3(0.0, 0.1 * k as f64, 0.0);
        sim.previous[k] = sim.current[k];
    }
    sim.step_frame(still);
    let x: Vec<glam::DVec3> = sim.current.iter().map(|p| dvec(*p)).collect();
    // It did turn back towards +x (16° at the root).
    assert!(x[1].x > 0.01, "{x:?}");
    for k in 1..3 {
        let bend = (x[k] - x[k - 1])
            .angle_between(x[k + 1] - x[k])
            .to_degrees();
        assert!(bend < 20.0, "bent by {bend}° at vertex {k}: {x:?}");
    }
}
