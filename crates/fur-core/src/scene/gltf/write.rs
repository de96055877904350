//! Writing a body as a binary glTF (`.glb`): the mesh, and with a rig its nodes, skin
//! and clips, so that [`super::load_gltf`] reads back the same rig.

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use gltf::json;
use gltf::json::accessor::{ComponentType, Type};
use gltf::json::buffer::Target;
use gltf::json::validation::Checked;

use super::super::{Mesh, Property, Rig};
use super::builder::Doc;
use crate::error::{Error, Result};

/// Serialises a body as a `.glb` in memory: a 12-byte header, the JSON chunk (padded
/// with spaces) and the BIN chunk (padded with zeros), each 4-byte aligned.
///
/// Without a rig: the mesh's positions, normals and texture coordinates on one node.
/// With a rig (checked with [`Rig::validate`] first): positions and normals are the
/// rig's bind positions and normals, `JOINTS_0` (u16) and `WEIGHTS_0` (f32) its
/// influences and weights; the nodes are the rig's nodes in their order (names, TRS),
/// followed by one root node holding the mesh and the one skin (the rig's joints in
/// order, with their inverse bind matrices); each clip is an animation with one
/// sampler per channel, its interpolation kept. A rig whose `scale` is not 1 has it
/// baked into its root nodes (their rest translation and scale, and the translation
/// and scale keys of their channels), which moves every joint the same way.
///
/// glTF holds one texture coordinate per vertex and [`Mesh::uvs`] one per triangle
/// corner: a vertex whose corners disagree is written once per distinct coordinate
/// (its copies share everything else). A body whose corners agree is written with its
/// own vertices, so it reads back with the same vertex count and order. An embedded
/// PNG or JPEG texture ([`TextureSpec::Embedded`](crate::scene::TextureSpec::Embedded))
/// is written into the file; a texture file is not (a `.glb` in memory has no folder to
/// refer to it from).
pub fn write_glb(mesh: &Mesh, rig: Option<&Rig>) -> Result<Vec<u8>> {
    let error = |m: String| Error::Parameter(format!("the body cannot be written as glTF: {m}"));
    check_mesh(mesh).map_err(error)?;
    let rig = match rig {
        Some(rig) => {
            rig.validate(mesh.vertex_count()).map_err(error)?;
            Some(bake_scale(rig))
        }
        None => None,
    };
    let split = Split::new(mesh);
    let mut doc = Doc::default();
    let (positions, normals) = match &rig {
        Some(rig) => (&rig.bind_positions, &rig.bind_normals),
        None => (&mesh.positions, &mesh.normals),
    };
    let face_normals;
    let normals = if normals.len() == positions.len() {
        normals
    } else {
        face_normals = mesh.face_weighted_normals();
        &face_normals
    };
    let mut attributes = std::collections::BTreeMap::new();
    let pick = |v: &[Vec3]| -> Vec<Vec3> { split.source.iter().map(|&i| v[i as usize]).collect() };
    let written = pick(positions);
    let (min, max) = written.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let bounds = Some((min.to_array().to_vec(), max.to_array().to_vec()));
    let floats = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
    let position = doc.floats(
        &floats(&written),
        Type::Vec3,
        bounds,
        Some(Target::ArrayBuffer),
    );
    attributes.insert(Checked::Valid(json::mesh::Semantic::Positions), position);
    let normal = doc.floats(
        &floats(&pick(normals)),
        Type::Vec3,
        None,
        Some(Target::ArrayBuffer),
    );
    attributes.insert(Checked::Valid(json::mesh::Semantic::Normals), normal);
    if let Some(uvs) = &split.uvs {
        let data: Vec<f32> = uvs.iter().flat_map(|uv| uv.to_array()).collect();
        let uv = doc.floats(&data, Type::Vec2, None, Some(Target::ArrayBuffer));
        attributes.insert(Checked::Valid(json::mesh::Semantic::TexCoords(0)), uv);
    }
    if let Some(rig) = &rig {
        let joints: Vec<u8> = split
            .source
            .iter()
            .flat_map(|&i| rig.influences[i as usize])
            .flat_map(u16::to_le_bytes)
            .collect();
        let count = split.source.len();
        let joints = doc.accessor(
            &joints,
            count,
            ComponentType::U16,
            Type::Vec4,
            None,
            Some(Target::ArrayBuffer),
        );
        attributes.insert(Checked::Valid(json::mesh::Semantic::Joints(0)), joints);
        let weights: Vec<f32> = split
            .source
            .iter()
            .flat_map(|&i| rig.weights[i as usize])
            .collect();
        let weights = doc.floats(&weights, Type::Vec4, None, Some(Target::ArrayBuffer));
        attributes.insert(Checked::Valid(json::mesh::Semantic::Weights(0)), weights);
    }
    let index_bytes: Vec<u8> = split.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    let indices = doc.accessor(
        &index_bytes,
        split.indices.len(),
        ComponentType::U32,
        Type::Scalar,
        None,
        Some(Target::ElementArrayBuffer),
    );
    let material = mesh.texture.as_ref().and_then(|t| doc.texture(t));
    let primitive = json::mesh::Primitive {
        attributes,
        extensions: None,
        extras: Default::default(),
        indices: Some(indices),
        material,
        mode: Checked::Valid(json::mesh::Mode::Triangles),
        targets: None,
    };
    let mesh_index = doc.root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("body".into()),
        primitives: vec![primitive],
        weights: None,
    });
    let mut scene_nodes = Vec::new();
    match &rig {
        Some(rig) => {
            doc.rig(rig, &mut scene_nodes);
            let skin = doc.skin(rig);
            scene_nodes.push(doc.root.push(json::Node {
                mesh: Some(mesh_index),
                skin: Some(skin),
                name: Some("body".into()),
                ..Default::default()
            }));
            for clip in &rig.clips {
                doc.clip(clip);
            }
        }
        None => scene_nodes.push(doc.root.push(json::Node {
            mesh: Some(mesh_index),
            name: Some("body".into()),
            ..Default::default()
        })),
    }
    let scene = doc.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: scene_nodes,
    });
    doc.root.scene = Some(scene);
    doc.finish().map_err(error)
}

