//! Tests of clip sampling, poses and skinning.

use super::*;
use crate::scene::{Joint, Node};

fn channel(
    property: Property,
    interpolation: Interpolation,
    times: &[f32],
    values: &[Vec4],
) -> Channel {
    Channel {
        node: 0,
        property,
        interpolation,
        times: times.to_vec(),
        values: values.to_vec(),
    }
}

fn close(a: Vec4, b: Vec4) -> bool {
    (a - b).abs().max_element() < 1e-5
}

fn quat(axis: Vec3, degrees: f32) -> Vec4 {
    Quat::from_axis_angle(axis, degrees.to_radians()).into()
}

/// A chain root → a → b with turns and scales, joints bound at rest, and one clip.
fn chain() -> Rig {
    let node = |name: &str, parent, translation, rotation, scale| Node {
        name: name.into(),
        parent,
        rest: Transform {
            translation,
            rotation,
            scale,
        },
    };
    let nodes = vec![
        node(
            "root",
            None,
            Vec3::new(1.0, 2.0, 3.0),
            Quat::from_rotation_y(0.3),
            Vec3::ONE,
        ),
        node(
            "a",
            Some(0),
            Vec3::new(0.0, 0.0, 1.0),
            Quat::from_rotation_x(0.5),
            Vec3::splat(1.5),
        ),
        node(
            "b",
            Some(1),
            Vec3::new(0.0, 1.0, 0.0),
            Quat::IDENTITY,
            Vec3::new(1.0, 2.0, 1.0),
        ),
    ];
    let mut rig = Rig {
        nodes,
        joints: Vec::new(),
        influences: vec![[0, 1, 0, 0], [2, 0, 0, 0]],
        weights: vec![[0.5, 0.5, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]],
        bind_positions: vec![Vec3::new(1.0, 2.5, 3.5), Vec3::new(1.0, 3.0, 4.0)],
        bind_normals: vec![Vec3::Y, Vec3::Z],
        clips: Vec::new(),
        scale: 1.0,
    };
    let world = rig.world(&rig.pose(None, 0.0, false));
    rig.joints = (0..3)
        .map(|node| Joint {
            node,
            inverse_bind: world[node].inverse(),
        })
        .collect();
    let walk = vec![
        channel(
            Property::Translation,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[Vec4::new(1.0, 2.0, 3.0, 0.0), Vec4::new(1.5, 2.2, 5.0, 0.0)],
        ),
        Channel {
            node: 2,
            ..channel(
                Property::Rotation,
                Interpolation::Linear,
                &[0.0, 1.0],
                &[Vec4::W, quat(Vec3::Z, 40.0)],
            )
        },
    ];
    rig.clips = vec![Clip {
        name: "Walk".into(),
        channels: walk,
    }];
    rig
}

#[test]
fn step_holds_the_previous_key() {
    let c = channel(
        Property::Translation,
        Interpolation::Step,
        &[0.0, 1.0, 2.0],
        &[Vec4::X, Vec4::Y, Vec4::Z],
    );
    assert_eq!(c.sample(0.99), Vec4::X);
    assert_eq!(c.sample(1.0), Vec4::Y);
    assert_eq!(c.sample(1.5), Vec4::Y);
    assert_eq!(c.sample(7.0), Vec4::Z);
}

#[test]
fn linear_lerps_and_clamps_outside_the_keys() {
    let v = [
        Vec4::new(1.0, 2.0, 3.0, 0.0),
        Vec4::new(3.0, 2.0, -1.0, 0.0),
    ];
    let c = channel(
        Property::Translation,
        Interpolation::Linear,
        &[1.0, 3.0],
        &v,
    );
    assert!(close(c.sample(1.5), Vec4::new(1.5, 2.0, 2.0, 0.0)));
    assert_eq!(c.sample(1.0), v[0]);
    assert_eq!(c.sample(3.0), v[1]);
    assert_eq!(c.sample(-5.0), v[0], "before the first key");
    assert_eq!(c.sample(9.0), v[1], "after the last key");
    assert_eq!(c.sample(f32::NAN), v[0]);
    let one = channel(
        Property::Scale,
        Interpolation::Linear,
        &[0.5],
        &[Vec4::splat(2.0)],
    );
    assert_eq!(one.sample(0.0), one.sample(3.0), "one key is constant");
}

