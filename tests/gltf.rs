//! glTF 2.0 input and output: skinned and animated bodies read from `.gltf` and `.glb`
//! files made here, written back with `write_glb`, and bad files refused with messages
//! that name the file and the problem. Pure Rust, no GPU.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use base64::Engine as _;
use fur::scene::{
    load_gltf, write_glb, Channel, Clip, Interpolation, Joint, Mesh, Node, Property, Rig,
    TextureSpec, Transform,
};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

/// A scratch folder for one test, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("fur-gltf-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A glTF document under construction: its binary buffer, buffer views and accessors;
/// the rest of the JSON is given as text.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

const FLOAT: u32 = 5126;
const UBYTE: u32 = 5121;
const USHORT: u32 = 5123;

impl Doc {
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: u32,
        ty: &str,
        normalized: bool,
    ) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend_from_slice(bytes);
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":{component},"count":{count},"type":"{ty}","normalized":{normalized}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, data.len() / dims(ty), FLOAT, ty, false)
    }

    fn u8s(&mut self, data: &[u8], ty: &str, normalized: bool) -> usize {
        self.accessor(data, data.len() / dims(ty), UBYTE, ty, normalized)
    }

    fn u16s(&mut self, data: &[u16], ty: &str) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, data.len() / dims(ty), USHORT, ty, false)
    }

    /// The JSON text with `buffer` as buffer 0's object and `rest` (`,"nodes":...`).
    fn json(&self, buffer: &str, rest: &str) -> String {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{buffer}],"bufferViews":[{}],"accessors":[{}]{rest}}}"#,
            self.views.join(","),
            self.accessors.join(",")
        )
    }

    fn glb(&self, rest: &str) -> Vec<u8> {
        glb(
            &self.json(&format!(r#"{{"byteLength":{}}}"#, self.bin.len()), rest),
            &self.bin,
        )
    }
}

fn dims(ty: &str) -> usize {
    match ty {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        _ => 16,
    }
}

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.len() + pad(bin.len());
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json.as_bytes());
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.extend(std::iter::repeat_n(0, pad(bin.len())));
    out
}

const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// A triangle skinned to one bone (translated by +x), the mesh node's own transform
/// (ignored) far away, with a clip turning the bone; `weights` and `joints` per vertex.
fn one_bone(joints: &[u8], weights: &[f32], times: &[f32]) -> Vec<u8> {
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let j = doc.u8s(joints, "VEC4", false);
    let w = doc.floats(weights, "VEC4");
    let t = doc.floats(times, "SCALAR");
    let values: Vec<f32> = (0..times.len())
        .flat_map(|k| Quat::from_rotation_z(0.5 * k as f32).to_array())
        .collect();
    let r = doc.floats(&values, "VEC4");
    doc.glb(&format!(
        r#","nodes":[{{"name":"bone","translation":[1,0,0]}},{{"name":"skinned","mesh":0,"skin":0,"translation":[100,100,100]}}],
        "skins":[{{"joints":[0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"JOINTS_0":{j},"WEIGHTS_0":{w}}}}}]}}],
        "animations":[{{"name":"wave","channels":[{{"sampler":0,"target":{{"node":0,"path":"rotation"}}}}],"samplers":[{{"input":{t},"output":{r}}}]}}],
        "scenes":[{{"nodes":[0,1]}}],"scene":0"#
    ))
}

