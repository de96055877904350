//! Reading: skinned and unskinned meshes, external and embedded buffers and images,
//! and every kind of animation channel.

use base64::Engine as _;
use fur_core::scene::{
    load_gltf, write_glb, Channel, Interpolation, Joint, Node, Property, TextureSpec, Transform,
};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

use super::*;

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
