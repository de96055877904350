//! From the document to a body: the scene's triangle primitives merged into one mesh,
//! skinned at rest, with the rig when the body is skinned or animated.

use std::collections::BTreeSet;

use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::json;
use gltf::json::validation::Checked;

use super::super::{Mesh, Node, Rig, TextureSpec};
use super::animation;
use super::primitive::{add_node, has_skin_attributes, is_triangles};
use super::skin::{blend, Joints};
use super::source::Source;
use super::tree::Tree;

/// The merged primitives, per vertex in bind space (for a body without a rig, bind
/// space is the scene's world space).
#[derive(Default)]
pub(super) struct Body {
    pub(super) positions: Vec<Vec3>,
    pub(super) normals: Vec<Vec3>,
    pub(super) uvs: Vec<Vec2>,
    pub(super) indices: Vec<u32>,
    pub(super) influences: Vec<[u16; 4]>,
    pub(super) weights: Vec<[f32; 4]>,
    pub(super) all_normals: bool,
    pub(super) all_uvs: bool,
    /// The first triangle primitive's material, once one is read.
    pub(super) material: Option<Option<usize>>,
}

pub(super) fn read_body(
    source: &Source,
    warnings: &mut Vec<String>,
) -> Result<(Mesh, Option<Rig>), String> {
    let root = &source.root;
    let tree = Tree::build(root)?;
    let mesh_nodes: Vec<usize> = tree
        .order
        .iter()
        .copied()
        .filter(|&i| root.nodes[i].mesh.is_some())
        .collect();
    let rigged = is_rigged(root, &tree, &mesh_nodes);
    if !rigged && !root.animations.is_empty() {
        warnings.push(format!(
            "{}: its animations move no mesh; they are ignored",
            source.model.display()
        ));
    }
    let rig_index = rig_indices(root, &tree, rigged);
    let mut body = Body {
        all_normals: true,
        all_uvs: true,
        ..Body::default()
    };
    let mut joints = Joints::default();
    let mut morph_warned = BTreeSet::new();
    for &f in &mesh_nodes {
        add_node(
            source,
            &tree,
            f,
            rigged.then_some((&mut joints, rig_index.as_slice())),
            &mut body,
            &mut morph_warned,
            warnings,
        )?;
    }
    if body.material.is_none() {
        return Err(
            "no triangles: the scene has no triangle primitives, and fur grows from \
                    triangles"
                .into(),
        );
    }
    if body.indices.is_empty() {
        return Err(
            "no triangles: the scene's triangle primitives have no complete triangle".into(),
        );
    }
    let skinning: Vec<Mat4> = joints
        .joints
        .iter()
        .zip(&joints.file_nodes)
        .map(|(j, &f)| tree.global[f] * j.inverse_bind)
        .collect();
    let rest: Vec<Vec3> = if rigged {
        (0..body.positions.len())
            .map(|v| {
                blend(&skinning, body.influences[v], body.weights[v])
                    .transform_point3(body.positions[v])
            })
            .collect()
    } else {
        body.positions.clone()
    };
    if let Some(v) = rest.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "vertex {v}'s position in the scene is not finite ({}): a node transform or \
             skin overflows",
            rest[v]
        ));
    }
    let mut mesh = Mesh {
        positions: rest,
        normals: Vec::new(),
        indices: std::mem::take(&mut body.indices),
        uvs: Vec::new(),
        texture: None,
    };
    if body.all_uvs {
        mesh.uvs = mesh.indices.iter().map(|&i| body.uvs[i as usize]).collect();
    }
    drop_degenerate_triangles(&mut mesh);
    if mesh.indices.is_empty() {
        return Err("every triangle is degenerate (zero area)".into());
    }
    let file_normals: Option<Vec<Vec3>> = if body.all_normals {
        body.normals.iter().map(|&n| unit(n)).collect()
    } else {
        None
    };
    let bind_normals = match file_normals {
        Some(normals) => {
            mesh.normals = if rigged {
                skin_normals(&mesh, &skinning, &body, &normals)
            } else {
                normals.clone()
            };
            normals
        }
        None => {
            mesh.normals = mesh.face_weighted_normals();
            let bind = Mesh {
                positions: body.positions.clone(),
                ..mesh.clone()
            };
            bind.face_weighted_normals()
        }
    };
    if let Some(Some(material)) = body.material {
        mesh.texture = texture(source, material, warnings);
    }
    if !rigged {
        return Ok((mesh, None));
    }
    let nodes = tree
        .order
        .iter()
        .filter(|&&f| rig_index[f].is_some())
        .map(|&f| Node {
            name: root.nodes[f]
                .name
                .clone()
                .unwrap_or_else(|| format!("node{f}")),
            parent: tree.parent[f].and_then(|p| rig_index[p]),
            rest: tree.local[f],
        })
        .collect();
    let clips = animation::read_clips(source, &tree, &rig_index, warnings)?;
    let rig = Rig {
        nodes,
        joints: joints.joints,
        influences: body.influences,
        weights: body.weights,
        bind_positions: body.positions,
        bind_normals,
        clips,
        scale: 1.0,
    };
    rig.validate(mesh.vertex_count())
        .map_err(|e| format!("the rig read is inconsistent: {e}"))?;
    Ok((mesh, Some(rig)))
}