#[test]
fn one_triangle_on_one_bone_brings_its_rig_and_clip() {
    let dir = Scratch::new("one-bone");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let j = doc.u16s(&[0; 12], "VEC4");
    // Normalised unsigned bytes: 255 is a weight of 1.
    let w = doc.u8s(&[255, 0, 0, 0, 128, 128, 0, 0, 255, 0, 0, 0], "VEC4", true);
    let uv = doc.u16s(&[0, 0, 65535, 0, 0, 65535], "VEC2");
    doc.accessors[uv] = doc.accessors[uv].replace("false", "true");
    let t = doc.floats(&[0.0, 1.0], "SCALAR");
    let r = doc.floats(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5f32.sin(), 0.5f32.cos()],
        "VEC4",
    );
    let path = dir.write(
        "bone.glb",
        doc.glb(&format!(
            r#","nodes":[{{"name":"bone","translation":[1,0,0]}},{{"mesh":0,"skin":0,"translation":[100,100,100]}}],
            "skins":[{{"joints":[0]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"JOINTS_0":{j},"WEIGHTS_0":{w},"TEXCOORD_0":{uv}}}}}]}}],
            "animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"rotation"}}}}],"samplers":[{{"input":{t},"output":{r}}}]}}],
            "scenes":[{{"nodes":[0,1]}}],"scene":0"#
        )),
    );
    let body = load_gltf(&path).unwrap();
    assert!(body.warnings.is_empty(), "{:?}", body.warnings);
    let rig = body.rig.expect("a skinned file has a rig");
    // The mesh node only holds the skinned mesh: it is not part of the rig.
    assert_eq!(
        rig.nodes,
        [Node {
            name: "bone".into(),
            parent: None,
            rest: Transform {
                translation: Vec3::X,
                ..Transform::default()
            },
        }]
    );
    assert_eq!(
        rig.joints,
        [Joint {
            node: 0,
            inverse_bind: Mat4::IDENTITY
        }]
    );
    assert_eq!(rig.influences, [[0; 4]; 3]);
    assert_eq!(rig.weights[0], [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(
        rig.weights[1],
        [0.5, 0.5, 0.0, 0.0],
        "128/255 twice, renormalised"
    );
    assert_eq!(rig.scale, 1.0);
    let triangle: Vec<Vec3> = TRIANGLE.chunks(3).map(Vec3::from_slice).collect();
    assert_eq!(rig.bind_positions, triangle);
    // Skinned at rest by the bone; the mesh node's own transform is ignored.
    let expected: Vec<Vec3> = triangle.iter().map(|p| *p + Vec3::X).collect();
    assert_eq!(body.mesh.positions, expected);
    assert_eq!(body.mesh.indices, [0, 1, 2]);
    assert!(body
        .mesh
        .normals
        .iter()
        .all(|n| (*n - Vec3::Z).length() < 1e-6));
    assert_eq!(
        body.mesh.uvs,
        [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]
    );
    assert_eq!(rig.clips.len(), 1);
    let clip = &rig.clips[0];
    assert_eq!(clip.name, "animation0");
    assert_eq!(
        clip.channels,
        [Channel {
            node: 0,
            property: Property::Rotation,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 1.0],
            values: vec![Vec4::W, Vec4::new(0.0, 0.0, 0.5f32.sin(), 0.5f32.cos())],
        }]
    );
    rig.validate(3).unwrap();
}

#[test]
fn unskinned_meshes_are_placed_by_their_nodes() {
    let dir = Scratch::new("two-meshes");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let n = doc.floats(&[0.0, 0.0, 1.0].repeat(3), "VEC3");
    let i = doc.u8s(&[0, 1, 2], "SCALAR", false);
    let turn = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let [x, y, z, w] = turn.to_array();
    let path = dir.write(
        "two.glb",
        doc.glb(&format!(
            r#","nodes":[{{"translation":[0,0,5],"children":[1]}},{{"mesh":0,"rotation":[{x},{y},{z},{w}],"scale":[2,2,2]}},{{"mesh":1,"matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 3,0,0,1]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}},"indices":{i}}}]}},{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}],
            "scenes":[{{"nodes":[0,2]}}]"#
        )),
    );
    let body = load_gltf(&path).unwrap();
    assert!(body.rig.is_none(), "no skin, no animation: just a mesh");
    let mesh = &body.mesh;
    assert_eq!(mesh.vertex_count(), 6);
    let first: Vec<Vec3> = TRIANGLE
        .chunks(3)
        .map(|p| Vec3::new(0.0, 0.0, 5.0) + turn * (2.0 * Vec3::from_slice(p)))
        .collect();
    for (a, b) in mesh.positions[..3].iter().zip(&first) {
        assert!((*a - *b).length() < 1e-5, "{a} vs {b}");
    }
    let second = [
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(3.0, 1.0, 0.0),
    ];
    assert_eq!(&mesh.positions[3..], &second);
    // The mirrored node's triangle is turned back to counter-clockwise.
    assert_eq!(mesh.indices, [0, 1, 2, 3, 5, 4]);
    // The second primitive has no normals: all come from the faces.
    for t in mesh.indices.chunks(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
        let face = (b - a).cross(c - a).normalize();
        for &v in t {
            assert!((mesh.normals[v as usize] - face).length() < 1e-5);
        }
    }
}