fn check_mesh(mesh: &Mesh) -> std::result::Result<(), String> {
    let n = mesh.positions.len();
    if u32::try_from(n).is_err() {
        return Err(format!("{n} vertices are more than 32-bit indices reach"));
    }
    if mesh.indices.len() % 3 != 0 {
        return Err(format!(
            "{} indices are not whole triangles",
            mesh.indices.len()
        ));
    }
    if let Some(k) = mesh.indices.iter().position(|&i| i as usize >= n) {
        return Err(format!(
            "index {k} is {}, past the {n} vertices",
            mesh.indices[k]
        ));
    }
    if !mesh.uvs.is_empty() && mesh.uvs.len() != mesh.indices.len() {
        return Err(format!(
            "{} texture coordinates for {} triangle corners",
            mesh.uvs.len(),
            mesh.indices.len()
        ));
    }
    if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "vertex {v}'s position {} is not finite",
            mesh.positions[v]
        ));
    }
    Ok(())
}

/// The rig with its scale moved into its root nodes (see [`write_glb`]).
fn bake_scale(rig: &Rig) -> Rig {
    let mut rig = rig.clone();
    let s = rig.scale;
    if s == 1.0 {
        return rig;
    }
    for node in rig.nodes.iter_mut().filter(|n| n.parent.is_none()) {
        node.rest.translation *= s;
        node.rest.scale *= s;
    }
    let roots: Vec<bool> = rig.nodes.iter().map(|n| n.parent.is_none()).collect();
    for channel in rig.clips.iter_mut().flat_map(|c| &mut c.channels) {
        if roots.get(channel.node) == Some(&true) && channel.property != Property::Rotation {
            channel.values.iter_mut().for_each(|v| *v *= s);
        }
    }
    rig.scale = 1.0;
    rig
}

/// The vertices written: per written vertex the mesh vertex it copies, the triangles
/// over them, and per written vertex its texture coordinate (when the mesh has them).
struct Split {
    source: Vec<u32>,
    indices: Vec<u32>,
    uvs: Option<Vec<Vec2>>,
}

impl Split {
    fn new(mesh: &Mesh) -> Self {
        let n = mesh.positions.len() as u32;
        let mut source: Vec<u32> = (0..n).collect();
        if mesh.uvs.len() != mesh.indices.len() || mesh.uvs.is_empty() {
            return Self {
                source,
                indices: mesh.indices.clone(),
                uvs: None,
            };
        }
        let mut uvs: Vec<Option<Vec2>> = vec![None; n as usize];
        let mut copies: HashMap<(u32, [u32; 2]), u32> = HashMap::new();
        let mut indices = Vec::with_capacity(mesh.indices.len());
        for (&i, &uv) in mesh.indices.iter().zip(&mesh.uvs) {
            let bits = [uv.x.to_bits(), uv.y.to_bits()];
            let same = |u: Vec2| [u.x.to_bits(), u.y.to_bits()] == bits;
            let written = match uvs[i as usize] {
                None => {
                    uvs[i as usize] = Some(uv);
                    i
                }
                Some(u) if same(u) => i,
                Some(_) => *copies.entry((i, bits)).or_insert_with(|| {
                    source.push(i);
                    uvs.push(Some(uv));
                    source.len() as u32 - 1
                }),
            };
            indices.push(written);
        }
        Self {
            source,
            indices,
            uvs: Some(uvs.into_iter().map(|u| u.unwrap_or(Vec2::ZERO)).collect()),
        }
    }
}
