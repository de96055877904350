//! Guide curves as USD text: one linear `BasisCurves` prim, written through the
//! `openusd` crate's text writer (Pixar's `usd-core` reads it; tests check).

use glam::Vec3;
use openusd::gf;
use openusd::sdf::{self, ChildrenKey, FieldKey, SpecType, Specifier, Value, Variability};

use crate::groom_file::Guides;

/// The prim the curves are written to.
pub const GROOM_PRIM: &str = "Groom";

fn vec3s(v: &[Vec3]) -> Value {
    Value::Vec3fVec(
        v.iter()
            .map(|p| gf::Vec3f {
                x: p.x,
                y: p.y,
                z: p.z,
            })
            .collect(),
    )
}

/// `guides` as `.usda` text; `generator` goes into the layer's documentation.
pub fn write_usda(guides: &Guides, generator: &str) -> Result<String, String> {
    let data = groom_layer(guides, generator)?;
    openusd::usda::TextWriter::write_to_string(&data).map_err(|e| format!("{e:#}"))
}

/// `guides` as a USD layer: one linear `BasisCurves` prim, `/Groom`.
pub fn groom_layer(guides: &Guides, generator: &str) -> Result<sdf::Data, String> {
    let mut data = sdf::Data::new();
    let root = data.create_spec(sdf::Path::abs_root(), SpecType::PseudoRoot);
    root.add(
        ChildrenKey::PrimChildren,
        Value::TokenVec(vec![GROOM_PRIM.into()]),
    );
    root.add(FieldKey::DefaultPrim, Value::Token(GROOM_PRIM.into()));
    root.add(
        FieldKey::Documentation,
        Value::String(format!("guide curves written by {generator}")),
    );
    root.add("upAxis", Value::Token("Y".into()));
    root.add("metersPerUnit", Value::Double(1.0));
    let prim = sdf::path(format!("/{GROOM_PRIM}")).map_err(|e| e.to_string())?;
    let (lo, hi) = guides.points.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let widest = guides
        .widths
        .iter()
        .flatten()
        .fold(0.0f32, |a, &w| a.max(w));
    let mut attributes: Vec<(&str, &str, Value, bool, Option<&str>)> = vec![
        ("type", "token", Value::Token("linear".into()), true, None),
        (
            "wrap",
            "token",
            Value::Token("nonperiodic".into()),
            true,
            None,
        ),
        (
            "curveVertexCounts",
            "int[]",
            Value::IntVec(guides.counts.iter().map(|&c| c as i32).collect()),
            false,
            None,
        ),
        ("points", "point3f[]", vec3s(&guides.points), false, None),
        (
            "extent",
            "float3[]",
            vec3s(&[lo - 0.5 * widest, hi + 0.5 * widest]),
            false,
            None,
        ),
    ];
    if let Some(w) = &guides.widths {
        attributes.push((
            "widths",
            "float[]",
            Value::FloatVec(w.clone()),
            false,
            Some("vertex"),
        ));
    }
    if let Some(c) = &guides.colors {
        attributes.push((
            "primvars:displayColor",
            "color3f[]",
            vec3s(c),
            false,
            Some("vertex"),
        ));
    }
    let names = attributes.iter().map(|a| a.0.into()).collect();
    let spec = data.create_spec(prim.clone(), SpecType::Prim);
    spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Def));
    spec.add(FieldKey::TypeName, Value::Token("BasisCurves".into()));
    spec.add(ChildrenKey::PropertyChildren, Value::TokenVec(names));
    for (name, type_name, value, uniform, interpolation) in attributes {
        let path = prim.append_property(name).map_err(|e| e.to_string())?;
        let a = data.create_spec(path, SpecType::Attribute);
        a.add(FieldKey::TypeName, Value::Token(type_name.into()));
        a.add(FieldKey::Default, value);
        if uniform {
            a.add(
                FieldKey::Variability,
                Value::Variability(Variability::Uniform),
            );
        }
        if let Some(i) = interpolation {
            a.add("interpolation", Value::Token(i.into()));
        }
    }
    Ok(data)
}
