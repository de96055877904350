//! Writing with `write_glb` and reading back: rigs, UV seams, scale, node order,
//! warnings, and the built-in critter through `fur export-model`.

use fur_core::scene::{
    load_gltf, write_glb, Channel, Clip, Interpolation, Joint, Mesh, Node, Property, Rig, Transform,
};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

use super::*;

/// Linear blend skinning at rest, as the reader does it.
fn skin_at_rest(rig: &Rig) -> Vec<Vec3> {
    let mut global: Vec<Mat4> = Vec::new();
    for node in &rig.nodes {
        let above = node.parent.map_or(Mat4::IDENTITY, |p| global[p]);
        global.push(above * node.rest.matrix());
    }
    let joints: Vec<Mat4> = rig
        .joints
        .iter()
        .map(|j| global[j.node] * j.inverse_bind)
        .collect();
    rig.bind_positions
        .iter()
        .zip(rig.influences.iter().zip(&rig.weights))
        .map(|(p, (i, w))| {
            (0..4)
                .map(|k| w[k] * joints[i[k] as usize].transform_point3(*p))
                .sum()
        })
        .collect()
}

/// A three-node arm with two joints and a clip of each interpolation, and its mesh: a
/// strip of 8 vertices up the arm whose corners agree on their texture coordinates.
fn arm() -> (Mesh, Rig) {
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
            Vec3::new(0.1, 1.0, -0.3),
            Quat::from_rotation_y(0.3),
            Vec3::ONE,
        ),
        node(
            "upper",
            Some(0),
            Vec3::new(0.0, 0.5, 0.0),
            Quat::from_euler(glam::EulerRot::XYZ, 0.2, -0.7, 0.1),
            Vec3::ONE,
        ),
        node(
            "lower",
            Some(1),
            Vec3::new(0.0, 0.45, 0.01),
            Quat::IDENTITY,
            Vec3::new(1.0, 1.2, 0.9),
        ),
    ];
    let mut global: Vec<Mat4> = Vec::new();
    for n in &nodes {
        let above = n.parent.map_or(Mat4::IDENTITY, |p| global[p]);
        global.push(above * n.rest.matrix());
    }
    let joints = vec![
        Joint {
            node: 1,
            inverse_bind: global[1].inverse(),
        },
        Joint {
            node: 2,
            inverse_bind: global[2].inverse(),
        },
    ];
    let bind_positions: Vec<Vec3> = (0..8)
        .map(|k| {
            global[0].transform_point3(Vec3::new(
                0.1 * (k % 2) as f32 - 0.05,
                0.5 + 0.15 * (k / 2) as f32,
                0.03,
            ))
        })
        .collect();
    let bind_normals = (0..8)
        .map(|k| Vec3::new(0.1 * k as f32, 0.2, 1.0).normalize())
        .collect();
    let weights = vec![
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
        [0.75, 0.25, 0.0, 0.0],
        [0.7, 0.3, 0.0, 0.0],
        [0.4, 0.6, 0.0, 0.0],
        [0.5, 0.5, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.1, 0.9, 0.0, 0.0],
    ];
    let influences = vec![[0, 1, 0, 0]; 8];
    let q = |angle: f32| Vec4::from(Quat::from_rotation_z(angle));
    let clips = vec![
        Clip {
            name: "wave".into(),
            channels: vec![
                Channel {
                    node: 0,
                    property: Property::Translation,
                    interpolation: Interpolation::Step,
                    times: vec![0.0, 0.4, 1.1],
                    values: vec![
                        Vec4::new(0.1, 1.0, -0.3, 0.0),
                        Vec4::new(0.2, 1.1, -0.3, 0.0),
                        Vec4::new(0.0, 0.9, 0.7, 0.0),
                    ],
                },
                Channel {
                    node: 1,
                    property: Property::Rotation,
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 0.7],
                    values: vec![q(0.0), q(1.3)],
                },
                Channel {
                    node: 2,
                    property: Property::Scale,
                    interpolation: Interpolation::CubicSpline,
                    times: vec![0.1, 0.9],
                    values: vec![
                        Vec4::new(0.0, 0.1, 0.0, 0.0),
                        Vec4::ONE.truncate().extend(0.0),
                        Vec4::new(0.3, -0.2, 0.1, 0.0),
                        Vec4::new(0.5, 0.5, 0.5, 0.0),
                        Vec4::new(1.0, 1.5, 1.25, 0.0),
                        Vec4::ZERO,
                    ],
                },
            ],
        },
        Clip {
            name: "twist".into(),
            channels: vec![Channel {
                node: 2,
                property: Property::Rotation,
                interpolation: Interpolation::CubicSpline,
                times: vec![0.0],
                values: vec![Vec4::ZERO, q(-0.4), Vec4::ZERO],
            }],
        },
    ];
    let rig = Rig {
        nodes,
        joints,
        influences,
        weights,
        bind_positions,
        bind_normals,
        clips,
        scale: 1.0,
    };
    let indices = vec![0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5, 4, 5, 6, 6, 5, 7];
    let uv = |v: u32| Vec2::new((v % 2) as f32, 0.25 * (v / 2) as f32);
    let mesh = Mesh {
        positions: skin_at_rest(&rig),
        normals: vec![Vec3::Z; 8],
        uvs: indices.iter().map(|&v| uv(v)).collect(),
        indices,
        texture: None,
    };
    rig.validate(8).unwrap();
    (mesh, rig)
}

