//! One mesh node's triangle primitives, read and merged into the body.

use std::collections::BTreeSet;

use glam::{Mat3, Vec2, Vec3};
use gltf::json::accessor::Type;
use gltf::json::mesh::{Mode, Semantic};
use gltf::json::validation::Checked;
use gltf::json::{self, Index};

use super::accessor::Allowed;
use super::read::Body;
use super::skin::{read_skin_weights, Joints, SkinUse};
use super::source::Source;
use super::tree::Tree;
use super::MAX_VERTICES;

/// The most triangle corners read (strips and fans triple their indices).
const MAX_CORNERS: usize = 6 * MAX_VERTICES;

pub(super) fn attribute(primitive: &json::mesh::Primitive, semantic: Semantic) -> Option<usize> {
    primitive
        .attributes
        .get(&Checked::Valid(semantic))
        .map(|i: &Index<json::Accessor>| i.value())
}

/// Whether a primitive is made of triangles (a list, strip or fan).
pub(super) fn is_triangles(primitive: &json::mesh::Primitive) -> bool {
    matches!(
        primitive.mode,
        Checked::Valid(Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)
    )
}

pub(super) fn has_skin_attributes(primitive: &json::mesh::Primitive) -> bool {
    attribute(primitive, Semantic::Joints(0)).is_some()
        && attribute(primitive, Semantic::Weights(0)).is_some()
}

