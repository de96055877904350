//! Animations: each glTF animation becomes a [`Clip`] whose channels keep their
//! interpolation and values as the file has them.

use glam::Vec4;
use gltf::json::accessor::Type;
use gltf::json::animation::{Interpolation as FileInterpolation, Property as FileProperty};
use gltf::json::validation::Checked;

use super::super::rig_check::check_times;
use super::super::{Channel, Clip, Interpolation, Property};
use super::accessor::Allowed;
use super::source::Source;
use super::tree::Tree;
use super::MAX_VERTICES;

/// The most key values read over all channels.
const MAX_VALUES: usize = 4 * MAX_VERTICES;

/// The clips of the file, one per animation (named `animation{i}` when unnamed).
/// Channels on nodes outside the rig and morph weight channels are skipped with a
/// warning; key times must be finite and strictly increasing.
pub(super) fn read_clips(
    source: &Source,
    tree: &Tree,
    rig_index: &[Option<usize>],
    warnings: &mut Vec<String>,
) -> Result<Vec<Clip>, String> {
    let mut budget = MAX_VALUES;
    let mut clips = Vec::new();
    for (a, animation) in source.root.animations.iter().enumerate() {
        let name = animation
            .name
            .clone()
            .unwrap_or_else(|| format!("animation{a}"));
        let mut channels = Vec::new();
        for (c, channel) in animation.channels.iter().enumerate() {
            let place = format!("animation {a} (`{name}`) channel {c}");
            let property = match channel.target.path {
                Checked::Valid(FileProperty::Translation) => Property::Translation,
                Checked::Valid(FileProperty::Rotation) => Property::Rotation,
                Checked::Valid(FileProperty::Scale) => Property::Scale,
                Checked::Valid(FileProperty::MorphTargetWeights) => {
                    warnings.push(format!(
                        "{place} animates morph target weights; it is ignored"
                    ));
                    continue;
                }
                Checked::Invalid => {
                    warnings.push(format!(
                        "{place} animates an unknown property; it is ignored"
                    ));
                    continue;
                }
            };
            let f = channel.target.node.value();
            let node = match (rig_index.get(f), tree.in_scene.get(f)) {
                (Some(Some(node)), _) => *node,
                (Some(None), Some(true)) => {
                    warnings.push(format!(
                        "{place} moves node {f}, which only holds a skinned mesh (its \
                         transform has no effect); it is ignored"
                    ));
                    continue;
                }
                (Some(None), _) => {
                    warnings.push(format!(
                        "{place} moves node {f}, which is not in the scene read; it is ignored"
                    ));
                    continue;
                }
                (None, _) => {
                    return Err(format!(
                        "{place} targets node {f}, which does not exist (the file has {} nodes)",
                        rig_index.len()
                    ))
                }
            };
            let s = channel.sampler.value();
            let sampler = animation.samplers.get(s).ok_or_else(|| {
                format!(
                    "{place} uses sampler {s}, which does not exist (the animation has {} samplers)",
                    animation.samplers.len()
                )
            })?;
            let interpolation = match sampler.interpolation {
                Checked::Valid(FileInterpolation::Step) => Interpolation::Step,
                Checked::Valid(FileInterpolation::Linear) => Interpolation::Linear,
                Checked::Valid(FileInterpolation::CubicSpline) => Interpolation::CubicSpline,
                Checked::Invalid => {
                    return Err(format!("{place} has an unknown interpolation"));
                }
            };
            let input = sampler.input.value();
            let output = sampler.output.value();
            let count = |i| source.accessor_count(i, &format!("sampler {s} of {place}"));
            let declared = count(input)?.saturating_add(count(output)?);
            if declared > budget as u64 {
                return Err(format!(
                    "the animations hold more than {MAX_VALUES} key times and values (at \
                     {place})"
                ));
            }
            budget -= declared as usize;
            let times = source.floats(
                input,
                &format!("key times of {place}"),
                Type::Scalar,
                Allowed::Float,
            )?;
            check_times(&times).map_err(|e| format!("{place}: {e}"))?;
            let (ty, allowed) = match property {
                Property::Rotation => (Type::Vec4, Allowed::FloatOrNormalized { signed: true }),
                _ => (Type::Vec3, Allowed::Float),
            };
            let values = source.floats(output, &format!("values of {place}"), ty, allowed)?;
            let values: Vec<Vec4> = match ty {
                Type::Vec4 => values.chunks_exact(4).map(Vec4::from_slice).collect(),
                _ => values
                    .chunks_exact(3)
                    .map(|v| Vec4::new(v[0], v[1], v[2], 0.0))
                    .collect(),
            };
            let per_key = if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if values.len() != per_key * times.len() {
                return Err(format!(
                    "{place}: {} keys need {} values ({per_key} per key), the file has {}",
                    times.len(),
                    per_key * times.len(),
                    values.len()
                ));
            }
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!("{place}: value {k} ({}) is not finite", values[k]));
            }
            channels.push(Channel {
                node,
                property,
                interpolation,
                times,
                values,
            });
        }
        clips.push(Clip { name, channels });
    }
    Ok(clips)
}