#[test]
fn rotations_slerp_on_the_shorter_arc() {
    let c = channel(
        Property::Rotation,
        Interpolation::Linear,
        &[0.0, 1.0],
        &[Vec4::W, quat(Vec3::Y, 90.0)],
    );
    assert!(close(c.sample(0.5), quat(Vec3::Y, 45.0)));
    assert!(close(c.sample(0.25), quat(Vec3::Y, 22.5)));
    // The same end rotation with its sign flipped: still 45° half-way, not 135°.
    let flipped = channel(
        Property::Rotation,
        Interpolation::Linear,
        &[0.0, 1.0],
        &[Vec4::W, -quat(Vec3::Y, 90.0)],
    );
    let half = Quat::from_vec4(flipped.sample(0.5));
    assert!((half.angle_between(Quat::from_vec4(quat(Vec3::Y, 45.0)))).abs() < 1e-3);
    // Nearly equal keys do not divide by zero.
    let near = channel(
        Property::Rotation,
        Interpolation::Linear,
        &[0.0, 1.0],
        &[Vec4::W, quat(Vec3::X, 0.001)],
    );
    assert!(near.sample(0.5).is_finite());
    assert!((near.sample(0.5).length() - 1.0).abs() < 1e-6);
}

#[test]
fn cubic_splines_follow_the_hermite_formula() {
    // Per key: in-tangent, value, out-tangent; key interval 2 scales the tangents.
    let values = [
        Vec4::ZERO,
        Vec4::new(1.0, 2.0, 3.0, 0.0),
        Vec4::new(4.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 2.0, 0.0, 0.0),
        Vec4::new(3.0, 2.0, 1.0, 0.0),
        Vec4::ZERO,
    ];
    let c = channel(
        Property::Translation,
        Interpolation::CubicSpline,
        &[1.0, 3.0],
        &values,
    );
    // p(½) = ½v0 + td/8·b0 + ½v1 − td/8·a1
    assert!(
        close(c.sample(2.0), Vec4::new(3.0, 1.5, 2.0, 0.0)),
        "{}",
        c.sample(2.0)
    );
    assert_eq!(c.sample(1.0), values[1]);
    assert!(close(c.sample(3.0), values[4]));
    assert_eq!(c.sample(0.0), values[1]);
    assert_eq!(c.sample(4.0), values[4]);
    // Rotations come back normalised.
    let q = [
        Vec4::ZERO,
        Vec4::W,
        Vec4::ZERO,
        Vec4::ZERO,
        quat(Vec3::Y, 90.0),
        Vec4::ZERO,
    ];
    let r = channel(
        Property::Rotation,
        Interpolation::CubicSpline,
        &[0.0, 1.0],
        &q,
    );
    let mid = r.sample(0.5);
    assert!((mid.length() - 1.0).abs() < 1e-6);
    assert!(close(mid, (Vec4::W + quat(Vec3::Y, 90.0)).normalize()));
}

#[test]
fn a_key_hit_exactly_gives_its_value() {
    let v = [Vec4::X, Vec4::Y, Vec4::Z];
    for interpolation in [Interpolation::Step, Interpolation::Linear] {
        let c = channel(Property::Translation, interpolation, &[0.0, 0.5, 1.0], &v);
        assert_eq!(c.sample(0.5), Vec4::Y);
    }
    let cubic: Vec<Vec4> = v.iter().flat_map(|&v| [Vec4::ONE, v, Vec4::ONE]).collect();
    let c = channel(
        Property::Translation,
        Interpolation::CubicSpline,
        &[0.0, 0.5, 1.0],
        &cubic,
    );
    assert_eq!(c.sample(0.5), Vec4::Y);
}

#[test]
fn a_clip_lasts_until_its_last_key() {
    let rig = chain();
    assert_eq!(rig.clips[0].duration(), 1.0);
    assert_eq!(
        Clip {
            name: "none".into(),
            channels: Vec::new()
        }
        .duration(),
        0.0
    );
}

