//! The node hierarchy of the scene read: which nodes it holds, their parents, a
//! parents-first order, and their rest transforms.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::{Mat4, Quat, Vec3};
use gltf::json;

use super::super::Transform;

/// The scene's nodes, by file index.
pub(super) struct Tree {
    /// Scene nodes, parents first; in file order where the file has parents first.
    pub order: Vec<usize>,
    /// Per file node: its parent in the scene.
    pub parent: Vec<Option<usize>>,
    /// Per file node: whether the scene holds it.
    pub in_scene: Vec<bool>,
    /// Per file node: whether it has children in the scene.
    pub has_children: Vec<bool>,
    /// Per file node: its local rest transform (identity outside the scene).
    pub local: Vec<Transform>,
    /// Per file node: its global rest transform (identity outside the scene).
    pub global: Vec<Mat4>,
}

impl Tree {
    /// The default scene (or scene 0, or every root node when there are no scenes),
    /// checked: children exist, nobody has two parents, nothing is reached twice, and
    /// transforms are finite.
    pub fn build(root: &json::Root) -> Result<Self, String> {
        let n = root.nodes.len();
        let mut file_parent: Vec<Option<usize>> = vec![None; n];
        for (p, node) in root.nodes.iter().enumerate() {
            for child in node.children.iter().flatten() {
                let c = child.value();
                if c >= n {
                    return Err(format!(
                        "node {p} lists child {c}, which does not exist (the file has {n} nodes)"
                    ));
                }
                if let Some(other) = file_parent[c] {
                    return Err(format!(
                        "node {c} is a child of both node {other} and node {p}; a node has at \
                         most one parent"
                    ));
                }
                file_parent[c] = Some(p);
            }
        }
        let (roots, scene_name) = match (root.scene, root.scenes.first()) {
            (Some(s), _) => {
                let scene = root.scenes.get(s.value()).ok_or_else(|| {
                    format!(
                        "the default scene {} does not exist (the file has {} scenes)",
                        s.value(),
                        root.scenes.len()
                    )
                })?;
                (scene_nodes(scene), format!("scene {}", s.value()))
            }
            (None, Some(scene)) => (scene_nodes(scene), "scene 0".to_string()),
            (None, None) => (
                (0..n).filter(|&i| file_parent[i].is_none()).collect(),
                "the file's root nodes".to_string(),
            ),
        };
        let mut parent = vec![None; n];
        let mut in_scene = vec![false; n];
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut stack: Vec<(usize, Option<usize>)> =
            roots.iter().rev().map(|&r| (r, None)).collect();
        while let Some((node, from)) = stack.pop() {
            let seen = in_scene.get_mut(node).ok_or_else(|| {
                format!(
                    "{scene_name} lists node {node}, which does not exist (the file has {n} nodes)"
                )
            })?;
            if *seen {
                return Err(format!(
                    "node {node} is reached twice from {scene_name} (listed twice, or both as a \
                     root and as a child)"
                ));
            }
            *seen = true;
            parent[node] = from;
            if let Some(p) = from {
                children[p].push(node);
            }
            for child in root.nodes[node].children.iter().flatten().rev() {
                stack.push((child.value(), Some(node)));
            }
        }
        // Parents first, smallest file index first among the nodes whose parent is placed:
        // a file already in parents-first order keeps its order.
        let mut order = Vec::new();
        let mut ready: BinaryHeap<Reverse<usize>> = (0..n)
            .filter(|&i| in_scene[i] && parent[i].is_none())
            .map(Reverse)
            .collect();
        while let Some(Reverse(node)) = ready.pop() {
            order.push(node);
            ready.extend(children[node].iter().map(|&c| Reverse(c)));
        }
        let mut local = vec![Transform::default(); n];
        let mut global = vec![Mat4::IDENTITY; n];
        for &i in &order {
            local[i] = local_transform(&root.nodes[i]).map_err(|e| format!("node {i}: {e}"))?;
            let above = parent[i].map_or(Mat4::IDENTITY, |p| global[p]);
            global[i] = above * local[i].matrix();
        }
        let has_children = children.iter().map(|c| !c.is_empty()).collect();
        Ok(Self {
            order,
            parent,
            in_scene,
            has_children,
            local,
            global,
        })
    }
}

fn scene_nodes(scene: &json::Scene) -> Vec<usize> {
    scene.nodes.iter().map(|n| n.value()).collect()
}

/// A node's transform: its matrix decomposed, or its TRS; finite, with a rotation
/// normalised unless it is unit length already (then kept bit for bit).
fn local_transform(node: &json::Node) -> Result<Transform, String> {
    let transform = match node.matrix {
        Some(m) => {
            let matrix = Mat4::from_cols_array(&m);
            if !matrix.is_finite() {
                return Err(format!("its matrix {m:?} is not finite"));
            }
            let (scale, rotation, translation) = matrix.to_scale_rotation_translation();
            Transform {
                translation,
                rotation,
                scale,
            }
        }
        None => Transform {
            translation: node.translation.map_or(Vec3::ZERO, Vec3::from),
            rotation: node
                .rotation
                .map_or(Quat::IDENTITY, |q| Quat::from_array(q.0)),
            scale: node.scale.map_or(Vec3::ONE, Vec3::from),
        },
    };
    if !(transform.translation.is_finite()
        && transform.rotation.is_finite()
        && transform.scale.is_finite())
    {
        return Err(format!("its transform is not finite: {transform:?}"));
    }
    let length = transform.rotation.length_squared();
    if length == 0.0 {
        return Err("its rotation is the zero quaternion".into());
    }
    let rotation = if (length - 1.0).abs() <= 2e-5 {
        transform.rotation
    } else {
        transform.rotation.normalize()
    };
    Ok(Transform {
        rotation,
        ..transform
    })
}
