//! The USD text encoding (`.usda`) of an exported frame: one root `Xform` holding the
//! camera, the lights, the body (`Mesh`) and the hairs (one linear `BasisCurves`).
//!
//! Every number is written as the shortest decimal that reads back to the same `f32`,
//! so the file holds exactly what was drawn. Names fur adds are in the `fur:`
//! namespace (docs/ground-truth.md lists them).

use std::fmt::Write as _;

use glam::{Mat4, Quat, Vec3};

use super::{BodyExport, CameraExport, FrameExport, LightExport};
use fur_gpu::error::{Error, Result};

/// The camera's film height in the file's units (USD cameras take apertures and a
/// focal length; only their ratio to each other matters here).
const APERTURE: f32 = 24.0;

/// The frame as `.usda` text; `generator` names the program in the layer's metadata.
pub fn write_usda(frame: &FrameExport, generator: &str) -> Result<String> {
    check_finite(frame)?;
    let mut out = String::with_capacity(frame.estimated_bytes() as usize);
    let c = &frame.camera;
    // `writeln!` into a String cannot fail.
    let _ = writeln!(
        out,
        "#usda 1.0\n(\n    defaultPrim = \"World\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n    \
         customLayerData = {{\n        string generator = \"{generator}\"\n        \
         int2 \"fur:resolution\" = ({}, {})\n        \
         color3f \"fur:background\" = {}\n    }}\n)\n\ndef Xform \"World\"\n{{",
        c.width,
        c.height,
        vec3(fur_gpu::render::BACKGROUND)
    );
    camera(&mut out, c);
    lights(&mut out, &frame.light);
    if let Some(body) = &frame.body {
        body_mesh(&mut out, body);
    }
    hairs(&mut out, frame);
    out.push_str("}\n");
    Ok(out)
}

fn check_finite(frame: &FrameExport) -> Result<()> {
    let h = &frame.hairs;
    let finite = h.points.iter().all(|p| p.is_finite())
        && h.widths
            .iter()
            .chain(&h.drawn_widths)
            .all(|w| w.is_finite())
        && h.colors.iter().all(|c| c.is_finite())
        && frame
            .body
            .as_ref()
            .is_none_or(|b| b.positions.iter().chain(&b.normals).all(|p| p.is_finite()));
    if finite {
        Ok(())
    } else {
        Err(Error::parameter(
            "the frame holds a non-finite position, width or colour: the simulation has \
             diverged; nothing was written",
        ))
    }
}

fn camera(out: &mut String, c: &CameraExport) {
    let focal = 0.5 * APERTURE / (0.5 * c.fov_y_deg.to_radians()).tan();
    let aspect = c.width as f32 / c.height.max(1) as f32;
    let _ = writeln!(
        out,
        "    def Camera \"Camera\"\n    {{\n        \
         float2 clippingRange = ({}, {})\n        \
         float focalLength = {focal}\n        \
         float horizontalAperture = {}\n        \
         float verticalAperture = {APERTURE}\n        \
         token projection = \"perspective\"\n        \
         custom float fur:fovY = {}\n        \
         custom point3f fur:eye = {}\n        \
         custom point3f fur:target = {}\n        \
         custom vector3f fur:up = {}\n        \
         matrix4d xformOp:transform = {}\n        \
         uniform token[] xformOpOrder = [\"xformOp:transform\"]\n    }}",
        c.near,
        c.far,
        APERTURE * aspect,
        c.fov_y_deg,
        vec3(c.eye),
        vec3(c.target),
        vec3(c.up),
        matrix(c.view.inverse()),
    );
}

fn lights(out: &mut String, l: &LightExport) {
    // A distant light shines down its local −Z: its +Z turns to the light.
    let orient = Mat4::from_quat(Quat::from_rotation_arc(Vec3::Z, l.direction));
    let _ = writeln!(
        out,
        "    def DistantLight \"Sun\"\n    {{\n        \
         float inputs:angle = 0\n        \
         color3f inputs:color = (1, 1, 1)\n        \
         float inputs:intensity = {}\n        \
         custom float fur:irradiance = {}\n        \
         custom vector3f fur:direction = {}\n        \
         matrix4d xformOp:transform = {}\n        \
         uniform token[] xformOpOrder = [\"xformOp:transform\"]\n    }}\n\
         \n    def DomeLight \"Environment\"\n    {{\n        \
         color3f inputs:color = (1, 1, 1)\n        \
         float inputs:intensity = {}\n        \
         custom float fur:radiance = {}\n    }}",
        l.irradiance,
        l.irradiance,
        vec3(l.direction),
        matrix(orient),
        l.environment,
        l.environment,
    );
}

