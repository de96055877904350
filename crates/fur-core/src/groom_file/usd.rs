//! Guide curves from USD: every `BasisCurves` prim of the file's layer, its transforms
//! applied, read through the `openusd` crate (text, binary and zip packages).
//!
//! One layer is read: references, payloads and sublayers are not followed (a prim
//! that has them is reported in the notes). Linear curves are taken as they are;
//! cubic ones (Bézier, B-spline, Catmull–Rom; non-periodic or pinned) are evaluated
//! to polylines of [`CUBIC_SAMPLES`] segments per cubic segment, and the notes say so.

use std::borrow::Cow;
use std::time::Duration;

use glam::{DMat4, DQuat, DVec3, Vec3};
use openusd::sdf::{self, AbstractData, Value};

use super::{wire, GroomFormat, Guides, MAX_CURVE_VERTICES};
use crate::isolate;

mod crate_file;
mod cubic;
mod layer;
mod write;

pub use crate_file::{usdc_from_text, write_usdc};
pub use layer::{check_nesting, MAX_TEXT_NESTING};
pub use write::{groom_layer, write_usda};

/// Polyline segments per cubic segment when a cubic curve is evaluated.
pub const CUBIC_SAMPLES: usize = 4;

/// The most prims visited (a bound on a malformed file's hierarchy).
pub const MAX_PRIMS: usize = 1 << 20;
/// The deepest prim nesting followed (each level is a call: a bound on the stack).
pub const MAX_DEPTH: usize = 256;
/// The most notes kept (a file with a million prims that each earn one says so once).
pub const MAX_NOTES: usize = 32;

/// What decoding a USD file may take, beyond the reading process's own: this many
/// bytes of memory per byte of the file…
pub const USD_MEMORY_PER_BYTE: u64 = 16;
/// …plus this many.
pub const USD_MEMORY_BASE: u64 = 512 << 20;
/// CPU seconds, plus [`USD_SECONDS_PER_MIB`] a MiB of the file.
pub const USD_SECONDS_BASE: u64 = 30;
/// CPU seconds a MiB of the file.
pub const USD_SECONDS_PER_MIB: u64 = 2;
/// Wall-clock seconds past twice the CPU limit before the decoding is killed.
pub const USD_WALL_SLACK_SECONDS: u64 = 30;

/// The limits a USD file of `len` bytes is decoded under.
pub fn usd_limits(len: usize) -> isolate::Limits {
    let len = len as u64;
    let cpu_seconds = USD_SECONDS_BASE + USD_SECONDS_PER_MIB * len.div_ceil(1 << 20);
    isolate::Limits {
        memory: USD_MEMORY_BASE + USD_MEMORY_PER_BYTE * len,
        cpu_seconds,
        wall: Duration::from_secs(2 * cpu_seconds + USD_WALL_SLACK_SECONDS),
    }
}

/// Reads the guide curves of a USD file's bytes; `format` from its extension (`.usd`
/// may hold text or binary: the bytes decide). The decoding runs in a child process
/// under [`usd_limits`] ([`crate::isolate`]): `openusd` trusts the counts and offsets
/// in a file, and a hostile one could otherwise abort the process.
pub fn parse_usd(bytes: &[u8], format: GroomFormat) -> Result<Guides, String> {
    parse_usd_measured(bytes, format).map(|(guides, _)| guides)
}

/// [`parse_usd`], and the most memory its decoding took (the child's peak address
/// space over its start, in bytes).
pub fn parse_usd_measured(bytes: &[u8], format: GroomFormat) -> Result<(Guides, u64), String> {
    let reply = isolate::run(usd_limits(bytes.len()), || {
        decode_usd(bytes, format).map(|g| wire::encode(&g))
    })?;
    Ok((wire::decode(&reply.bytes)?, reply.peak_memory))
}

/// [`parse_usd`] in this process, without its limits: for files that are known to be
/// sound (and for the isolated child).
pub fn decode_usd(bytes: &[u8], format: GroomFormat) -> Result<Guides, String> {
    let data = layer::open_layer(bytes, format)?;
    let mut guides = Guides::default();
    let mut visited = 0;
    walk(
        &*data,
        &sdf::Path::abs_root(),
        DMat4::IDENTITY,
        &mut guides,
        &mut visited,
        0,
    )?;
    if guides.counts.is_empty() {
        return Err("it holds no BasisCurves prim with points".into());
    }
    Ok(guides)
}