#[test]
fn a_gltf_reads_its_bin_file_and_its_texture() {
    let dir = Scratch::new("separate-bin");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let uv = doc.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2");
    dir.write("my mesh.bin", &doc.bin);
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255]))
        .save(dir.0.join("fur coat.png"))
        .unwrap();
    let json = |image: &str| {
        doc.json(
            &format!(r#"{{"byteLength":{},"uri":"my%20mesh.bin"}}"#, doc.bin.len()),
            &format!(
                r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"TEXCOORD_0":{uv}}},"material":0}}]}}],
                "materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
                "textures":[{{"source":0}}],"images":[{{"uri":"{image}"}}]"#
            ),
        )
    };
    let path = dir.write("model.gltf", json("fur%20coat.png"));
    let body = load_gltf(&path).unwrap();
    assert!(body.warnings.is_empty(), "{:?}", body.warnings);
    assert_eq!(body.mesh.vertex_count(), 3);
    assert_eq!(
        body.mesh.texture,
        Some(TextureSpec::File(dir.0.join("fur coat.png")))
    );
    let texture = body.mesh.texture.unwrap().load().unwrap();
    assert_eq!((texture.width, texture.height), (2, 2));

    let path = dir.write("gone.gltf", json("missing.png"));
    let body = load_gltf(&path).unwrap();
    assert_eq!(body.mesh.texture, None);
    let warning = body.warnings.join("\n");
    assert!(
        warning.contains("gone.gltf") && warning.contains("missing.png"),
        "{warning}"
    );
}

#[test]
fn embedded_buffers_and_images_need_no_other_file() {
    let dir = Scratch::new("embedded");
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(4, 2, image::Rgba([1, 2, 3, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let base64 = base64::engine::general_purpose::STANDARD;
    let rest = |image: &str| {
        format!(
            r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}},"material":0}}]}}],
            "materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
            "textures":[{{"source":0}}],"images":[{image}]"#
        )
    };
    let data_image = format!(
        r#"{{"uri":"data:image/png;base64,{}"}}"#,
        base64.encode(&png)
    );
    let json = doc.json(
        &format!(
            r#"{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}"#,
            doc.bin.len(),
            base64.encode(&doc.bin)
        ),
        &rest(&data_image),
    );
    let path = dir.write("inline.gltf", json);
    let body = load_gltf(&path).unwrap();
    assert_eq!(body.mesh.positions[1], Vec3::X);
    let Some(TextureSpec::Embedded { name, bytes }) = &body.mesh.texture else {
        panic!("{:?}", body.mesh.texture);
    };
    assert_eq!(name, "inline.gltf#image0");
    assert_eq!(&bytes[..], &png[..]);
    // An image in a buffer view of a .glb.
    let view = doc.accessor(&png, 1, UBYTE, "SCALAR", false);
    let path = dir.write(
        "packed.glb",
        doc.glb(&rest(&format!(
            r#"{{"bufferView":{view},"mimeType":"image/png"}}"#
        ))),
    );
    let texture = load_gltf(&path).unwrap().mesh.texture.unwrap();
    assert_eq!(texture.name(), "packed.glb#image0");
    let image = texture.load().unwrap();
    assert_eq!((image.width, image.height), (4, 2));
    // An embedded PNG is written into a .glb too.
    let mut mesh = load_gltf(&path).unwrap().mesh;
    mesh.texture = Some(texture);
    let path = dir.write("again.glb", write_glb(&mesh, None).unwrap());
    let Some(TextureSpec::Embedded { name, bytes }) = load_gltf(&path).unwrap().mesh.texture else {
        panic!("the texture was not written");
    };
    assert_eq!(name, "again.glb#image0");
    assert_eq!(&bytes[..], &png[..]);
}