/// Adds the triangle primitives of mesh node `f`. `rig` is the joints being made and
/// the nodes' rig indices, for a rigged body.
pub(super) fn add_node(
    source: &Source,
    tree: &Tree,
    f: usize,
    mut rig: Option<(&mut Joints, &[Option<usize>])>,
    body: &mut Body,
    morph_warned: &mut BTreeSet<usize>,
    warnings: &mut Vec<String>,
) -> Result<(), String> {
    let root = &source.root;
    let node = &root.nodes[f];
    let Some(m) = node.mesh.map(|m| m.value()) else {
        return Ok(());
    };
    let mesh = root.meshes.get(m).ok_or_else(|| {
        format!(
            "node {f} refers to mesh {m}, which does not exist (the file has {} meshes)",
            root.meshes.len()
        )
    })?;
    let skin = match node.skin.map(|s| s.value()) {
        Some(s) => Some((
            s,
            root.skins.get(s).ok_or_else(|| {
                format!(
                    "node {f} refers to skin {s}, which does not exist (the file has {} skins)",
                    root.skins.len()
                )
            })?,
        )),
        None => None,
    };
    let morphs = mesh.weights.is_some()
        || node.weights.is_some()
        || mesh
            .primitives
            .iter()
            .any(|p| p.targets.as_ref().is_some_and(|t| !t.is_empty()));
    if morphs && morph_warned.insert(m) {
        warnings.push(format!(
            "mesh {m} has morph targets (blend shapes); they are ignored and it keeps its base shape"
        ));
    }
    let global = tree.global[f];
    let normal_matrix = Mat3::from_mat4(global).inverse().transpose();
    let mirrored = global.determinant() < 0.0;
    for (p, primitive) in mesh.primitives.iter().enumerate() {
        let place = format!("mesh {m} primitive {p}");
        let mode = match primitive.mode {
            Checked::Valid(mode @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => {
                mode
            }
            Checked::Valid(other) => {
                warnings.push(format!(
                    "{place} is made of {}; only triangles are read, it is skipped",
                    mode_name(other)
                ));
                continue;
            }
            Checked::Invalid => {
                warnings.push(format!("{place} has an unknown mode; it is skipped"));
                continue;
            }
        };
        if body.material.is_none() {
            body.material = Some(primitive.material.map(|i| i.value()));
        }
        let position = attribute(primitive, Semantic::Positions)
            .ok_or_else(|| format!("{place} has no POSITION attribute"))?;
        let read_vec3 = |index: usize, what: &str| -> Result<Vec<Vec3>, String> {
            let floats = source.floats(
                index,
                &format!("{what} of {place}"),
                Type::Vec3,
                Allowed::Float,
            )?;
            Ok(floats.chunks_exact(3).map(Vec3::from_slice).collect())
        };
        // Bounds-checked against its buffer first: at most the buffer's size is read.
        let positions = read_vec3(position, "POSITION")?;
        let count = positions.len();
        if count > MAX_VERTICES.saturating_sub(body.positions.len()) {
            return Err(format!(
                "the scene's meshes add up to more than {MAX_VERTICES} vertices (at {place} of \
                 node {f}), more than fur can grow hair on"
            ));
        }
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(format!(
                "vertex {v} of {place} has a position that is not finite ({})",
                positions[v]
            ));
        }
        let same_count = |index: usize, what: &str| {
            source.expect_count(index, &format!("{what} of {place}"), count)
        };
        let normals = match attribute(primitive, Semantic::Normals) {
            Some(index) => {
                same_count(index, "NORMAL")?;
                Some(read_vec3(index, "NORMAL")?)
            }
            None => None,
        };
        let uvs = match attribute(primitive, Semantic::TexCoords(0)) {
            Some(index) => {
                same_count(index, "TEXCOORD_0")?;
                let floats = source.floats(
                    index,
                    &format!("TEXCOORD_0 of {place}"),
                    Type::Vec2,
                    Allowed::FloatOrNormalized { signed: false },
                )?;
                let uvs: Vec<Vec2> = floats.chunks_exact(2).map(Vec2::from_slice).collect();
                if let Some(k) = uvs.iter().position(|uv| !uv.is_finite()) {
                    return Err(format!(
                        "TEXCOORD_0 {k} of {place} is not finite ({})",
                        uvs[k]
                    ));
                }
                Some(uvs)
            }
            None => None,
        };
        let corners: Vec<u32> = match primitive.indices.map(|i| i.value()) {
            Some(index) => {
                let declared = source.accessor_count(index, &format!("indices of {place}"))?;
                if declared as usize > MAX_CORNERS.saturating_sub(body.indices.len()) / 3 {
                    return Err(format!(
                        "the scene's meshes add up to more than {MAX_CORNERS} triangle corners \
                         (at {place} of node {f})"
                    ));
                }
                let indices = source.uints(
                    index,
                    &format!("indices of {place}"),
                    Type::Scalar,
                    Allowed::Unsigned { wide: true },
                )?;
                if let Some(k) = indices.iter().position(|&i| i as usize >= count) {
                    return Err(format!(
                        "index {k} of {place} is {}, past its {count} vertices",
                        indices[k]
                    ));
                }
                indices
            }
            None => (0..count as u32).collect(),
        };
        let skinned = match skin {
            Some(_) if has_skin_attributes(primitive) => true,
            Some((s, _)) => {
                warnings.push(format!(
                    "{place} is on node {f} with skin {s} but has no JOINTS_0/WEIGHTS_0; it \
                     moves with node {f} unskinned"
                ));
                false
            }
            None => false,
        };
        let mut triangles = triangulate(mode, &corners, &place, warnings);
        if mirrored && !skinned {
            // A mirroring transform turns counter-clockwise faces clockwise.
            triangles.iter_mut().for_each(|t| t.swap(1, 2));
        }
        let base = body.positions.len() as u32;
        body.indices
            .extend(triangles.iter().flat_map(|t| t.map(|i| base + i)));
        match (&mut rig, skin) {
            (Some((joints, rig_index)), Some((s, skin))) if skinned => {
                if primitive
                    .attributes
                    .contains_key(&Checked::Valid(Semantic::Joints(1)))
                {
                    warnings.push(format!(
                        "{place} has a second set of joint influences (JOINTS_1/WEIGHTS_1); \
                         it is ignored, only JOINTS_0/WEIGHTS_0 are used"
                    ));
                }
                let first = joints.add_skin(source, rig_index, s, skin)?;
                let used = SkinUse {
                    index: s,
                    joints: skin.joints.len(),
                    first,
                };
                read_skin_weights(source, primitive, &place, used, count, body)?;
                body.positions.extend(&positions);
                if let Some(normals) = &normals {
                    body.normals.extend(normals);
                }
            }
            _ => {
                body.positions
                    .extend(positions.iter().map(|&q| global.transform_point3(q)));
                if let Some(normals) = &normals {
                    body.normals
                        .extend(normals.iter().map(|&n| normal_matrix * n));
                }
                if let Some((joints, rig_index)) = &mut rig {
                    let joint = joints.add_node_joint(tree, rig_index, f)?;
                    body.influences
                        .extend(std::iter::repeat_n([joint, 0, 0, 0], count));
                    body.weights
                        .extend(std::iter::repeat_n([1.0, 0.0, 0.0, 0.0], count));
                }
            }
        }
        body.all_normals &= normals.is_some();
        match uvs {
            Some(uvs) => body.uvs.extend(uvs),
            None => {
                body.all_uvs = false;
                body.uvs.extend(std::iter::repeat_n(Vec2::ZERO, count));
            }
        }
        if normals.is_none() {
            body.normals.extend(std::iter::repeat_n(Vec3::ZERO, count));
        }
    }
    Ok(())
}

/// A primitive's triangles (as corner indices) by its mode; a list whose length is no
/// multiple of 3 loses its last corners, with a warning.
fn triangulate(mode: Mode, c: &[u32], place: &str, warnings: &mut Vec<String>) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..c.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [c[i], c[i + 1], c[i + 2]]
                } else {
                    [c[i + 1], c[i], c[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..c.len().saturating_sub(1))
            .map(|i| [c[i], c[i + 1], c[0]])
            .collect(),
        _ => {
            if c.len() % 3 != 0 {
                warnings.push(format!(
                    "{place} has {} triangle corners, not a multiple of 3; the last {} are \
                     ignored",
                    c.len(),
                    c.len() % 3
                ));
            }
            c.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
    }
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "points (POINTS)",
        Mode::Lines => "lines (LINES)",
        Mode::LineLoop => "a line loop (LINE_LOOP)",
        Mode::LineStrip => "a line strip (LINE_STRIP)",
        Mode::Triangles => "triangles",
        Mode::TriangleStrip => "a triangle strip",
        Mode::TriangleFan => "a triangle fan",
    }
}