fn field<'a>(data: &'a dyn AbstractData, path: &sdf::Path, name: &str) -> Option<Cow<'a, Value>> {
    data.try_field(path, name).ok().flatten()
}

/// An attribute's value: its default, else its earliest time sample.
fn attribute(
    data: &dyn AbstractData,
    prim: &sdf::Path,
    name: &str,
    notes: &mut Vec<String>,
) -> Option<(Value, Option<String>)> {
    let path = prim.append_property(name).ok()?;
    let interpolation = match field(data, &path, "interpolation").as_deref() {
        Some(Value::Token(t)) => Some(t.as_str().to_string()),
        _ => None,
    };
    if let Some(v) = field(data, &path, "default") {
        return Some((v.into_owned(), interpolation));
    }
    if let Some(Value::TimeSamples(samples)) = field(data, &path, "timeSamples").as_deref() {
        let first = samples
            .iter()
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|s| s.1.clone())?;
        note(
            notes,
            format!("`{name}` has no default: its earliest time sample is read"),
        );
        return Some((first, interpolation));
    }
    None
}

fn note(notes: &mut Vec<String>, text: String) {
    if notes.len() < MAX_NOTES && !notes.contains(&text) {
        notes.push(text);
    }
}

fn token(v: &Value) -> Option<&str> {
    match v {
        Value::Token(t) => Some(t.as_str()),
        Value::String(s) => Some(s),
        _ => None,
    }
}

fn children(data: &dyn AbstractData, path: &sdf::Path) -> Vec<String> {
    match field(data, path, "primChildren").as_deref() {
        Some(Value::TokenVec(v)) => v.iter().map(|t| t.as_str().to_string()).collect(),
        _ => Vec::new(),
    }
}

fn walk(
    data: &dyn AbstractData,
    path: &sdf::Path,
    parent: DMat4,
    guides: &mut Guides,
    visited: &mut usize,
    depth: usize,
) -> Result<(), String> {
    *visited += 1;
    if *visited > MAX_PRIMS {
        return Err(format!("it has more than {MAX_PRIMS} prims"));
    }
    if depth > MAX_DEPTH {
        return Err(format!("{path}: prims nested over {MAX_DEPTH} deep"));
    }
    let world = if path.is_abs_root() {
        parent
    } else {
        parent * local_transform(data, path)?
    };
    if !path.is_abs_root() {
        for arc in ["references", "payload", "inheritPaths", "specializes"] {
            if data.has_field(path, arc) {
                note(
                    &mut guides.notes,
                    format!("{path}: its {arc} are not followed (one layer is read)"),
                );
            }
        }
        let type_name = field(data, path, "typeName");
        if type_name.as_deref().and_then(token) == Some("BasisCurves") {
            let mut curves =
                read_curves(data, path, &mut guides.notes).map_err(|m| format!("{path}: {m}"))?;
            curves.transform(world.as_mat4());
            guides.append(curves);
        }
    }
    for child in children(data, path) {
        let child_path = if path.is_abs_root() {
            sdf::path(format!("/{child}"))
        } else {
            sdf::path(format!("{path}/{child}"))
        }
        .map_err(|e| format!("prim `{child}` under {path}: {e}"))?;
        walk(data, &child_path, world, guides, visited, depth + 1)?;
    }
    Ok(())
}

fn dvec3(v: &Value) -> Option<DVec3> {
    match v {
        Value::Vec3f(a) => Some(DVec3::new(a.x.into(), a.y.into(), a.z.into())),
        Value::Vec3d(a) => Some(DVec3::new(a.x, a.y, a.z)),
        Value::Vec3h(a) => Some(DVec3::new(a.x.into(), a.y.into(), a.z.into())),
        _ => None,
    }
}

fn scalar(v: &Value) -> Option<f64> {
    match v {
        Value::Float(x) => Some((*x).into()),
        Value::Double(x) => Some(*x),
        Value::Half(x) => Some(f64::from(*x)),
        _ => None,
    }
}

