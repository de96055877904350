//! Tests of the built-in creature: its surface, skeleton, weights and clips.

use std::collections::HashMap;

use super::*;
use crate::scene::Interpolation;

#[test]
fn print_the_critter() {
    let (mesh, rig) = critter();
    let (lo, hi) = mesh.aabb();
    let smallest_angle = mesh
        .indices
        .chunks_exact(3)
        .flat_map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
            [(a, b, c), (b, c, a), (c, a, b)].map(|(p, q, r)| (q - p).angle_between(r - p))
        })
        .fold(f32::MAX, f32::min);
    let clips: Vec<_> = rig.clips.iter().map(|c| (&c.name, c.duration())).collect();
    println!(
        "critter: {} vertices, {} triangles, bounds {lo} .. {hi}, smallest angle {:.1}°, {} nodes, clips {clips:?}",
        mesh.vertex_count(),
        mesh.triangle_count(),
        smallest_angle.to_degrees(),
        rig.nodes.len(),
    );
}

#[test]
fn the_surface_is_closed_outward_and_well_shaped() {
    let (mesh, _) = critter();
    assert!(
        (3000..=6000).contains(&mesh.vertex_count()),
        "{}",
        mesh.vertex_count()
    );
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let mut volume = 0.0;
    let shape: Vec<Part> = parts(&skeleton()).iter().map(|(_, p)| *p).collect();
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
        volume += a.dot(b.cross(c)) / 6.0;
        let outward = implicit::gradient(&shape, (a + b + c) / 3.0, 0.005);
        assert!((b - a).cross(c - a).dot(outward) > 0.0, "a fold at {a}");
        for (p, q, r) in [(a, b, c), (b, c, a), (c, a, b)] {
            let angle = (q - p).angle_between(r - p).to_degrees();
            assert!(angle > 8.0, "a sliver at {p}: {angle}°");
        }
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            *edges.entry((p.min(q), p.max(q))).or_default() += 1;
        }
    }
    assert!(
        edges.values().all(|&n| n == 2),
        "every edge between two triangles"
    );
    assert!(implicit::is_closed_manifold(
        mesh.vertex_count(),
        &mesh.indices
    ));
    assert!(volume > 0.05, "outward: volume {volume}");
    let euler = mesh.vertex_count() + mesh.triangle_count() - edges.len();
    assert_eq!(euler, 2, "one piece, no handles");
    // Normals: unit, and with the triangles around them.
    let faces = mesh.face_weighted_normals();
    let agree = faces
        .iter()
        .zip(&mesh.normals)
        .filter(|(f, n)| f.dot(**n) > 0.7)
        .count();
    assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    assert!(agree as f32 > 0.995 * mesh.vertex_count() as f32, "{agree}");
}

#[test]
fn it_is_fox_sized_and_stands_on_the_ground() {
    let (mesh, _) = critter();
    let (lo, hi) = mesh.aabb();
    assert!(lo.y.abs() < 0.01, "{lo}");
    assert!((0.9..1.0).contains(&hi.z), "nose at {}", hi.z);
    assert!(
        (1.2..1.4).contains(&hi.y) && (-1.25..-1.15).contains(&lo.z),
        "{lo} {hi}"
    );
    assert!(
        (lo.x + hi.x).abs() < 1e-3,
        "left and right mirror each other"
    );
}

#[test]
fn texture_coordinates_agree_at_every_corner_of_a_vertex() {
    let (mesh, _) = critter();
    assert_eq!(mesh.uvs.len(), mesh.indices.len());
    let mut seen: HashMap<u32, Vec2> = HashMap::new();
    for (&i, uv) in mesh.indices.iter().zip(&mesh.uvs) {
        assert!(
            (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y),
            "{uv}"
        );
        assert_eq!(*seen.entry(i).or_insert(*uv), *uv);
    }
    assert_eq!(mesh.texture, None);
}

#[test]
fn the_skeleton_has_every_named_node() {
    let (_, rig) = critter();
    let mut expected = vec![
        ("root", None),
        ("spine", Some("root")),
        ("chest", Some("spine")),
        ("neck", Some("chest")),
        ("head", Some("neck")),
        ("snout", Some("head")),
        ("ear.L", Some("head")),
        ("ear.R", Some("head")),
        ("tail.1", Some("root")),
        ("tail.2", Some("tail.1")),
        ("tail.3", Some("tail.2")),
    ];
    let legs: Vec<(String, String)> = ["front_leg.L", "front_leg.R", "hind_leg.L", "hind_leg.R"]
        .iter()
        .flat_map(|leg| {
            let top = if leg.starts_with("front") {
                "chest"
            } else {
                "root"
            };
            [
                (format!("{leg}.upper"), top.to_string()),
                (format!("{leg}.lower"), format!("{leg}.upper")),
                (format!("{leg}.paw"), format!("{leg}.lower")),
            ]
        })
        .collect();
    expected.extend(legs.iter().map(|(n, p)| (n.as_str(), Some(p.as_str()))));
    assert_eq!(rig.nodes.len(), expected.len());
    for (name, parent) in expected {
        let node = rig
            .nodes
            .iter()
            .position(|n| n.name == name)
            .unwrap_or_else(|| panic!("{name}"));
        let parent_index = rig.nodes[node].parent;
        assert_eq!(
            parent_index.map(|p| rig.nodes[p].name.as_str()),
            parent,
            "{name}"
        );
        assert!(parent_index.is_none_or(|p| p < node), "parents first");
    }
    assert_eq!(rig.joints.len(), rig.nodes.len());
    assert!(rig.joints.iter().enumerate().all(|(i, j)| j.node == i));
    assert_eq!(rig.scale, 1.0);
}

