//! Consistency checks of a [`Rig`]: what the skinning pass and the clip sampler rely on,
//! checked once where a rig is made or read, so they never index out of range.

use super::{Interpolation, Property, Rig};

/// How far a vertex's weights may sum from 1.
const WEIGHT_SUM_TOLERANCE: f32 = 1e-3;

impl Rig {
    /// Checks that the rig fits a mesh of `vertex_count` vertices and holds together:
    /// per-vertex arrays of that length, joint indices within `joints`, weights finite,
    /// non-negative and summing to 1 (within 1e-3), bind positions and normals finite,
    /// nodes stored parents first with finite rest transforms, joints on existing nodes
    /// with finite inverse bind matrices, and every clip's channels on existing nodes
    /// with at least one key, finite and strictly increasing times and finite values,
    /// one per key (three for [`Interpolation::CubicSpline`]). The scale must be finite
    /// and positive. The error says what is wrong and where.
    pub fn validate(&self, vertex_count: usize) -> std::result::Result<(), String> {
        self.check_nodes()?;
        self.check_joints()?;
        self.check_vertices(vertex_count)?;
        self.check_clips()?;
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(format!(
                "the rig's scale is {}; it must be finite and positive",
                self.scale
            ));
        }
        Ok(())
    }

    fn check_nodes(&self) -> std::result::Result<(), String> {
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(parent) = node.parent {
                if parent >= i {
                    return Err(format!(
                        "node {i} (`{}`) has parent {parent}: nodes must come after their parent",
                        node.name
                    ));
                }
            }
            let rest = &node.rest;
            if !(rest.translation.is_finite()
                && rest.rotation.is_finite()
                && rest.scale.is_finite())
            {
                return Err(format!(
                    "node {i} (`{}`) has a rest transform that is not finite: {:?}",
                    node.name, rest
                ));
            }
        }
        Ok(())
    }

    fn check_joints(&self) -> std::result::Result<(), String> {
        if self.joints.len() > usize::from(u16::MAX) + 1 {
            return Err(format!(
                "the rig has {} joints; at most {} can be indexed",
                self.joints.len(),
                usize::from(u16::MAX) + 1
            ));
        }
        for (j, joint) in self.joints.iter().enumerate() {
            if joint.node >= self.nodes.len() {
                return Err(format!(
                    "joint {j} is bound to node {}, but the rig has {} nodes",
                    joint.node,
                    self.nodes.len()
                ));
            }
            if !joint.inverse_bind.is_finite() {
                return Err(format!(
                    "joint {j} (node `{}`) has an inverse bind matrix that is not finite",
                    self.nodes[joint.node].name
                ));
            }
        }
        Ok(())
    }

    fn check_vertices(&self, vertex_count: usize) -> std::result::Result<(), String> {
        for (what, len) in [
            ("influence sets", self.influences.len()),
            ("weight sets", self.weights.len()),
            ("bind positions", self.bind_positions.len()),
            ("bind normals", self.bind_normals.len()),
        ] {
            if len != vertex_count {
                return Err(format!(
                    "the rig has {len} {what} for a mesh of {vertex_count} vertices"
                ));
            }
        }
        for (v, (influence, weight)) in self.influences.iter().zip(&self.weights).enumerate() {
            for (slot, &joint) in influence.iter().enumerate() {
                if usize::from(joint) >= self.joints.len() {
                    return Err(format!(
                        "vertex {v}: influence {slot} is joint {joint}, but the rig has {} joints",
                        self.joints.len()
                    ));
                }
            }
            if let Some(w) = weight.iter().find(|w| !w.is_finite() || **w < 0.0) {
                return Err(format!(
                    "vertex {v} has the weight {w} (weights {weight:?}): weights must be finite \
                     and not negative"
                ));
            }
            let sum: f32 = weight.iter().sum();
            if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
                return Err(format!(
                    "vertex {v}'s weights {weight:?} sum to {sum}, not 1"
                ));
            }
        }
        if let Some(v) = self.bind_positions.iter().position(|p| !p.is_finite()) {
            return Err(format!(
                "vertex {v}'s bind position {} is not finite",
                self.bind_positions[v]
            ));
        }
        if let Some(v) = self.bind_normals.iter().position(|n| !n.is_finite()) {
            return Err(format!(
                "vertex {v}'s bind normal {} is not finite",
                self.bind_normals[v]
            ));
        }
        Ok(())
    }

    fn check_clips(&self) -> std::result::Result<(), String> {
        for clip in &self.clips {
            for (c, channel) in clip.channels.iter().enumerate() {
                let Some(node) = self.nodes.get(channel.node) else {
                    return Err(format!(
                        "clip `{}` channel {c} drives node {}, but the rig has {} nodes",
                        clip.name,
                        channel.node,
                        self.nodes.len()
                    ));
                };
                let property = match channel.property {
                    Property::Translation => "translation",
                    Property::Rotation => "rotation",
                    Property::Scale => "scale",
                };
                let place = format!(
                    "clip `{}` channel {c} ({} of node `{}`)",
                    clip.name, property, node.name
                );
                check_times(&channel.times).map_err(|e| format!("{place}: {e}"))?;
                let per_key = match channel.interpolation {
                    Interpolation::CubicSpline => 3,
                    Interpolation::Step | Interpolation::Linear => 1,
                };
                let expected = channel.times.len().saturating_mul(per_key);
                if channel.values.len() != expected {
                    return Err(format!(
                        "{place}: {} keys need {expected} values ({per_key} per key), it has {}",
                        channel.times.len(),
                        channel.values.len()
                    ));
                }
                if let Some(k) = channel.values.iter().position(|v| !v.is_finite()) {
                    return Err(format!(
                        "{place}: value {k} ({}) is not finite",
                        channel.values[k]
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Key times: at least one, finite, strictly increasing; the error says which key.
pub(crate) fn check_times(times: &[f32]) -> std::result::Result<(), String> {
    if times.is_empty() {
        return Err("it has no keys".into());
    }
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!("key {k}'s time {} is not finite", times[k]));
    }
    if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
        return Err(format!(
            "key times must increase, but key {} at {} s is not after key {k} at {} s",
            k + 1,
            times[k + 1],
            times[k]
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3, Vec4};

    use super::super::{Channel, Clip, Joint, Node, Transform};
    use super::*;

    fn rig() -> Rig {
        Rig {
            nodes: vec![
                Node {
                    name: "root".into(),
                    parent: None,
                    rest: Transform::default(),
                },
                Node {
                    name: "arm".into(),
                    parent: Some(0),
                    rest: Transform::default(),
                },
            ],
            joints: vec![
                Joint {
                    node: 0,
                    inverse_bind: Mat4::IDENTITY,
                },
                Joint {
                    node: 1,
                    inverse_bind: Mat4::IDENTITY,
                },
            ],
            influences: vec![[0, 1, 0, 0]; 3],
            weights: vec![[0.25, 0.75, 0.0, 0.0]; 3],
            bind_positions: vec![Vec3::ZERO; 3],
            bind_normals: vec![Vec3::Z; 3],
            clips: vec![Clip {
                name: "wave".into(),
                channels: vec![Channel {
                    node: 1,
                    property: Property::Rotation,
                    interpolation: Interpolation::CubicSpline,
                    times: vec![0.0, 1.0],
                    values: vec![Vec4::W; 6],
                }],
            }],
            scale: 1.0,
        }
    }

    #[test]
    fn a_consistent_rig_passes() {
        rig().validate(3).unwrap();
    }

    #[test]
    fn each_inconsistency_is_named() {
        type Break = fn(&mut Rig);
        let cases: [(Break, &str); 9] = [
            (|r| r.nodes[0].parent = Some(1), "after their parent"),
            (|r| r.joints[1].node = 5, "joint 1 is bound to node 5"),
            (
                |r| r.influences[2][1] = 2,
                "vertex 2: influence 1 is joint 2",
            ),
            (
                |r| r.weights[1] = [f32::NAN, 1.0, 0.0, 0.0],
                "vertex 1 has the weight NaN",
            ),
            (|r| r.weights[0] = [0.5, 0.4, 0.0, 0.0], "sum to 0.9"),
            (
                |r| r.bind_normals.pop().map(drop).unwrap_or(()),
                "2 bind normals",
            ),
            (
                |r| r.clips[0].channels[0].times = vec![1.0, 1.0],
                "key 1 at 1 s",
            ),
            (
                |r| r.clips[0].channels[0].values.pop().map(drop).unwrap_or(()),
                "need 6 values",
            ),
            (|r| r.clips[0].channels[0].node = 9, "drives node 9"),
        ];
        for (break_it, needle) in cases {
            let mut r = rig();
            break_it(&mut r);
            let message = r.validate(3).unwrap_err();
            assert!(message.contains(needle), "`{needle}` not in: {message}");
        }
        assert!(rig().validate(4).unwrap_err().contains("3 influence sets"));
    }
}
