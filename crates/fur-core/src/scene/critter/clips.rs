//! The built-in creature's clips: a trot with root motion and an idle.

use std::f32::consts::{PI, TAU};

use glam::{Quat, Vec3, Vec4};

use super::{bone, Bone, STRIDE};
use crate::scene::{Channel, Clip, Interpolation, Property};

fn rot(axis: Vec3, angle: f32) -> Vec4 {
    Quat::from_axis_angle(axis, angle).into()
}

/// A LINEAR channel of `keys` + 1 evenly spaced keys over `duration` from `f`, the
/// last key a copy of the first (seamless loops).
fn looped(
    node: usize,
    property: Property,
    duration: f32,
    keys: usize,
    f: impl Fn(f32) -> Vec4,
) -> Channel {
    let times: Vec<f32> = (0..=keys)
        .map(|k| duration * k as f32 / keys as f32)
        .collect();
    let mut values: Vec<Vec4> = times[..keys].iter().map(|&t| f(t)).collect();
    values.push(values[0]);
    Channel {
        node,
        property,
        interpolation: Interpolation::Linear,
        times,
        values,
    }
}

/// A CUBICSPLINE rotation channel through `f` at `keys` + 1 even keys, tangents from
/// its derivative (per second), the last key a copy of the first.
fn looped_cubic(node: usize, duration: f32, keys: usize, f: impl Fn(f32) -> Vec4) -> Channel {
    let mut channel = looped(node, Property::Rotation, duration, keys, &f);
    let slope = |t: f32| (f(t + 1e-3) - f(t - 1e-3)) / 2e-3;
    let mut values: Vec<Vec4> = channel.times[..keys]
        .iter()
        .flat_map(|&t| [slope(t), f(t), slope(t)])
        .collect();
    values.extend_from_within(..3);
    channel.interpolation = Interpolation::CubicSpline;
    channel.values = values;
    channel
}

/// A 1 s trot: diagonal pairs (front left with hind right) swing together; the root
/// moves `STRIDE` forwards with a small bob; spine, head and tail sway.
pub(super) fn walk(bones: &[Bone]) -> Clip {
    let b = |name: &str| bone(bones, name);
    const KEYS: usize = 16;
    let root = bones[0].2;
    let times: Vec<f32> = (0..=KEYS).map(|k| k as f32 / KEYS as f32).collect();
    let travel = Channel {
        node: 0,
        property: Property::Translation,
        interpolation: Interpolation::Linear,
        values: times
            .iter()
            .map(|&t| {
                (root + Vec3::new(0.0, -0.035 * (TAU * t).cos().powi(2), STRIDE * t)).extend(0.0)
            })
            .collect(),
        times,
    };
    let mut channels = vec![travel];
    let sway = |node: usize, axis: Vec3, amplitude: f32, lag: f32| {
        looped(node, Property::Rotation, 1.0, KEYS, move |t| {
            rot(axis, amplitude * (TAU * t - lag).sin())
        })
    };
    channels.push(sway(0, Vec3::Z, 0.03, 0.0));
    channels.push(sway(b("spine"), Vec3::Y, 0.04, 0.0));
    channels.push(sway(b("chest"), Vec3::Y, -0.05, 0.0));
    channels.push(looped(b("neck"), Property::Rotation, 1.0, KEYS, |t| {
        rot(Vec3::X, 0.04 * (2.0 * TAU * t).sin())
    }));
    channels.push(sway(b("head"), Vec3::Y, 0.05, 0.3));
    channels.push(looped(b("tail.1"), Property::Rotation, 1.0, KEYS, |t| {
        Vec4::from(Quat::from_rotation_y(0.18 * (TAU * t).sin()) * Quat::from_rotation_x(0.1))
    }));
    channels.push(sway(b("tail.2"), Vec3::Y, 0.15, 0.7));
    channels.push(sway(b("tail.3"), Vec3::Y, 0.15, 1.4));
    // Per leg: phase, swing amplitude, and how far the lower leg and paw fold in the
    // swing (positive folds the lower end backwards). The front legs run 0.4 rad (6 % of
    // the cycle) behind their diagonal hind legs: exactly in phase, the paws on each
    // side met under the body and passed through each other. Tuned (docs/testing.md,
    // "Tuned constants").
    for (leg, phase, swing, fold_lower, fold_paw) in [
        ("front_leg.L", -0.4, 0.4, 0.9, 0.8),
        ("front_leg.R", PI - 0.4, 0.4, 0.9, 0.8),
        ("hind_leg.L", PI, 0.38, 0.5, -0.6),
        ("hind_leg.R", 0.0, 0.38, 0.5, -0.6),
    ] {
        // Stance for phase in [0, π] (the paw sweeps back), swing for [π, 2π].
        let at = move |t: f32| TAU * t + phase;
        let lift = move |t: f32| (-at(t).sin()).max(0.0);
        channels.push(looped(
            b(&format!("{leg}.upper")),
            Property::Rotation,
            1.0,
            KEYS,
            move |t| rot(Vec3::X, -swing * at(t).cos()),
        ));
        channels.push(looped(
            b(&format!("{leg}.lower")),
            Property::Rotation,
            1.0,
            KEYS,
            move |t| rot(Vec3::X, fold_lower * lift(t)),
        ));
        channels.push(looped(
            b(&format!("{leg}.paw")),
            Property::Rotation,
            1.0,
            KEYS,
            move |t| rot(Vec3::X, fold_paw * lift(t)),
        ));
    }
    Clip {
        name: "Walk".into(),
        channels,
    }
}