#[test]
fn weights_are_normalised_and_stay_on_their_side() {
    let (mesh, rig) = critter();
    assert_eq!(rig.bind_positions, mesh.positions);
    assert_eq!(rig.bind_normals, mesh.normals);
    assert_eq!(rig.influences.len(), mesh.vertex_count());
    assert_eq!(rig.weights.len(), mesh.vertex_count());
    let mut blended = 0;
    for ((j, w), p) in rig.influences.iter().zip(&rig.weights).zip(&mesh.positions) {
        assert!(w.iter().all(|w| w.is_finite() && *w >= 0.0), "{w:?}");
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{w:?}");
        assert!(j.iter().all(|&j| (j as usize) < rig.joints.len()));
        blended += usize::from(w[1] > 0.1);
        // A leg never pulls the body's far side.
        for (j, w) in j.iter().zip(w) {
            let name = &rig.nodes[rig.joints[*j as usize].node].name;
            let leg = name.contains("_leg");
            let far = leg
                && ((name.contains(".R") && p.x > 0.05) || (name.contains(".L") && p.x < -0.05));
            assert!(!far || *w == 0.0, "{name} pulls {p} by {w}");
        }
    }
    assert!(
        blended > mesh.vertex_count() / 5,
        "smooth, not rigid: {blended}"
    );
}

/// The world position of the node named `name` in a clip at time `t`, in place.
fn node_at(rig: &Rig, clip: usize, name: &str, t: f32) -> Vec3 {
    let node = rig.nodes.iter().position(|n| n.name == name).unwrap();
    rig.world(&rig.pose(Some(&rig.clips[clip]), t, true))[node]
        .w_axis
        .truncate()
}

#[test]
fn the_walk_trots_forwards_and_the_idle_wags() {
    let (_, rig) = critter();
    assert_eq!(rig.clip_index("walk"), Ok(0));
    assert_eq!(rig.clip_index("idle"), Ok(1));
    assert_eq!(rig.clips[0].duration(), 1.0);
    assert_eq!(rig.clips[1].duration(), 2.0);
    let leg = rig.nodes[bone_index(&rig, "front_leg.L.upper")]
        .rest
        .translation
        .y
        + 0.12;
    for paw in [
        "front_leg.L.paw",
        "front_leg.R.paw",
        "hind_leg.L.paw",
        "hind_leg.R.paw",
    ] {
        let moved = node_at(&rig, 0, paw, 0.0).distance(node_at(&rig, 0, paw, 0.5));
        assert!(moved > 0.1 * leg, "{paw} moved {moved}");
    }
    // Diagonal pairs: front left with hind right.
    let lift = |paw: &str| node_at(&rig, 0, paw, 0.75).y - node_at(&rig, 0, paw, 0.25).y;
    assert!(lift("front_leg.L.paw") > 0.03 && lift("hind_leg.R.paw") > 0.03);
    assert!(lift("front_leg.R.paw") < -0.03 && lift("hind_leg.L.paw") < -0.03);
    // Root motion: forwards along +z over the loop, held by `in_place`.
    let walk = Some(&rig.clips[0]);
    let (start, end) = (rig.pose(walk, 0.0, false)[0], rig.pose(walk, 1.0, false)[0]);
    assert!((end.translation.z - start.translation.z - STRIDE).abs() < 1e-5);
    assert_eq!(
        rig.pose(walk, 0.6, true)[0].translation.z,
        start.translation.z
    );
    let tip = node_at(&rig, 1, "tail.3", 0.0).distance(node_at(&rig, 1, "tail.3", 0.25));
    assert!(tip > 0.05, "the idle's tail tip moved {tip}");
    assert!(rig.clips[1]
        .channels
        .iter()
        .any(|c| c.interpolation == Interpolation::CubicSpline));
}

fn bone_index(rig: &Rig, name: &str) -> usize {
    rig.nodes.iter().position(|n| n.name == name).unwrap()
}

#[test]
fn both_clips_loop_seamlessly() {
    let (_, rig) = critter();
    for clip in &rig.clips {
        let (a, b) = (
            rig.pose(Some(clip), 0.0, true),
            rig.pose(Some(clip), clip.duration(), true),
        );
        for (i, (a, b)) in a.iter().zip(&b).enumerate() {
            let same = a.translation.abs_diff_eq(b.translation, 1e-5)
                && a.rotation.abs_diff_eq(b.rotation, 1e-5)
                && a.scale.abs_diff_eq(b.scale, 1e-5);
            assert!(same, "{} node {i}: {a:?} {b:?}", clip.name);
        }
    }
}

#[test]
fn the_critter_is_deterministic() {
    assert!(critter() == critter());
}

#[test]
fn bone_directions_run_down_the_legs_and_out_along_the_tail() {
    let (mesh, rig) = critter();
    let directions = rig.bone_directions();
    assert_eq!(directions.len(), mesh.vertex_count());
    for ((d, j), w) in directions.iter().zip(&rig.influences).zip(&rig.weights) {
        assert!((d.length() - 1.0).abs() < 1e-5);
        let heaviest = (0..4).max_by(|a, b| w[*a].total_cmp(&w[*b])).unwrap();
        let name = &rig.nodes[rig.joints[j[heaviest] as usize].node].name;
        if name.ends_with(".upper") || name.ends_with(".lower") {
            assert!(d.y < -0.7, "{name}: {d}");
        } else if name.starts_with("tail") {
            assert!(d.z < -0.8, "{name}: {d}");
        } else if name == "spine" || name == "head" {
            assert!(d.z > 0.9, "{name}: {d}");
        }
    }
}