#[test]
fn step_linear_and_cubic_channels_keep_their_keys() {
    let dir = Scratch::new("interpolations");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let t = doc.floats(&[0.0, 0.5, 2.0], "SCALAR");
    let step = doc.floats(&[0.0, 0.0, 0.0, 1.0, 2.0, 3.0, -1.0, 0.5, 0.25], "VEC3");
    let linear = doc.floats(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.6, 0.0, 0.8, 0.6, 0.0, 0.0, 0.8],
        "VEC4",
    );
    let t2 = doc.floats(&[0.0, 1.0], "SCALAR");
    let cubic_values: Vec<f32> = (0..18).map(|k| k as f32 * 0.5).collect();
    let cubic = doc.floats(&cubic_values, "VEC3");
    let path = dir.write(
        "keys.glb",
        doc.glb(&format!(
            r#","nodes":[{{"name":"body","mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}],
            "animations":[{{"name":"all","channels":[
                {{"sampler":0,"target":{{"node":0,"path":"translation"}}}},
                {{"sampler":1,"target":{{"node":0,"path":"rotation"}}}},
                {{"sampler":2,"target":{{"node":0,"path":"scale"}}}}],
              "samplers":[{{"input":{t},"output":{step},"interpolation":"STEP"}},
                {{"input":{t},"output":{linear},"interpolation":"LINEAR"}},
                {{"input":{t2},"output":{cubic},"interpolation":"CUBICSPLINE"}}]}}]"#
        )),
    );
    let body = load_gltf(&path).unwrap();
    let rig = body.rig.expect("an animated mesh node makes a rig");
    // The unskinned mesh gets a joint of its own, bound to its node.
    assert_eq!(rig.nodes.len(), 1);
    assert_eq!(rig.nodes[0].name, "body");
    assert_eq!(
        rig.joints,
        [Joint {
            node: 0,
            inverse_bind: Mat4::IDENTITY
        }]
    );
    assert_eq!(rig.weights, [[1.0, 0.0, 0.0, 0.0]; 3]);
    let channels = &rig.clips[0].channels;
    assert_eq!(rig.clips[0].name, "all");
    let v3 = |v: &[f32]| -> Vec<Vec4> {
        v.chunks(3)
            .map(|c| Vec4::new(c[0], c[1], c[2], 0.0))
            .collect()
    };
    assert_eq!(channels[0].interpolation, Interpolation::Step);
    assert_eq!(channels[0].property, Property::Translation);
    assert_eq!(channels[0].times, [0.0, 0.5, 2.0]);
    assert_eq!(
        channels[0].values,
        v3(&[0.0, 0.0, 0.0, 1.0, 2.0, 3.0, -1.0, 0.5, 0.25])
    );
    assert_eq!(channels[1].interpolation, Interpolation::Linear);
    assert_eq!(channels[1].values[1], Vec4::new(0.0, 0.6, 0.0, 0.8));
    assert_eq!(channels[2].interpolation, Interpolation::CubicSpline);
    assert_eq!(channels[2].property, Property::Scale);
    assert_eq!(
        channels[2].values,
        v3(&cubic_values),
        "in-tangent, value, out-tangent per key"
    );
}

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