fn close(a: &[Vec3], b: &[Vec3], tolerance: f32) {
    assert_eq!(a.len(), b.len());
    for (k, (p, q)) in a.iter().zip(b).enumerate() {
        assert!((*p - *q).length() <= tolerance, "vertex {k}: {p} vs {q}");
    }
}

#[test]
fn a_written_rig_reads_back_equal() {
    let dir = Scratch::new("round-trip");
    let (mesh, rig) = arm();
    let bytes = write_glb(&mesh, Some(&rig)).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(bytes.len() % 4, 0);
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );
    let path = dir.write("arm.glb", &bytes);
    let body = load_gltf(&path).unwrap();
    assert!(body.warnings.is_empty(), "{:?}", body.warnings);
    assert_eq!(body.rig.as_ref(), Some(&rig));
    assert_eq!(body.mesh.indices, mesh.indices);
    assert_eq!(body.mesh.uvs, mesh.uvs);
    close(&body.mesh.positions, &mesh.positions, 1e-5);
    // A second round trip changes nothing.
    let again = write_glb(&body.mesh, body.rig.as_ref()).unwrap();
    assert_eq!(again, bytes);
}

#[test]
fn corners_that_disagree_on_uvs_split_their_vertex() {
    let dir = Scratch::new("uv-split");
    let (mut mesh, rig) = arm();
    // Vertex 2 is used by three triangles; give its corner in the second one its own UV.
    let corner = mesh
        .indices
        .iter()
        .enumerate()
        .filter(|(_, &v)| v == 2)
        .nth(1)
        .unwrap()
        .0;
    mesh.uvs[corner] = Vec2::new(0.9, 0.9);
    let path = dir.write("split.glb", write_glb(&mesh, Some(&rig)).unwrap());
    let body = load_gltf(&path).unwrap();
    assert_eq!(body.mesh.vertex_count(), 9, "vertex 2 written twice");
    assert_eq!(body.mesh.uvs, mesh.uvs);
    assert_eq!(body.mesh.indices[corner], 8);
    let read = body.rig.unwrap();
    assert_eq!(read.bind_positions[8], rig.bind_positions[2]);
    assert_eq!(read.weights[8], rig.weights[2]);
    // Without a rig: the mesh alone, positions as they are.
    let path = dir.write("plain.glb", write_glb(&mesh, None).unwrap());
    let body = load_gltf(&path).unwrap();
    assert!(body.rig.is_none());
    assert_eq!(&body.mesh.positions[..8], &mesh.positions[..]);
}

