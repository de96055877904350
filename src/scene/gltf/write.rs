//! Writing a body as a binary glTF (`.glb`): the mesh, and with a rig its nodes, skin
//! and clips, so that [`super::load_gltf`] reads back the same rig.

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};
use gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use gltf::json::buffer::Target;
use gltf::json::validation::{Checked, USize64};
use gltf::json::{self, Index};

use super::super::{Interpolation, Mesh, Property, Rig, TextureSpec};
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
/// PNG or JPEG texture ([`TextureSpec::Embedded`]) is written into the file; a texture
/// file is not (a `.glb` in memory has no folder to refer to it from).
pub fn write_glb(mesh: &Mesh, rig: Option<&Rig>) -> Result<Vec<u8>> {
    let error = |m: String| Error::Parameter(format!("the body cannot be written as glTF: {m}"));
    check_mesh(mesh).map_err(error)?;
    let rig = match rig {
        Some(rig) => {
            rig.validate(mesh.vertex_count()).map_err(error)?;
            check_nodes(rig).map_err(error)?;
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

/// Node transforms go into the JSON, which has no NaN or infinity; the rig check sees
/// to that, this names the node for the writer too.
fn check_nodes(rig: &Rig) -> std::result::Result<(), String> {
    match rig.nodes.iter().position(|n| {
        !(n.rest.translation.is_finite() && n.rest.rotation.is_finite() && n.rest.scale.is_finite())
    }) {
        Some(i) => Err(format!("node {i}'s rest transform is not finite")),
        None => Ok(()),
    }
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

/// The document being written and its binary chunk.
#[derive(Default)]
struct Doc {
    root: json::Root,
    bin: Vec<u8>,
}

impl Doc {
    /// A buffer view over `data` appended to the binary chunk (4-byte aligned).
    fn view(&mut self, data: &[u8], target: Option<Target>) -> Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(data);
        self.root.push(json::buffer::View {
            buffer: Index::new(0),
            byte_length: USize64::from(data.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Checked::Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    fn accessor(
        &mut self,
        data: &[u8],
        count: usize,
        component: ComponentType,
        ty: Type,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
        target: Option<Target>,
    ) -> Index<json::Accessor> {
        let view = self.view(data, target);
        let value = |v: Vec<f32>| json::Value::from(v);
        let (min, max) = bounds.map_or((None, None), |(lo, hi)| (Some(value(lo)), Some(value(hi))));
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(ty),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// An accessor of floats, `dims(ty)` per element.
    fn floats(
        &mut self,
        data: &[f32],
        ty: Type,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
        target: Option<Target>,
    ) -> Index<json::Accessor> {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let count = data.len() / super::accessor::dims(ty);
        self.accessor(&bytes, count, ComponentType::F32, ty, bounds, target)
    }

    /// The rig's nodes, in order; their roots go into `scene_nodes`.
    fn rig(&mut self, rig: &Rig, scene_nodes: &mut Vec<Index<json::Node>>) {
        let mut children: Vec<Vec<Index<json::Node>>> = vec![Vec::new(); rig.nodes.len()];
        for (i, node) in rig.nodes.iter().enumerate() {
            match node.parent {
                Some(p) => children[p].push(Index::new(i as u32)),
                None => scene_nodes.push(Index::new(i as u32)),
            }
        }
        for (node, children) in rig.nodes.iter().zip(children) {
            let t = &node.rest;
            self.root.push(json::Node {
                name: Some(node.name.clone()),
                children: (!children.is_empty()).then_some(children),
                translation: Some(t.translation.to_array()),
                rotation: Some(json::scene::UnitQuaternion(t.rotation.to_array())),
                scale: Some(t.scale.to_array()),
                ..Default::default()
            });
        }
    }

    /// The one skin: the rig's joints in order.
    fn skin(&mut self, rig: &Rig) -> Index<json::Skin> {
        let data: Vec<f32> = rig
            .joints
            .iter()
            .flat_map(|j| j.inverse_bind.to_cols_array())
            .collect();
        let matrices = self.floats(&data, Type::Mat4, None, None);
        self.root.push(json::Skin {
            extensions: None,
            extras: Default::default(),
            inverse_bind_matrices: Some(matrices),
            joints: rig
                .joints
                .iter()
                .map(|j| Index::new(j.node as u32))
                .collect(),
            name: None,
            skeleton: None,
        })
    }

    /// One animation per clip, one sampler per channel.
    fn clip(&mut self, clip: &super::super::Clip) {
        use json::animation::{Channel, Interpolation as I, Property as P, Sampler, Target};
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        for (c, channel) in clip.channels.iter().enumerate() {
            let (lo, hi) = channel
                .times
                .iter()
                .fold((f32::MAX, f32::MIN), |(lo, hi), &t| (lo.min(t), hi.max(t)));
            let input = self.floats(
                &channel.times,
                Type::Scalar,
                Some((vec![lo], vec![hi])),
                None,
            );
            let (ty, values): (Type, Vec<f32>) = match channel.property {
                Property::Rotation => (
                    Type::Vec4,
                    channel.values.iter().flat_map(|v| v.to_array()).collect(),
                ),
                _ => (
                    Type::Vec3,
                    channel
                        .values
                        .iter()
                        .flat_map(|v: &Vec4| v.truncate().to_array())
                        .collect(),
                ),
            };
            let output = self.floats(&values, ty, None, None);
            samplers.push(Sampler {
                extensions: None,
                extras: Default::default(),
                input,
                interpolation: Checked::Valid(match channel.interpolation {
                    Interpolation::Step => I::Step,
                    Interpolation::Linear => I::Linear,
                    Interpolation::CubicSpline => I::CubicSpline,
                }),
                output,
            });
            channels.push(Channel {
                sampler: Index::new(c as u32),
                target: Target {
                    extensions: None,
                    extras: Default::default(),
                    node: Index::new(channel.node as u32),
                    path: Checked::Valid(match channel.property {
                        Property::Translation => P::Translation,
                        Property::Rotation => P::Rotation,
                        Property::Scale => P::Scale,
                    }),
                },
                extensions: None,
                extras: Default::default(),
            });
        }
        self.root.push(json::Animation {
            extensions: None,
            extras: Default::default(),
            channels,
            name: Some(clip.name.clone()),
            samplers,
        });
    }

    /// A material with an embedded PNG or JPEG texture as its base colour.
    fn texture(&mut self, texture: &TextureSpec) -> Option<Index<json::Material>> {
        let TextureSpec::Embedded { bytes, .. } = texture else {
            return None;
        };
        let mime = if bytes.starts_with(b"\x89PNG") {
            "image/png"
        } else if bytes.starts_with(b"\xFF\xD8") {
            "image/jpeg"
        } else {
            return None;
        };
        let view = self.view(bytes, None);
        let image = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType(mime.into())),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        let texture = self.root.push(json::Texture {
            name: None,
            sampler: None,
            source: image,
            extensions: None,
            extras: Default::default(),
        });
        let mut material = json::Material::default();
        material.pbr_metallic_roughness.base_color_texture = Some(json::texture::Info {
            index: texture,
            tex_coord: 0,
            extensions: None,
            extras: Default::default(),
        });
        Some(self.root.push(material))
    }

    /// The `.glb` bytes.
    fn finish(mut self) -> std::result::Result<Vec<u8>, String> {
        self.root.asset.generator = Some(format!("fur {}", env!("CARGO_PKG_VERSION")));
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        let text = json::serialize::to_vec(&self.root).map_err(|e| e.to_string())?;
        if text.len() + self.bin.len() > u32::MAX as usize - 64 {
            return Err("the body is larger than a .glb can hold (4 GiB)".into());
        }
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: 0,
            },
            json: text.into(),
            bin: Some(self.bin.into()),
        };
        glb.to_vec().map_err(|e| e.to_string())
    }
}