/// The error `load_gltf` gives for `path`, checked to name the file.
fn refused(path: &Path) -> String {
    let start = Instant::now();
    let error = load_gltf(path)
        .expect_err("the file should be refused")
        .to_string();
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "took {:?}: {error}",
        start.elapsed()
    );
    assert!(
        error.contains(&path.display().to_string()),
        "the file is not named: {error}"
    );
    error
}

fn assert_names(error: &str, needle: &str) {
    assert!(error.contains(needle), "`{needle}` not in: {error}");
}

#[test]
fn broken_containers_and_buffers_are_refused() {
    let dir = Scratch::new("containers");
    let good = one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0].repeat(3), &[0.0, 1.0]);
    let total = good.len();
    let path = dir.write("cut.glb", &good[..120]);
    assert_names(
        &refused(&path),
        &format!("truncated .glb: the header says {total} bytes, the file has 120"),
    );
    let path = dir.write("tiny.glb", b"glTF\x02\0\0\0\x05\0\0\0");
    assert_names(&refused(&path), "too few");
    let path = dir.write("short.glb", b"glTF\x02\0");
    assert_names(&refused(&path), "12-byte header");
    let path = dir.write("garbage.glb", [7u8; 64]);
    assert_names(&refused(&path), "not a glTF file");
    let path = dir.write(
        "old.gltf",
        r#"{"asset":{"version":"1.0"},"meshes":{"a":{}}}"#,
    );
    assert_names(&refused(&path), "glTF 1.0");

    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let rest = format!(
        r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}]"#
    );
    let with_uri = |uri: &str| doc.json(&format!(r#"{{"byteLength":36,"uri":"{uri}"}}"#), &rest);
    let path = dir.write("scene.gltf", with_uri("scene.bin"));
    assert_names(
        &refused(&path),
        "buffer 0 (scene.bin) cannot be read: no such file",
    );
    let path = dir.write("web.gltf", with_uri("https://example.com/scene.bin"));
    assert_names(&refused(&path), "http(s) URLs are not fetched");
    let path = dir.write("absolute.gltf", with_uri("/etc/passwd"));
    assert_names(&refused(&path), "absolute path");
    std::fs::create_dir_all(dir.0.join("folder.bin")).unwrap();
    let path = dir.write("folder.gltf", with_uri("folder.bin"));
    assert_names(&refused(&path), "a folder");
    dir.write("small.bin", [0u8; 20]);
    let path = dir.write("small.gltf", with_uri("small.bin"));
    assert_names(
        &refused(&path),
        "buffer 0 (small.bin) has 20 bytes, but its byteLength says 36",
    );
    let path = dir.write("draco.gltf", with_uri("x.bin").replace(
        r#""asset":{"version":"2.0"}"#,
        r#""asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"]"#,
    ));
    assert_names(
        &refused(&path),
        "requires the glTF extension(s) KHR_draco_mesh_compression",
    );
}

#[test]
fn out_of_bounds_and_absurd_accessors_are_refused_before_allocating() {
    let dir = Scratch::new("bounds");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let rest = format!(
        r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}]"#
    );
    let original = doc.accessors[p].clone();
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":4"#);
    let path = dir.write("overrun.glb", doc.glb(&rest));
    assert_names(
        &refused(&path),
        "accessor 0 (POSITION of mesh 0 primitive 0) reaches byte 48 of a 36-byte buffer view 0",
    );
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":2147483648"#);
    let path = dir.write("huge.glb", doc.glb(&rest));
    let start = Instant::now();
    let error = refused(&path);
    assert!(
        start.elapsed() < Duration::from_millis(500),
        "{:?}",
        start.elapsed()
    );
    assert_names(
        &error,
        "accessor 0 (POSITION of mesh 0 primitive 0) reaches byte 25769803776",
    );
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":3,"byteOffset":4294967296"#);
    let path = dir.write("far.glb", doc.glb(&rest));
    assert_names(&refused(&path), "reaches byte 4294967332");
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":3,"sparse":{"count":1,"indices":{"bufferView":0,"componentType":5121},"values":{"bufferView":0}}"#);
    let path = dir.write("sparse.glb", doc.glb(&rest));
    assert_names(&refused(&path), "sparse accessors are not supported");
    doc.accessors[p] = original.clone();
    // The buffer view claims more than the buffer holds.
    doc.views[0] = doc.views[0].replace(r#""byteLength":36"#, r#""byteLength":4000000000"#);
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":300000000"#);
    let path = dir.write("view.glb", doc.glb(&rest));
    assert_names(
        &refused(&path),
        "buffer view 0 reaches byte 4000000000 of the 36-byte buffer 0",
    );
    doc.views[0] = doc.views[0].replace(r#""byteLength":4000000000"#, r#""byteLength":36"#);
    doc.accessors[p] = original;
    // Indices naming missing things, which panic the gltf crate's own validation.
    let path = dir.write(
        "index.glb",
        doc.glb(&rest.replace(&format!(r#""POSITION":{p}"#), r#""POSITION":7"#)),
    );
    assert_names(
        &refused(&path),
        "accessor 7 (POSITION of mesh 0 primitive 0) does not exist",
    );
    let path = dir.write(
        "node.glb",
        doc.glb(&format!(r#"{rest},"scenes":[{{"nodes":[3]}}]"#)),
    );
    assert_names(
        &refused(&path),
        "scene 0 lists node 3, which does not exist",
    );
    let path = dir.write(
        "cycle.glb",
        doc.glb(
            &rest
                .replace(r#""mesh":0}"#, r#""mesh":0,"children":[0]}"#)
                .replace("\"nodes\":[", "\"scenes\":[{\"nodes\":[0]}],\"nodes\":["),
        ),
    );
    assert_names(&refused(&path), "node 0 is reached twice");
}

#[test]
fn bad_skins_and_keys_are_refused_naming_them() {
    let dir = Scratch::new("skins");
    let one = [1.0, 0.0, 0.0, 0.0];
    let cases: [(&str, Vec<u8>, &str); 6] = [
        ("joint.glb", one_bone(&[0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 0, 0], &one.repeat(3), &[0.0, 1.0]), "JOINTS_0 of mesh 0 primitive 0: vertex 1 names joint 3, but skin 0 has 1 joints"),
        ("nan.glb", one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0, f32::NAN, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[0.0, 1.0]), "WEIGHTS_0 of mesh 0 primitive 0: vertex 1 has the weight NaN"),
        ("zero.glb", one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[0.0, 1.0]), "vertex 1's weights [0.0, 0.0, 0.0, 0.0] sum to 0"),
        ("negative.glb", one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0, 1.5, -0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[0.0, 1.0]), "vertex 1 has the weight -0.5"),
        ("keys.glb", one_bone(&[0; 12], &one.repeat(3), &[0.0, 1.0, 1.0]), "animation 0 (`wave`) channel 0: key times must increase, but key 2 at 1 s is not after key 1 at 1 s"),
        ("nan-key.glb", one_bone(&[0; 12], &one.repeat(3), &[0.0, f32::NAN]), "key 1's time NaN is not finite"),
    ];
    for (name, bytes, needle) in cases {
        let path = dir.write(name, bytes);
        assert_names(&refused(&path), needle);
    }
    // No triangles: only points.
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let path = dir.write("points.glb", doc.glb(&format!(r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}},"mode":0}}]}}]"#)));
    assert_names(&refused(&path), "no triangles");
    let path = dir.write("empty.glb", doc.glb(""));
    assert_names(&refused(&path), "no triangles");
}