/// Whether the body needs a rig: a mesh node of the scene has a skin, or an animation
/// channel moves a mesh node or one of its ancestors.
fn is_rigged(root: &json::Root, tree: &Tree, mesh_nodes: &[usize]) -> bool {
    if mesh_nodes.iter().any(|&f| root.nodes[f].skin.is_some()) {
        return true;
    }
    let mut holds_mesh: Vec<bool> = root.nodes.iter().map(|n| n.mesh.is_some()).collect();
    for &f in tree.order.iter().rev() {
        if let Some(p) = tree.parent[f] {
            holds_mesh[p] |= holds_mesh[f];
        }
    }
    root.animations.iter().flat_map(|a| &a.channels).any(|c| {
        let node = c.target.node.value();
        let moves = !matches!(
            c.target.path,
            Checked::Valid(json::animation::Property::MorphTargetWeights) | Checked::Invalid
        );
        moves && tree.in_scene.get(node) == Some(&true) && holds_mesh[node]
    })
}

/// Per file node, its index in `Rig::nodes`: the scene's nodes in order, less those
/// that only hold a skinned mesh (leaves that are no joint: their transform does
/// nothing).
fn rig_indices(root: &json::Root, tree: &Tree, rigged: bool) -> Vec<Option<usize>> {
    let mut is_joint = vec![false; root.nodes.len()];
    for skin in tree
        .order
        .iter()
        .filter_map(|&f| root.skins.get(root.nodes[f].skin?.value()))
    {
        for j in &skin.joints {
            if let Some(flag) = is_joint.get_mut(j.value()) {
                *flag = true;
            }
        }
    }
    let only_skinned_mesh = |f: usize| {
        let node = &root.nodes[f];
        let Some(mesh) = node.mesh.and_then(|m| root.meshes.get(m.value())) else {
            return false;
        };
        node.skin.is_some()
            && !tree.has_children[f]
            && !is_joint[f]
            && mesh
                .primitives
                .iter()
                .filter(|p| is_triangles(p))
                .all(has_skin_attributes)
    };
    let mut index = vec![None; root.nodes.len()];
    let mut next = 0;
    for &f in &tree.order {
        if !(rigged && only_skinned_mesh(f)) {
            index[f] = Some(next);
            next += 1;
        }
    }
    index
}

/// Rest normals of a rigged body: each bind normal through the inverse transpose of its
/// blended matrix; a vertex where that fails gets its face-weighted normal.
fn skin_normals(mesh: &Mesh, skinning: &[Mat4], body: &Body, bind: &[Vec3]) -> Vec<Vec3> {
    let mut faces: Option<Vec<Vec3>> = None;
    (0..bind.len())
        .map(|v| {
            let m = Mat3::from_mat4(blend(skinning, body.influences[v], body.weights[v]));
            (m.inverse().transpose() * bind[v])
                .try_normalize()
                .unwrap_or_else(|| faces.get_or_insert_with(|| mesh.face_weighted_normals())[v])
        })
        .collect()
}

/// A unit normal: kept bit for bit when already of unit length (within 1e-5), else
/// normalised; `None` when it cannot be (zero, not finite).
fn unit(n: Vec3) -> Option<Vec3> {
    if !n.is_finite() {
        return None;
    }
    if (n.length_squared() - 1.0).abs() <= 2e-5 {
        Some(n)
    } else {
        n.try_normalize()
    }
}

/// Removes triangles with repeated corners or zero area (and their corner UVs); the
/// vertices stay.
fn drop_degenerate_triangles(mesh: &mut Mesh) {
    let has_uvs = mesh.uvs.len() == mesh.indices.len();
    let mut indices = Vec::with_capacity(mesh.indices.len());
    let mut uvs = Vec::with_capacity(mesh.uvs.len());
    for (k, t) in mesh.indices.chunks_exact(3).enumerate() {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
        let degenerate = t[0] == t[1]
            || t[1] == t[2]
            || t[0] == t[2]
            || (b - a).cross(c - a).length_squared().partial_cmp(&0.0)
                != Some(std::cmp::Ordering::Greater);
        if !degenerate {
            indices.extend_from_slice(t);
            if has_uvs {
                uvs.extend_from_slice(&mesh.uvs[3 * k..3 * k + 3]);
            }
        }
    }
    mesh.indices = indices;
    mesh.uvs = uvs;
}

/// The base colour texture of material `index`, if it has one that can be used.
fn texture(source: &Source, index: usize, warnings: &mut Vec<String>) -> Option<TextureSpec> {
    let material = source.root.materials.get(index)?;
    let info = material
        .pbr_metallic_roughness
        .base_color_texture
        .as_ref()?;
    if info.tex_coord != 0 {
        warnings.push(format!(
            "model {}: material {index}'s base colour texture uses TEXCOORD_{}, which fur does \
             not read; it loads without a texture",
            source.model.display(),
            info.tex_coord
        ));
        return None;
    }
    source.texture(info.index.value(), warnings)
}