/// The prim's own transform, from its `xformOpOrder` (the first op outermost, as USD
/// composes them).
fn local_transform(data: &dyn AbstractData, path: &sdf::Path) -> Result<DMat4, String> {
    let mut notes = Vec::new();
    let Some((Value::TokenVec(order), _)) = attribute(data, path, "xformOpOrder", &mut notes)
    else {
        return Ok(DMat4::IDENTITY);
    };
    let mut m = DMat4::IDENTITY;
    for op in &order {
        let op = op.as_str();
        if op == "!resetXformStack!" {
            return Err(format!("{path}: `!resetXformStack!` is not supported"));
        }
        let (invert, name) = match op.strip_prefix("!invert!") {
            Some(name) => (true, name),
            None => (false, op),
        };
        let value = attribute(data, path, name, &mut notes)
            .map(|(v, _)| v)
            .ok_or_else(|| format!("{path}: transform op `{name}` has no value"))?;
        let bad = || format!("{path}: transform op `{name}` holds {value:?}, not its type");
        let kind = name
            .strip_prefix("xformOp:")
            .map(|k| k.split(':').next().unwrap_or(k))
            .unwrap_or("");
        let op_matrix = match kind {
            "transform" => match &value {
                Value::Matrix4d(a) => DMat4::from_cols_array(&a.0),
                _ => return Err(bad()),
            },
            "translate" => DMat4::from_translation(dvec3(&value).ok_or_else(bad)?),
            "scale" => DMat4::from_scale(dvec3(&value).ok_or_else(bad)?),
            "rotateX" => DMat4::from_rotation_x(scalar(&value).ok_or_else(bad)?.to_radians()),
            "rotateY" => DMat4::from_rotation_y(scalar(&value).ok_or_else(bad)?.to_radians()),
            "rotateZ" => DMat4::from_rotation_z(scalar(&value).ok_or_else(bad)?.to_radians()),
            "rotateXYZ" | "rotateXZY" | "rotateYXZ" | "rotateYZX" | "rotateZXY" | "rotateZYX" => {
                let a = dvec3(&value).ok_or_else(bad)?;
                let mut r = DMat4::IDENTITY;
                // The first named axis turns first: it is the innermost factor.
                for axis in kind["rotate".len()..].chars() {
                    let turn = match axis {
                        'X' => DMat4::from_rotation_x(a.x.to_radians()),
                        'Y' => DMat4::from_rotation_y(a.y.to_radians()),
                        _ => DMat4::from_rotation_z(a.z.to_radians()),
                    };
                    r = turn * r;
                }
                r
            }
            "orient" => {
                let q = match &value {
                    Value::Quatf(q) => {
                        DQuat::from_xyzw(q.x.into(), q.y.into(), q.z.into(), q.w.into())
                    }
                    Value::Quatd(q) => DQuat::from_xyzw(q.x, q.y, q.z, q.w),
                    _ => return Err(bad()),
                };
                DMat4::from_quat(q.normalize())
            }
            _ => return Err(format!("{path}: transform op `{op}` is not supported")),
        };
        m *= if invert {
            op_matrix.inverse()
        } else {
            op_matrix
        };
    }
    Ok(m)
}

fn points(v: &Value) -> Option<Vec<Vec3>> {
    match v {
        Value::Vec3fVec(p) => Some(p.iter().map(|a| Vec3::new(a.x, a.y, a.z)).collect()),
        Value::Vec3dVec(p) => Some(
            p.iter()
                .map(|a| Vec3::new(a.x as f32, a.y as f32, a.z as f32))
                .collect(),
        ),
        _ => None,
    }
}

fn floats(v: &Value) -> Option<Vec<f32>> {
    match v {
        Value::FloatVec(w) => Some(w.clone()),
        Value::DoubleVec(w) => Some(w.iter().map(|&x| x as f32).collect()),
        Value::Float(x) => Some(vec![*x]),
        Value::Double(x) => Some(vec![*x as f32]),
        _ => None,
    }
}