/// A 2 s idle: the tail wags twice (its base cubic), each ear twitches once, the chest
/// breathes (its children scaled back so legs and head keep their size), and the head
/// turns slowly to one side and the other.
pub(super) fn idle(bones: &[Bone]) -> Clip {
    let b = |name: &str| bone(bones, name);
    const KEYS: usize = 16;
    let wag =
        |lag: f32, amplitude: f32| move |t: f32| rot(Vec3::Y, amplitude * (TAU * t - lag).sin());
    let mut channels = vec![
        looped_cubic(b("tail.1"), 2.0, 8, |t| {
            Vec4::from(Quat::from_rotation_y(0.35 * (TAU * t).sin()) * Quat::from_rotation_x(0.15))
        }),
        looped(b("tail.2"), Property::Rotation, 2.0, KEYS, wag(0.8, 0.3)),
        looped(b("tail.3"), Property::Rotation, 2.0, KEYS, wag(1.6, 0.3)),
        looped(b("head"), Property::Rotation, 2.0, KEYS, |t| {
            Vec4::from(
                Quat::from_rotation_y(0.3 * (PI * t).sin())
                    * Quat::from_rotation_x(0.05 * (TAU * t).sin()),
            )
        }),
    ];
    for (ear, start, out) in [("ear.L", 0.6, -1.0), ("ear.R", 1.3, 1.0)] {
        let times = vec![0.0, start, start + 0.08, start + 0.16, start + 0.26, 2.0];
        let angles = [0.0, 0.0, 0.35, -0.06, 0.0, 0.0];
        let values = angles.iter().map(|a| rot(Vec3::Z, out * a)).collect();
        channels.push(Channel {
            node: b(ear),
            property: Property::Rotation,
            interpolation: Interpolation::Linear,
            times,
            values,
        });
    }
    let breath = |t: f32| Vec3::new(0.03, 0.04, 0.01) * (0.5 - 0.5 * (PI * t).cos()) + Vec3::ONE;
    channels.push(looped(b("chest"), Property::Scale, 2.0, KEYS, move |t| {
        breath(t).extend(0.0)
    }));
    for child in ["neck", "front_leg.L.upper", "front_leg.R.upper"] {
        channels.push(looped(b(child), Property::Scale, 2.0, KEYS, move |t| {
            breath(t).recip().extend(0.0)
        }));
    }
    Clip {
        name: "Idle".into(),
        channels,
    }
}