#[test]
fn a_rig_scale_is_baked_into_its_roots() {
    let dir = Scratch::new("scale");
    let (mesh, mut rig) = arm();
    rig.scale = 2.0;
    let scaled: Vec<Vec3> = mesh.positions.iter().map(|p| *p * 2.0).collect();
    let path = dir.write("big.glb", write_glb(&mesh, Some(&rig)).unwrap());
    let body = load_gltf(&path).unwrap();
    let read = body.rig.unwrap();
    assert_eq!(read.scale, 1.0);
    assert_eq!(read.nodes[0].rest.scale, Vec3::splat(2.0));
    close(&body.mesh.positions, &scaled, 1e-5);
}

#[test]
fn nodes_come_parents_first_with_their_names() {
    let dir = Scratch::new("order");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let t = doc.floats(&[0.0, 1.0], "SCALAR");
    let s = doc.floats(&[1.0, 1.0, 1.0, 2.0, 2.0, 2.0], "VEC3");
    // Node 0 is a child of node 2, which is a child of node 1: stored children first.
    let path = dir.write(
        "order.glb",
        doc.glb(&format!(
            r#","nodes":[{{"mesh":0,"translation":[0,0,1]}},{{"name":"hips","children":[2]}},{{"children":[0],"scale":[2,2,2]}},{{"name":"elsewhere"}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}],
            "animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"scale"}}}},{{"sampler":0,"target":{{"node":3,"path":"scale"}}}}],
              "samplers":[{{"input":{t},"output":{s}}}]}}],
            "scenes":[{{"nodes":[1]}},{{"nodes":[3]}}]"#
        )),
    );
    let body = load_gltf(&path).unwrap();
    let rig = body.rig.unwrap();
    let names: Vec<(&str, Option<usize>)> = rig
        .nodes
        .iter()
        .map(|n| (n.name.as_str(), n.parent))
        .collect();
    assert_eq!(
        names,
        [("hips", None), ("node2", Some(0)), ("node0", Some(1))]
    );
    assert_eq!(rig.joints[0].node, 2);
    assert_eq!(rig.clips[0].channels.len(), 1);
    assert_eq!(rig.clips[0].channels[0].node, 2);
    assert!(
        body.warnings
            .iter()
            .any(|w| w.contains("node 3, which is not in the scene")),
        "{:?}",
        body.warnings
    );
    // Placed by both ancestors: scaled by 2 after moving up by 1.
    assert_eq!(body.mesh.positions[0], Vec3::new(0.0, 0.0, 2.0));
    assert_eq!(rig.bind_positions[0], Vec3::new(0.0, 0.0, 2.0));
}

#[test]
fn unusable_parts_are_warnings_naming_them() {
    let dir = Scratch::new("warnings");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let j = doc.u8s(&[0; 12], "VEC4", false);
    let w = doc.floats(&[1.0, 0.0, 0.0, 0.0].repeat(3), "VEC4");
    let path = dir.write(
        "extras.glb",
        doc.glb(&format!(
            r#","extensionsUsed":["KHR_lights_punctual"],"cameras":[{{"type":"perspective","perspective":{{"yfov":1,"znear":0.1}}}}],
            "nodes":[{{"name":"bone","children":[1]}},{{"mesh":0,"skin":0}}],"skins":[{{"joints":[0]}}],
            "meshes":[{{"primitives":[
                {{"attributes":{{"POSITION":{p},"JOINTS_0":{j},"WEIGHTS_0":{w},"JOINTS_1":{j},"WEIGHTS_1":{w}}},"targets":[{{"POSITION":{p}}}]}},
                {{"attributes":{{"POSITION":{p}}},"mode":1}}]}}]"#
        )),
    );
    let body = load_gltf(&path).unwrap();
    let warnings = body.warnings.join("\n");
    for needle in [
        "KHR_lights_punctual",
        "camera",
        "morph targets",
        "JOINTS_1",
        "lines (LINES)",
    ] {
        assert!(
            warnings.contains(needle),
            "no warning about {needle}:\n{warnings}"
        );
    }
    assert_eq!(body.mesh.vertex_count(), 3, "the line primitive is skipped");
    // The node that holds the skinned mesh (and a skipped line primitive) is no joint.
    assert_eq!(body.rig.unwrap().nodes.len(), 1);
}
