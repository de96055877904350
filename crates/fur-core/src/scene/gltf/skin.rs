//! Skins: the rig's joints as they are made, and per-vertex joints and weights.

use std::collections::HashMap;

use glam::Mat4;
use gltf::json;
use gltf::json::accessor::Type;
use gltf::json::mesh::Semantic;

use super::super::Joint;
use super::accessor::Allowed;
use super::primitive::attribute;
use super::read::Body;
use super::source::Source;
use super::tree::Tree;

/// The rig's joints as they are made: per joint its file node, and where each skin's
/// joints start.
#[derive(Default)]
pub(super) struct Joints {
    pub(super) joints: Vec<Joint>,
    pub(super) file_nodes: Vec<usize>,
    pub(super) skin_base: HashMap<usize, usize>,
    pub(super) node_joint: HashMap<usize, u16>,
}

impl Joints {
    /// The rig index of skin `s`'s first joint, adding its joints on first use.
    pub(super) fn add_skin(
        &mut self,
        source: &Source,
        rig_index: &[Option<usize>],
        s: usize,
        skin: &json::Skin,
    ) -> Result<u16, String> {
        if let Some(&first) = self.skin_base.get(&s) {
            return Ok(first as u16);
        }
        let first = self.joints.len();
        if first + skin.joints.len() > usize::from(u16::MAX) + 1 {
            return Err(format!(
                "the skins add up to more than {} joints (at skin {s})",
                usize::from(u16::MAX) + 1
            ));
        }
        let matrices = match skin.inverse_bind_matrices.map(|i| i.value()) {
            Some(index) => {
                let m = source.matrices(
                    index,
                    &format!("inverseBindMatrices of skin {s}"),
                    skin.joints.len(),
                )?;
                if m.len() < 16 * skin.joints.len() {
                    return Err(format!(
                        "skin {s} has {} joints, but its inverseBindMatrices (accessor {index}) \
                         hold {} matrices",
                        skin.joints.len(),
                        m.len() / 16
                    ));
                }
                m
            }
            None => Vec::new(),
        };
        for (k, node) in skin.joints.iter().enumerate() {
            let f = node.value();
            let Some(Some(rig_node)) = rig_index.get(f) else {
                return Err(format!(
                    "skin {s}'s joint {k} is node {f}, which is not in the scene"
                ));
            };
            let inverse_bind = matrices
                .get(16 * k..16 * k + 16)
                .map_or(Mat4::IDENTITY, Mat4::from_cols_slice);
            if !inverse_bind.is_finite() {
                return Err(format!("skin {s}'s inverse bind matrix {k} is not finite"));
            }
            self.joints.push(Joint {
                node: *rig_node,
                inverse_bind,
            });
            self.file_nodes.push(f);
        }
        self.skin_base.insert(s, first);
        Ok(first as u16)
    }

    /// The joint that moves unskinned node `f`'s vertices, added on first use.
    pub(super) fn add_node_joint(
        &mut self,
        tree: &Tree,
        rig_index: &[Option<usize>],
        f: usize,
    ) -> Result<u16, String> {
        if let Some(&j) = self.node_joint.get(&f) {
            return Ok(j);
        }
        let j = u16::try_from(self.joints.len())
            .map_err(|_| format!("the body needs more than {} joints", u16::MAX))?;
        let inverse_bind = tree.global[f].inverse();
        let node = rig_index.get(f).copied().flatten();
        let (Some(node), true) = (node, inverse_bind.is_finite()) else {
            return Err(format!(
                "node {f}'s transform cannot be inverted (a zero scale), so its mesh cannot be \
                 bound to it"
            ));
        };
        self.joints.push(Joint { node, inverse_bind });
        self.file_nodes.push(f);
        self.node_joint.insert(f, j);
        Ok(j)
    }
}

/// A skin as a primitive uses it: its index, its joint count, and the rig index of its
/// first joint.
pub(super) struct SkinUse {
    pub index: usize,
    pub joints: usize,
    pub first: u16,
}

/// Reads a skinned primitive's JOINTS_0 and WEIGHTS_0 into the body (joint indices
/// offset by the skin's first, weights renormalised); it has `vertices` vertices.
pub(super) fn read_skin_weights(
    source: &Source,
    primitive: &json::mesh::Primitive,
    place: &str,
    skin: SkinUse,
    vertices: usize,
    body: &mut Body,
) -> Result<(), String> {
    let SkinUse {
        index: s,
        joints: joint_count,
        first,
    } = skin;
    let (Some(ji), Some(wi)) = (
        attribute(primitive, Semantic::Joints(0)),
        attribute(primitive, Semantic::Weights(0)),
    ) else {
        return Err(format!("{place} has no JOINTS_0/WEIGHTS_0"));
    };
    source.expect_count(ji, &format!("JOINTS_0 of {place}"), vertices)?;
    source.expect_count(wi, &format!("WEIGHTS_0 of {place}"), vertices)?;
    let joints = source.uints(
        ji,
        &format!("JOINTS_0 of {place}"),
        Type::Vec4,
        Allowed::Unsigned { wide: false },
    )?;
    let weights = source.floats(
        wi,
        &format!("WEIGHTS_0 of {place}"),
        Type::Vec4,
        Allowed::FloatOrNormalized { signed: false },
    )?;
    for (v, (j, w)) in joints
        .chunks_exact(4)
        .zip(weights.chunks_exact(4))
        .enumerate()
    {
        let w = [w[0], w[1], w[2], w[3]];
        if let Some(bad) = w.iter().find(|x| !x.is_finite() || **x < 0.0) {
            return Err(format!(
                "WEIGHTS_0 of {place}: vertex {v} has the weight {bad} (weights {w:?}); weights \
                 must be finite and not negative"
            ));
        }
        let sum: f32 = w.iter().sum();
        if sum <= 0.0 || !sum.is_finite() {
            return Err(format!(
                "WEIGHTS_0 of {place}: vertex {v}'s weights {w:?} sum to {sum}, so it is bound \
                 to no joint"
            ));
        }
        let w = if (sum - 1.0).abs() <= 1e-6 {
            w
        } else {
            w.map(|x| x / sum)
        };
        let mut influence = [0u16; 4];
        for (slot, &joint) in j.iter().enumerate() {
            if joint as usize >= joint_count {
                return Err(format!(
                    "JOINTS_0 of {place}: vertex {v} names joint {joint}, but skin {s} has \
                     {joint_count} joints"
                ));
            }
            influence[slot] = first + joint as u16;
        }
        body.influences.push(influence);
        body.weights.push(w);
    }
    Ok(())
}

/// The blended skinning matrix of one vertex.
pub(super) fn blend(skinning: &[Mat4], influence: [u16; 4], weight: [f32; 4]) -> Mat4 {
    influence
        .iter()
        .zip(weight)
        .filter(|(_, w)| *w != 0.0)
        .map(|(&j, w)| skinning.get(usize::from(j)).map_or(Mat4::ZERO, |m| *m * w))
        .fold(Mat4::ZERO, |sum, m| sum + m)
}
