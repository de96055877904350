//! The glTF document being written: JSON objects and the binary chunk they point into.

use glam::Vec4;
use gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use gltf::json::buffer::Target;
use gltf::json::validation::{Checked, USize64};
use gltf::json::{self, Index};

use super::super::{Clip, Interpolation, Property, Rig, TextureSpec};

/// The document being written and its binary chunk.
#[derive(Default)]
pub(super) struct Doc {
    pub root: json::Root,
    bin: Vec<u8>,
}

impl Doc {
    /// A buffer view over `data` appended to the binary chunk (4-byte aligned).
    pub fn view(&mut self, data: &[u8], target: Option<Target>) -> Index<json::buffer::View> {
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

    pub fn accessor(
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
    pub fn floats(
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
    pub fn rig(&mut self, rig: &Rig, scene_nodes: &mut Vec<Index<json::Node>>) {
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
    pub fn skin(&mut self, rig: &Rig) -> Index<json::Skin> {
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
    pub fn clip(&mut self, clip: &Clip) {
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
    pub fn texture(&mut self, texture: &TextureSpec) -> Option<Index<json::Material>> {
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
    pub fn finish(mut self) -> std::result::Result<Vec<u8>, String> {
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