fn body_mesh(out: &mut String, b: &BodyExport) {
    out.push_str("\n    def Mesh \"Body\"\n    {\n        uniform bool doubleSided = 0\n");
    let _ = writeln!(
        out,
        "        float3[] extent = {}",
        extent(&b.positions, 0.0)
    );
    out.push_str("        int[] faceVertexCounts = [");
    join(out, b.indices.chunks_exact(3), |out, _| out.push('3'));
    out.push_str("]\n        int[] faceVertexIndices = [");
    join(out, b.indices.iter(), |out, i| {
        let _ = write!(out, "{i}");
    });
    out.push_str("]\n        point3f[] points = [");
    join(out, b.positions.iter(), |out, p| out.push_str(&vec3(*p)));
    out.push_str("]\n        normal3f[] normals = [");
    join(out, b.normals.iter(), |out, n| out.push_str(&vec3(*n)));
    out.push_str("] (\n            interpolation = \"vertex\"\n        )\n        color3f[] primvars:displayColor = [");
    join(out, b.albedo.iter(), |out, c| out.push_str(&vec3(*c)));
    // One colour for the body, or one per triangle (a texture's).
    let interpolation = if b.albedo.len() == 1 {
        "constant"
    } else {
        "uniform"
    };
    let _ = writeln!(
        out,
        "] (\n            interpolation = \"{interpolation}\"\n        )\n        \
         uniform token orientation = \"rightHanded\"\n        \
         uniform token subdivisionScheme = \"none\"\n    }}"
    );
}

fn hairs(out: &mut String, frame: &FrameExport) {
    let h = &frame.hairs;
    let f = &frame.fibre;
    let widest = h
        .widths
        .iter()
        .chain(&h.drawn_widths)
        .fold(0.0f32, |a, &w| a.max(w));
    out.push_str(
        "\n    def BasisCurves \"Hair\"\n    {\n        uniform token type = \"linear\"\n",
    );
    out.push_str("        uniform token wrap = \"nonperiodic\"\n");
    let _ = writeln!(
        out,
        "        float3[] extent = {}",
        extent(&h.points, 0.5 * widest)
    );
    let _ = writeln!(
        out,
        "        custom float fur:fibre:longitudinalRoughness = {}\n        \
         custom float fur:fibre:azimuthalRoughness = {}\n        \
         custom float fur:fibre:cuticleTiltDegrees = {}\n        \
         custom float fur:fibre:ior = {}",
        f.longitudinal_roughness, f.azimuthal_roughness, f.cuticle_tilt_deg, f.ior
    );
    out.push_str("        int[] curveVertexCounts = [");
    let v = h.vertices_per_strand;
    join(out, 0..h.count(), |out, _| {
        let _ = write!(out, "{v}");
    });
    out.push_str("]\n        point3f[] points = [");
    join(out, h.points.iter(), |out, p| out.push_str(&vec3(*p)));
    out.push_str("]\n        float[] widths = [");
    join(out, h.widths.iter(), |out, w| {
        let _ = write!(out, "{w}");
    });
    out.push_str("] (\n            interpolation = \"vertex\"\n        )\n");
    out.push_str("        color3f[] primvars:displayColor = [");
    join(out, h.colors.iter(), |out, c| out.push_str(&vec3(*c)));
    out.push_str("] (\n            interpolation = \"vertex\"\n        )\n");
    out.push_str("        float[] primvars:fur:drawnWidths = [");
    join(out, h.drawn_widths.iter(), |out, w| {
        let _ = write!(out, "{w}");
    });
    out.push_str("] (\n            interpolation = \"vertex\"\n        )\n");
    out.push_str("        int[] primvars:fur:ribbon = [");
    join(out, h.ribbons.iter(), |out, r| {
        out.push(if *r { '1' } else { '0' })
    });
    out.push_str("] (\n            interpolation = \"uniform\"\n        )\n    }\n");
}

/// Writes `items` separated by ", " through `each`.
fn join<T>(out: &mut String, items: impl Iterator<Item = T>, mut each: impl FnMut(&mut String, T)) {
    for (i, item) in items.enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        each(out, item);
    }
}

fn vec3(v: Vec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

/// A USD matrix: rows are glam's columns (USD multiplies row vectors on the left).
fn matrix(m: Mat4) -> String {
    let c = m.to_cols_array_2d();
    let row = |r: [f32; 4]| format!("({}, {}, {}, {})", r[0], r[1], r[2], r[3]);
    format!(
        "( {}, {}, {}, {} )",
        row(c[0]),
        row(c[1]),
        row(c[2]),
        row(c[3])
    )
}

/// The bounding box of `points` grown by `margin`, as USD's `extent`.
fn extent(points: &[Vec3], margin: f32) -> String {
    let (lo, hi) = points.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    if points.is_empty() {
        return "[(0, 0, 0), (0, 0, 0)]".into();
    }
    format!("[{}, {}]", vec3(lo - margin), vec3(hi + margin))
}