#[test]
fn folders_and_fifos_are_refused_without_blocking() {
    let dir = Scratch::new("special");
    let folder = dir.0.join("model.glb");
    std::fs::create_dir_all(&folder).unwrap();
    assert_names(&refused(&folder), "a folder");
    let fifo = dir.0.join("pipe.glb");
    let status = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(status.success());
    let (send, receive) = std::sync::mpsc::channel();
    let path = fifo.clone();
    std::thread::spawn(move || {
        let _ = send.send(load_gltf(&path).map(|_| ()).map_err(|e| e.to_string()));
    });
    match receive.recv_timeout(Duration::from_secs(10)) {
        Ok(result) => assert_names(
            &result.expect_err("a FIFO is refused"),
            "a FIFO (named pipe), not a regular file",
        ),
        Err(_) => {
            // Unblock the reader before failing.
            let _ = std::fs::OpenOptions::new().write(true).open(&fifo);
            panic!("load_gltf blocked on a FIFO");
        }
    }
    assert_names(&refused(&dir.0.join("absent.glb")), "no such file");
}

/// `fur export-model --model critter critter.glb` writes the built-in creature, and
/// loading the file gives the same body, skin and animation.
#[test]
fn the_built_in_critter_round_trips_through_export_model() {
    let dir = std::env::temp_dir().join(format!("fur-critter-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("critter.glb");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["export-model", "--model", "critter"])
        .arg(&path)
        .status()
        .unwrap();
    assert!(status.success());
    let (mesh, rig) = fur::scene::critter();
    let body = fur::scene::load_gltf(&path).unwrap();
    assert!(body.warnings.is_empty(), "{:?}", body.warnings);
    assert_eq!(body.rig.as_ref(), Some(&rig), "the rig changed on the way");
    assert_eq!(body.mesh.indices, mesh.indices);
    assert_eq!(body.mesh.uvs, mesh.uvs);
    let moved = body
        .mesh
        .positions
        .iter()
        .zip(&mesh.positions)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(moved < 1e-5, "rest positions moved by {moved}");
    let clips: Vec<&str> = rig.clips.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(clips, ["Walk", "Idle"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `fur render --model` takes glTF files, and a broken one is a clean error naming the
/// file and the problem (exit 1, no panic), like a broken OBJ.
#[test]
fn the_command_line_refuses_a_broken_glb_by_name() {
    let dir = std::env::temp_dir().join(format!("fur-broken-glb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("critter.glb");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["export-model", "--model", "critter"])
        .arg(&good)
        .status()
        .unwrap();
    assert!(status.success());
    let bytes = std::fs::read(&good).unwrap();
    let broken = dir.join("truncated.glb");
    std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["render", "--width", "32", "--height", "24", "--model"])
        .arg(&broken)
        .arg("--out")
        .arg(dir.join("out.png"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("truncated.glb") && stderr.contains("truncated"),
        "{stderr}"
    );
    // An unknown clip names the clips there are.
    let out = render_animated(&good, "gallop", &dir.join("out.png"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("gallop") && stderr.contains("Walk") && stderr.contains("Idle"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `fur render` of `model` playing clip `animation`, a 32×24 image to `out`.
fn render_animated(
    model: &std::path::Path,
    animation: &str,
    out: &std::path::Path,
) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args([
            "render",
            "--width",
            "32",
            "--height",
            "24",
            "--animation",
            animation,
        ])
        .arg("--model")
        .arg(model)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// A skinned body whose mesh is open (one triangle on one bone) renders, with the same
/// warning as an open OBJ: its distance field's sign is estimated near the holes.
#[test]
fn an_open_skinned_body_gets_the_open_mesh_warning() {
    let dir = Scratch::new("open-skin");
    let weights: Vec<f32> = [1.0, 0.0, 0.0, 0.0].repeat(3);
    let path = dir.write("open.glb", one_bone(&[0; 12], &weights, &[0.0, 1.0]));
    let out = render_animated(&path, "wave", &dir.0.join("open.png"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("open.glb") && stderr.contains("is not a closed"),
        "{stderr}"
    );
}