#[test]
fn joint_matrices_at_rest_are_identities_and_world_composes_parents() {
    let rig = chain();
    for m in rig.rest_matrices() {
        assert!(m.abs_diff_eq(Mat4::IDENTITY, 1e-5), "{m}");
    }
    let locals = rig.pose(Some(&rig.clips[0]), 0.5, false);
    let world = rig.world(&locals);
    assert!(world[2].abs_diff_eq(
        locals[0].matrix() * locals[1].matrix() * locals[2].matrix(),
        1e-5
    ));
    let mut scaled = rig.clone();
    scaled.scale = 2.0;
    assert!(scaled.rest_matrices()[1].abs_diff_eq(Mat4::from_scale(Vec3::splat(2.0)), 1e-5));
}

#[test]
fn in_place_holds_the_roots_horizontal_translation() {
    let rig = chain();
    let moving = rig.pose(Some(&rig.clips[0]), 0.5, false);
    let still = rig.pose(Some(&rig.clips[0]), 0.5, true);
    assert!(moving[0]
        .translation
        .abs_diff_eq(Vec3::new(1.25, 2.1, 4.0), 1e-6));
    assert!(
        still[0]
            .translation
            .abs_diff_eq(Vec3::new(1.0, 2.1, 3.0), 1e-6),
        "the bob stays"
    );
    assert_eq!(moving[2].rotation, still[2].rotation);
    assert_eq!(rig.pose(None, 0.5, true)[0], rig.nodes[0].rest);
}

#[test]
fn skinning_blends_the_joint_matrices() {
    let rig = chain();
    let (p, n, t) = rig.skin(&rig.rest_matrices(), &[Vec3::X]);
    for (a, b) in p.iter().zip(&rig.bind_positions) {
        assert!(a.abs_diff_eq(*b, 1e-5));
    }
    assert!(n[1].abs_diff_eq(Vec3::Z, 1e-5));
    assert_eq!(t.len(), 1);
    assert!(t[0].abs_diff_eq(Vec3::X, 1e-5));
    let moved = [
        Mat4::from_translation(Vec3::X),
        Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2),
        Mat4::IDENTITY,
    ];
    let (p, n, t) = rig.skin(&moved, &[Vec3::X, Vec3::Y]);
    let half = 0.5 * (moved[0] + moved[1]);
    assert!(p[0].abs_diff_eq(half.transform_point3(rig.bind_positions[0]), 1e-5));
    assert!(n[0].abs_diff_eq(Vec3::new(-1.0, 1.0, 0.0).normalize(), 1e-5));
    assert!(t[0].abs_diff_eq(Vec3::new(1.0, 1.0, 0.0).normalize(), 1e-5));
    assert!(p[1].abs_diff_eq(rig.bind_positions[1], 1e-6));
}

#[test]
fn clips_are_found_by_name_in_any_case() {
    let rig = chain();
    assert_eq!(rig.clip_index("walk"), Ok(0));
    assert_eq!(rig.clip_index("WALK"), Ok(0));
    let error = rig.clip_index("run").unwrap_err();
    assert!(error.contains("run") && error.contains("Walk"), "{error}");
}

#[test]
fn bone_directions_point_to_the_child_or_away_from_the_parent() {
    let rig = chain();
    let world = rig.world(&rig.pose(None, 0.0, false));
    let at = |n: usize| world[n].w_axis.truncate();
    let d = rig.bone_directions();
    assert!(
        d[0].abs_diff_eq((at(1) - at(0)).normalize(), 1e-5),
        "root → a"
    );
    assert!(
        d[1].abs_diff_eq((at(2) - at(1)).normalize(), 1e-5),
        "b has no child: a → b"
    );
}

#[test]
fn skinning_the_critter_at_rest_reproduces_its_mesh() {
    let (mesh, rig) = crate::scene::critter();
    let (p, n, _) = rig.skin(&rig.rest_matrices(), &[]);
    for (a, b) in p.iter().zip(&mesh.positions) {
        assert!(a.abs_diff_eq(*b, 1e-5), "{a} {b}");
    }
    for (a, b) in n.iter().zip(&mesh.normals) {
        assert!(a.abs_diff_eq(*b, 1e-5), "{a} {b}");
    }
}
