//! The clip's timing, the tangents, the fur's flow, the animation's choice, the bones'
//! capsules and the skin's blend grid, on a rig small enough to work out by hand.

use glam::{Mat4, Vec3, Vec4};

use super::*;
use crate::scene::{Channel, Clip, Interpolation, Joint, Node, Property, Transform};

/// A stick animal, +y up: the hips at the origin, the spine and the head along +z (the
/// head is the front-most joint), a leg and its paw down −y. Every vertex is bound to
/// one joint alone:
/// - hips (joint 0, bone to the spine at (0, 0, 1)): five vertices at z = 0.5, 0.1 to
///   0.5 from the bone along x;
/// - spine (joint 1, bone to the head at (0, 0, 2)): four at z = 1.5, 0.2 from it;
/// - head (joint 2, a leaf): pairs at x = ±0.1 for z = 2.0, 2.1, …, 3.0;
/// - leg (joint 3, bone to the paw at (0, −2, 0)): four at y = −1.5, 0.15 from it;
/// - paw (joint 4, a leaf): three, too few for a capsule.
///
/// One clip, `Walk` (1 s): the hips move linearly from the origin to (0.4, 0.3, 0.2).
pub(crate) fn stick() -> Rig {
    let node = |name: &str, parent: Option<usize>, at: Vec3| Node {
        name: name.into(),
        parent,
        rest: Transform {
            translation: at,
            ..Transform::default()
        },
    };
    let nodes = vec![
        node("hips", None, Vec3::ZERO),
        node("spine", Some(0), Vec3::Z),
        node("head", Some(1), Vec3::Z),
        node("leg", Some(0), -Vec3::Y),
        node("paw", Some(3), -Vec3::Y),
    ];
    let mut vertices: Vec<(u16, Vec3, Vec3)> = Vec::new();
    for d in [0.1, 0.2, 0.3, 0.4, 0.5] {
        vertices.push((0, Vec3::new(d, 0.0, 0.5), Vec3::X));
    }
    for n in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
        vertices.push((1, Vec3::new(0.0, 0.0, 1.5) + 0.2 * n, n));
    }
    for k in 0..=10 {
        for x in [0.1, -0.1] {
            let z = 2.0 + 0.1 * k as f32;
            vertices.push((2, Vec3::new(x, 0.0, z), Vec3::X * x.signum()));
        }
    }
    for n in [Vec3::X, -Vec3::X, Vec3::Z, -Vec3::Z] {
        vertices.push((3, Vec3::new(0.0, -1.5, 0.0) + 0.15 * n, n));
    }
    for x in [0.1, -0.1, 0.2] {
        vertices.push((4, Vec3::new(x, -2.2, 0.0), Vec3::X));
    }
    let mut rig = Rig {
        nodes,
        joints: Vec::new(),
        influences: vertices.iter().map(|v| [v.0, 0, 0, 0]).collect(),
        weights: vec![[1.0, 0.0, 0.0, 0.0]; vertices.len()],
        bind_positions: vertices.iter().map(|v| v.1).collect(),
        bind_normals: vertices.iter().map(|v| v.2).collect(),
        clips: Vec::new(),
        scale: 1.0,
    };
    let world = rig.world(&rig.pose(None, 0.0, false));
    rig.joints = (0..5)
        .map(|node| Joint {
            node,
            inverse_bind: world[node].inverse(),
        })
        .collect();
    rig.clips = vec![Clip {
        name: "Walk".into(),
        channels: vec![Channel {
            node: 0,
            property: Property::Translation,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 1.0],
            values: vec![Vec4::ZERO, Vec4::new(0.4, 0.3, 0.2, 0.0)],
        }],
    }];
    rig
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-6
}

/// The clip time: the start plus speed × t, wrapped at the clip's end when looping,
/// clamped to it when not; no clip or a clip without length holds time 0.
#[test]
fn the_clip_time_wraps_or_holds_at_the_clips_end() {
    let mut rig = stick();
    let playing = |speed, start, looping| Playback {
        clip: Some(0),
        speed,
        start,
        looping,
        in_place: false,
    };
    let t = |rig: &Rig, p: Playback, at: f64| p.clip_time(rig, at);
    assert_eq!(t(&rig, playing(2.0, 0.25, true), 0.5), 0.25);
    assert_eq!(t(&rig, playing(0.5, 0.25, true), 0.5), 0.5);
    assert_eq!(t(&rig, playing(2.0, 0.25, false), 0.5), 1.0);
    assert_eq!(t(&rig, playing(0.5, 0.0, false), 1.0), 0.5);
    assert_eq!(t(&rig, Playback::default(), 0.7), 0.0, "no clip");
    rig.clips[0].channels[0].times = vec![0.0];
    rig.clips[0].channels[0].values = vec![Vec4::ZERO];
    assert_eq!(
        t(&rig, playing(1.0, 0.0, true), 0.7),
        0.0,
        "a clip of no length"
    );
}