/// One `BasisCurves` prim's curves, in its own space.
fn read_curves(
    data: &dyn AbstractData,
    prim: &sdf::Path,
    notes: &mut Vec<String>,
) -> Result<Guides, String> {
    let get = |name: &str, notes: &mut Vec<String>| attribute(data, prim, name, notes);
    let counts = match get("curveVertexCounts", notes) {
        Some((Value::IntVec(c), _)) => c,
        Some(_) => return Err("`curveVertexCounts` is not an int array".into()),
        None => return Err("it has no `curveVertexCounts`".into()),
    };
    let cvs = match get("points", notes) {
        Some((v, _)) => points(&v).ok_or("`points` is not a point array")?,
        None => return Err("it has no `points`".into()),
    };
    if let Some(i) = counts.iter().position(|&c| c < 2) {
        return Err(format!("curve {i} has {} control points", counts[i]));
    }
    let total: i64 = counts.iter().map(|&c| i64::from(c)).sum();
    if total != cvs.len() as i64 {
        return Err(format!(
            "`curveVertexCounts` add up to {total} but there are {} points",
            cvs.len()
        ));
    }
    let name = |v: Option<(Value, Option<String>)>, default: &str| {
        v.and_then(|(v, _)| token(&v).map(str::to_string))
            .unwrap_or_else(|| default.to_string())
    };
    let curve_type = name(get("type", notes), "cubic");
    let basis = name(get("basis", notes), "bezier");
    let wrap = name(get("wrap", notes), "nonperiodic");
    if wrap == "periodic" {
        return Err("its curves are periodic (closed loops), not hairs".into());
    }
    let shape = cubic::Shape::new(&curve_type, &basis, &wrap)?;
    if shape.is_cubic() {
        note(
            notes,
            format!(
                "cubic `{basis}` curves are evaluated to polylines ({CUBIC_SAMPLES} segments per \
                 cubic segment)"
            ),
        );
    }
    let counts: Vec<usize> = counts.iter().map(|&c| c as usize).collect();
    let widths = get("widths", notes)
        .map(|(v, i)| (floats(&v), i))
        .and_then(|(v, i)| v.map(|v| (v, i.unwrap_or_else(|| "vertex".into()))));
    // A colour is three channels, each interpolated as a scalar: split once.
    let colours = get("primvars:displayColor", notes).and_then(|(v, i)| {
        points(&v).map(|v| {
            let channel = |k: usize| v.iter().map(|p| p[k]).collect::<Vec<f32>>();
            (
                [channel(0), channel(1), channel(2)],
                i.unwrap_or_else(|| "constant".into()),
            )
        })
    });
    let exact = |what: &str, len: usize, interpolation: &str| -> Result<(), String> {
        let needed = shape
            .values_needed(interpolation, &counts)
            .map_err(|m| format!("`{what}` has {m}"))?;
        if len != needed {
            return Err(format!(
                "`{what}` ({interpolation}) has {len} value{}; {} curves of {} control points \
                 need exactly {needed}",
                if len == 1 { "" } else { "s" },
                counts.len(),
                cvs.len()
            ));
        }
        Ok(())
    };
    if let Some((w, i)) = &widths {
        exact("widths", w.len(), i)?;
    }
    if let Some((c, i)) = &colours {
        exact("primvars:displayColor", c[0].len(), i)?;
    }
    let mut out = Guides::default();
    let mut widths_out = widths.as_ref().map(|_| Vec::new());
    let mut colours_out = colours.as_ref().map(|_| Vec::new());
    let mut start = 0;
    let segments_before = shape.varying_starts(&counts)?;
    for (c, &count) in counts.iter().enumerate() {
        let polyline = shape.evaluate(&cvs[start..start + count])?;
        if polyline.len() > MAX_CURVE_VERTICES {
            return Err(format!(
                "curve {c} evaluates to over {MAX_CURVE_VERTICES} vertices"
            ));
        }
        let per_vertex = |values: &[f32], interpolation: &str, what: &str| {
            let curve = cubic::CurveAt {
                index: c,
                first: start,
                count,
                varying_at: segments_before[c],
            };
            shape.per_vertex(values, interpolation, curve, what)
        };
        if let (Some(out), Some((w, i))) = (&mut widths_out, &widths) {
            out.extend(per_vertex(w, i, "widths")?);
        }
        if let (Some(out), Some((v, i))) = (&mut colours_out, &colours) {
            let r = per_vertex(&v[0], i, "displayColor")?;
            let g = per_vertex(&v[1], i, "displayColor")?;
            let b = per_vertex(&v[2], i, "displayColor")?;
            out.extend((0..r.len()).map(|k| Vec3::new(r[k], g[k], b[k])));
        }
        out.counts.push(polyline.len() as u32);
        out.points.extend(polyline);
        start += count;
    }
    out.widths = widths_out;
    out.colors = colours_out;
    Ok(out)
}