/// The joint matrices at a time are the clip's pose then: halfway through the walk the
/// hips have moved half their way, every bone with them; on the spot, only upwards.
#[test]
fn joint_matrices_follow_the_clip_and_stay_on_the_spot_when_asked() {
    let rig = stick();
    let mut playback = Playback {
        clip: Some(0),
        in_place: false,
        ..Playback::default()
    };
    let moved = playback.joint_matrices(&rig, 0.5);
    assert_eq!(moved.len(), rig.joints.len());
    for m in &moved {
        let at = m.transform_point3(Vec3::new(0.0, 0.0, 1.0));
        assert!(close(at, Vec3::new(0.2, 0.15, 1.1)), "{at}");
    }
    playback.in_place = true;
    let on_spot = playback.joint_matrices(&rig, 0.5)[4].transform_point3(Vec3::ZERO);
    assert!(close(on_spot, Vec3::new(0.0, 0.15, 0.0)), "{on_spot}");
    let rest = Playback::default().joint_matrices(&rig, 0.5);
    assert!(rest.iter().all(|m| m.abs_diff_eq(Mat4::IDENTITY, 1e-6)));
}

/// The tangent across a normal is the hint made orthogonal to it and unit; a hint along
/// the normal, or none, gives some unit vector orthogonal to it.
#[test]
fn the_tangent_is_the_hint_made_orthogonal_to_the_normal() {
    let t = tangent_across(Vec3::Z, Vec3::new(3.0, 0.0, 4.0));
    assert!(close(t, Vec3::X), "{t}");
    let n = Vec3::new(0.0, 0.6, 0.8);
    let t = tangent_across(n, Vec3::new(1.0, 1.0, 0.0));
    let expected = (Vec3::new(1.0, 1.0, 0.0) - n * 0.6).normalize();
    assert!(close(t, expected), "{t} against {expected}");
    for hint in [Vec3::Z, -2.0 * Vec3::Z, Vec3::ZERO] {
        let t = tangent_across(Vec3::Z, hint);
        assert!((t.length() - 1.0).abs() < 1e-6 && t.z.abs() < 1e-6, "{t}");
    }
}

/// The fur flows along each vertex's bone away from the hips, except along the chain
/// from the hips to the front-most joint (the head), where it runs back towards the
/// tail: −z on the hips, spine and head; −y down the leg and the paw.
#[test]
fn fur_flows_back_along_the_spine_and_down_the_legs() {
    let rig = stick();
    let flow = fur_flow(&rig);
    assert_eq!(flow.directions.len(), rig.bind_positions.len());
    for (v, (f, w)) in flow.directions.iter().zip(&flow.one_bone).enumerate() {
        let heaviest = rig.weights[v].iter().copied().fold(0.0, f32::max);
        assert_eq!(*w, heaviest, "vertex {v}: the heaviest weight");
        let expected = if rig.influences[v][0] < 3 {
            -Vec3::Z
        } else {
            -Vec3::Y
        };
        assert!(close(*f, expected), "vertex {v}: {f}, not {expected}");
    }
    let body = SkinnedBody::new(&stick_mesh(&rig), rig.clone());
    assert_eq!(body.vertex_count(), rig.bind_positions.len());
}

/// A mesh vertex-aligned with the rig (no triangles: only what [`SkinnedBody`] reads).
pub(crate) fn stick_mesh(rig: &Rig) -> crate::scene::Mesh {
    crate::scene::Mesh {
        positions: rig.bind_positions.clone(),
        normals: rig.bind_normals.clone(),
        indices: Vec::new(),
        uvs: Vec::new(),
        texture: None,
    }
}

/// A scene's animation names a clip in any case, `none` holds the rest pose, and no
/// name plays the first clip; a clip for a body without a rig, an unknown clip, a speed
/// outside [0, 100] and a start before 0 are refused.
#[test]
fn an_animation_resolves_its_clip_and_refuses_what_cannot_play() {
    let rig = stick();
    let spec = |clip: Option<&str>, speed: f32, start: f32| AnimationSpec {
        clip: clip.map(str::to_string),
        speed,
        start,
        ..AnimationSpec::default()
    };
    let clip = |s: AnimationSpec, rig: Option<Rig>| {
        s.resolve(rig, "stick")
            .map(|r| r.map(|(_, playback)| playback.clip))
            .map_err(|e| e.to_string())
    };
    assert_eq!(
        clip(spec(Some("wALK"), 1.0, 0.0), Some(rig.clone())),
        Ok(Some(Some(0)))
    );
    assert_eq!(
        clip(spec(None, 100.0, 3.0), Some(rig.clone())),
        Ok(Some(Some(0)))
    );
    assert_eq!(
        clip(spec(Some("none"), 0.0, 0.0), Some(rig.clone())),
        Ok(Some(None))
    );
    let mut still = rig.clone();
    still.clips.clear();
    assert_eq!(clip(spec(None, 1.0, 0.0), Some(still)), Ok(Some(None)));
    assert_eq!(clip(spec(None, 1.0, 0.0), None), Ok(None));
    assert_eq!(clip(spec(Some("none"), 1.0, 0.0), None), Ok(None));
    let refused = |s: AnimationSpec, rig: Option<Rig>, why: &str| {
        let e = s.resolve(rig, "stick").unwrap_err().to_string();
        assert!(e.contains(why), "{e:?} does not say {why:?}");
    };
    refused(
        spec(Some("walk"), 1.0, 0.0),
        None,
        "model stick has no skin",
    );
    refused(spec(Some("run"), 1.0, 0.0), Some(rig.clone()), "run");
    for speed in [-0.5, 100.5, f32::NAN, f32::INFINITY] {
        refused(
            spec(None, speed, 0.0),
            Some(rig.clone()),
            "speed must be in [0, 100]",
        );
    }
    for start in [-0.5, f32::NAN, f32::INFINITY] {
        refused(spec(None, 1.0, start), Some(rig.clone()), "start must be");
    }
}
