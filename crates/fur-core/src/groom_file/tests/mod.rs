use glam::Vec3;

use super::*;

mod binary;
mod hostile;

pub(super) fn sample_guides() -> Guides {
    Guides {
        counts: vec![3, 4],
        points: (0..7)
            .map(|i| Vec3::new(0.1 * i as f32, 1.0 / 3.0, -0.7 * i as f32))
            .collect(),
        widths: Some((0..7).map(|i| 0.001 * (7 - i) as f32).collect()),
        colors: Some(
            (0..7)
                .map(|i| Vec3::new(0.9, 0.1 * i as f32, 0.3))
                .collect(),
        ),
        notes: Vec::new(),
    }
}

#[test]
fn usd_text_written_by_fur_reads_back_exactly() {
    let g = sample_guides();
    let text = write_usda(&g, "fur test").unwrap();
    assert!(text.starts_with("#usda 1.0"));
    let back = parse_usd(text.as_bytes(), GroomFormat::Usda).unwrap();
    assert_eq!(back, g);
    // `.usd` decides by the bytes.
    assert_eq!(parse_usd(text.as_bytes(), GroomFormat::Usdc).unwrap(), g);
}

fn usda(curves: &str) -> String {
    format!("#usda 1.0\n(\n    upAxis = \"Y\"\n)\n\ndef Xform \"Root\"\n{{\n{curves}\n}}\n")
}

fn read(text: &str) -> Result<Guides, String> {
    parse_usd(text.as_bytes(), GroomFormat::Usda)
}

#[test]
fn usd_transforms_compose_parent_first_and_the_first_op_outermost() {
    let text = "#usda 1.0\ndef Xform \"A\"\n{\n    double3 xformOp:translate = (10, 0, 0)\n    \
         uniform token[] xformOpOrder = [\"xformOp:translate\"]\n    \
         def BasisCurves \"C\"\n    {\n        uniform token type = \"linear\"\n        \
         int[] curveVertexCounts = [2]\n        point3f[] points = [(1, 0, 0), (1, 1, 0)]\n        \
         float3 xformOp:scale = (2, 2, 2)\n        float xformOp:rotateZ = 90\n        \
         uniform token[] xformOpOrder = [\"xformOp:scale\", \"xformOp:rotateZ\"]\n    }\n}\n";
    let g = read(text).unwrap();
    // Rotate (1, 0, 0) by 90° about Z → (0, 1, 0); scale → (0, 2, 0); parent → (10, 2, 0).
    assert!(
        g.points[0].distance(Vec3::new(10.0, 2.0, 0.0)) < 1e-5,
        "{:?}",
        g.points
    );
    assert!(
        g.points[1].distance(Vec3::new(8.0, 2.0, 0.0)) < 1e-5,
        "{:?}",
        g.points
    );
}

#[test]
fn cubic_usd_curves_are_evaluated_through_their_basis() {
    let curve =
        |basis: &str, wrap: &str, n: usize| {
            let pts: Vec<String> = (0..n)
                .map(|i| format!("({i}, {}, 0)", (i * i) as f32))
                .collect();
            usda(&format!(
            "    def BasisCurves \"C\"\n    {{\n        uniform token type = \"cubic\"\n        \
             uniform token basis = \"{basis}\"\n        uniform token wrap = \"{wrap}\"\n        \
             int[] curveVertexCounts = [{n}]\n        point3f[] points = [{}]\n        \
             float[] widths = [{}] (interpolation = \"vertex\")\n    }}",
            pts.join(", "),
            (0..n).map(|i| format!("{}", i + 1)).collect::<Vec<_>>().join(", ")
        ))
        };
    let p = |i: f32| Vec3::new(i, i * i, 0.0);
    // Bézier: through its first and last control points, 4 samples per segment.
    let g = read(&curve("bezier", "nonperiodic", 7)).unwrap();
    assert_eq!(g.counts, vec![2 * CUBIC_SAMPLES as u32 + 1]);
    assert_eq!(g.points[0], p(0.0));
    assert!(g.points[CUBIC_SAMPLES].distance(p(3.0)) < 1e-5);
    assert!(g.points.last().unwrap().distance(p(6.0)) < 1e-5);
    assert!(g.notes.iter().any(|n| n.contains("evaluated")));
    // Catmull–Rom: through its inner control points; pinned: through its ends too.
    let g = read(&curve("catmullRom", "nonperiodic", 5)).unwrap();
    assert_eq!(g.counts, vec![2 * CUBIC_SAMPLES as u32 + 1]);
    assert!(g.points[0].distance(p(1.0)) < 1e-5);
    assert!(g.points[CUBIC_SAMPLES].distance(p(2.0)) < 1e-5);
    let g = read(&curve("catmullRom", "pinned", 5)).unwrap();
    assert!(g.points[0].distance(p(0.0)) < 1e-5);
    assert!(g.points.last().unwrap().distance(p(4.0)) < 1e-5);
    // B-spline: a uniform B-spline's segment starts at (P0 + 4 P1 + P2) / 6.
    let g = read(&curve("bspline", "nonperiodic", 5)).unwrap();
    assert!(g.points[0].distance((p(0.0) + 4.0 * p(1.0) + p(2.0)) / 6.0) < 1e-5);
    let w = g.widths.unwrap();
    assert!((w[0] - (1.0 + 4.0 * 2.0 + 3.0) / 6.0).abs() < 1e-5, "{w:?}");
    let g = read(&curve("bspline", "pinned", 5)).unwrap();
    assert!(g.points[0].distance(p(0.0)) < 1e-5);
    // Counts a basis cannot take are errors naming the prim.
    let e = read(&curve("bezier", "nonperiodic", 6)).unwrap_err();
    assert!(e.contains("/Root/C") && e.contains("3n + 1"), "{e}");
    let e = read(&curve("bspline", "periodic", 5)).unwrap_err();
    assert!(e.contains("periodic"), "{e}");
}

#[test]
fn bad_usd_is_an_error_naming_the_problem() {
    assert!(read("#usda 1.0\ndef Xform \"A\" {")
        .unwrap_err()
        .contains("USD text"));
    assert!(read(&usda("")).unwrap_err().contains("no BasisCurves"));
    let mismatch = usda(
        "    def BasisCurves \"C\"\n    {\n        uniform token type = \"linear\"\n        \
         int[] curveVertexCounts = [3]\n        point3f[] points = [(0, 0, 0), (1, 0, 0)]\n    }",
    );
    assert!(read(&mismatch).unwrap_err().contains("add up to 3"));
    let short_widths = usda(
        "    def BasisCurves \"C\"\n    {\n        uniform token type = \"linear\"\n        \
         int[] curveVertexCounts = [2]\n        point3f[] points = [(0, 0, 0), (1, 0, 0)]\n        \
         float[] widths = [1] (interpolation = \"vertex\")\n    }",
    );
    assert!(read(&short_widths)
        .unwrap_err()
        .contains("has 1 value; 1 curves of 2 control points need exactly 2"));
    assert!(parse_usd(b"garbage", GroomFormat::Usdc)
        .unwrap_err()
        .contains("neither"));
    assert!(parse_usd(b"PK garbage", GroomFormat::Usdz).is_err());
    assert!(parse_usd(b"PXR-USDC garbage", GroomFormat::Usdc).is_err());
    // Prims nested deeper than the walk follows: an error, not a blown stack.
    let mut deep = String::from("#usda 1.0\n");
    for i in 0..300 {
        deep.push_str(&format!("def Xform \"P{i}\" {{\n"));
    }
    deep.push_str(&"}\n".repeat(300));
    let e = read(&deep).unwrap_err();
    assert!(e.contains("nested over 256"), "{e}");
    // Brackets nested a million deep are refused before the parser sees them.
    let brackets = format!("#usda 1.0\n{}", "[".repeat(1_000_000));
    assert!(read(&brackets).unwrap_err().contains("nested 1000000 deep"));
}

#[test]
fn the_format_follows_the_extension_and_unknown_ones_are_named() {
    use std::path::Path;
    assert_eq!(
        GroomFormat::of(Path::new("a.HAIR")).unwrap(),
        GroomFormat::CyHair
    );
    assert_eq!(
        GroomFormat::of(Path::new("a.usdz")).unwrap(),
        GroomFormat::Usdz
    );
    let e = GroomFormat::of(Path::new("a.abc")).unwrap_err().to_string();
    assert!(e.contains("a.abc") && e.contains(".tfx"), "{e}");
}

#[test]
fn validation_names_what_is_wrong() {
    let mut g = sample_guides();
    g.counts[0] = 1;
    assert!(g.validate().unwrap_err().contains("curve 0"));
    let mut g = sample_guides();
    g.points[2].y = f32::INFINITY;
    assert!(g.validate().unwrap_err().contains("point 2"));
    let mut g = sample_guides();
    g.widths.as_mut().unwrap().pop();
    assert!(g.validate().unwrap_err().contains("widths"));
    assert!(Guides::default()
        .validate()
        .unwrap_err()
        .contains("no curves"));
}

/// The cyHair writer at its limits: a curve of 65,535 vertices (65,534 segments, the
/// most a u16 count holds with room) is written and reads back, one more is refused
/// naming the curve; the arrays' flags name exactly the arrays written (widths alone,
/// colours alone); the header's text is the info cut to 87 bytes and a NUL.
#[test]
fn the_cyhair_writer_keeps_its_limits_flags_and_text() {
    let curve = |n: u32, widths: bool, colors: bool| {
        let points: Vec<Vec3> = (0..n).map(|i| Vec3::new(0.0, i as f32, 0.0)).collect();
        Guides {
            counts: vec![n],
            widths: widths.then(|| vec![0.01; points.len()]),
            colors: colors.then(|| vec![Vec3::ONE; points.len()]),
            points,
            notes: Vec::new(),
        }
    };
    let longest = curve(65_535, false, false);
    let written = write_cyhair(&longest, "").unwrap();
    assert_eq!(parse_cyhair(&written).unwrap(), longest);
    // A later curve's count with a high byte (299 segments after a curve of 1).
    let mut two = curve(2, false, false);
    two.counts.push(300);
    two.points
        .extend((0..300).map(|i| Vec3::new(1.0, i as f32, 0.0)));
    assert_eq!(parse_cyhair(&write_cyhair(&two, "").unwrap()).unwrap(), two);
    let err = write_cyhair(&curve(65_536, false, false), "").unwrap_err();
    assert_eq!(
        err,
        "curve 0 has 65536 vertices; cyHair holds at most 65535"
    );
    let flags = |g: &Guides| {
        let b = write_cyhair(g, "").unwrap();
        u32::from_le_bytes([b[12], b[13], b[14], b[15]])
    };
    assert_eq!(flags(&curve(3, false, false)), 1 | 2);
    assert_eq!(flags(&curve(3, true, false)), 1 | 2 | 4);
    assert_eq!(flags(&curve(3, false, true)), 1 | 2 | 16);
    assert_eq!(flags(&curve(3, true, true)), 1 | 2 | 4 | 16);
    let long_info = "x".repeat(100);
    let b = write_cyhair(&curve(2, false, false), &long_info).unwrap();
    assert_eq!(&b[40..127], "x".repeat(87).as_bytes());
    assert_eq!(b[127], 0);
    let b = write_cyhair(&curve(2, false, false), "fur").unwrap();
    assert_eq!(&b[40..43], b"fur");
    assert!(b[43..128].iter().all(|&x| x == 0));
}

/// Each transform op and value type the reader takes, on one point (1, 2, 3) of a
/// two-point curve: a 4×4 matrix (a translation by (10, 0, 0), row-vector layout as USD
/// writes it), rotateX and rotateY by 90° (in double), rotateXYZ (90, 0, 0) and (0, 90,
/// 0), orient as quatf and quatd (90° about Z), a translation and a rotation in halves,
/// each worked out by hand; points in double, widths in double and as one constant
/// float or double for the whole curve.
#[test]
fn every_transform_op_and_value_type_reads_as_worked_out() {
    let curve = |ops: &str, order: &str, points: &str, widths: &str| {
        usda(&format!(
            "    def BasisCurves \"C\"\n    {{\n        uniform token type = \"linear\"\n        \
             int[] curveVertexCounts = [2]\n        {points}\n        {widths}\n        \
             {ops}\n        uniform token[] xformOpOrder = [{order}]\n    }}"
        ))
    };
    let first = |ops: &str, order: &str| {
        let text = curve(
            ops,
            order,
            "point3f[] points = [(1, 2, 3), (1, 2, 4)]",
            "float[] widths = [0.5, 0.25] (interpolation = \"vertex\")",
        );
        read(&text).unwrap_or_else(|e| panic!("{ops}: {e}")).points[0]
    };
    let cases: [(&str, &str, Vec3); 9] = [
        ("half3 xformOp:translate = (10, 0, 0)", "\"xformOp:translate\"", Vec3::new(11.0, 2.0, 3.0)),
        ("half xformOp:rotateX = 90", "\"xformOp:rotateX\"", Vec3::new(1.0, -3.0, 2.0)),
        (
            "matrix4d xformOp:transform = ( (1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (10, 0, 0, 1) )",
            "\"xformOp:transform\"",
            Vec3::new(11.0, 2.0, 3.0),
        ),
        ("double xformOp:rotateX = 90", "\"xformOp:rotateX\"", Vec3::new(1.0, -3.0, 2.0)),
        ("double xformOp:rotateY = 90", "\"xformOp:rotateY\"", Vec3::new(3.0, 2.0, -1.0)),
        ("float3 xformOp:rotateXYZ = (90, 0, 0)", "\"xformOp:rotateXYZ\"", Vec3::new(1.0, -3.0, 2.0)),
        ("float3 xformOp:rotateXYZ = (0, 90, 0)", "\"xformOp:rotateXYZ\"", Vec3::new(3.0, 2.0, -1.0)),
        (
            "quatf xformOp:orient = (0.70710677, 0, 0, 0.70710677)",
            "\"xformOp:orient\"",
            Vec3::new(-2.0, 1.0, 3.0),
        ),
        (
            "quatd xformOp:orient = (0.7071067811865476, 0, 0, 0.7071067811865476)",
            "\"xformOp:orient\"",
            Vec3::new(-2.0, 1.0, 3.0),
        ),
    ];
    for (ops, order, expected) in cases {
        let got = first(ops, order);
        assert!(
            got.distance(expected) < 1e-5,
            "{ops}: {got} against {expected}"
        );
    }
    let g = read(&curve(
        "",
        "",
        "point3d[] points = [(1, 2, 3), (1, 2, 4)]",
        "double[] widths = [0.5, 0.25] (interpolation = \"vertex\")",
    ))
    .unwrap();
    assert_eq!(g.points[1], Vec3::new(1.0, 2.0, 4.0));
    assert_eq!(g.widths, Some(vec![0.5, 0.25]));
    for kind in ["float", "double"] {
        let g = read(&curve(
            "",
            "",
            "point3f[] points = [(1, 2, 3), (1, 2, 4)]",
            &format!("{kind} widths = 0.125 (interpolation = \"constant\")"),
        ))
        .unwrap();
        assert_eq!(g.widths, Some(vec![0.125, 0.125]), "{kind}");
    }
}

/// Brackets inside a quoted string (escaped quotes included) do not count towards the
/// nesting limit; the same brackets outside a string are refused before the parser
/// sees them, and as many one after another (a long curve's points) are not deep.
#[test]
fn usd_nesting_counts_brackets_outside_strings_only() {
    let deep = "(".repeat(1100);
    let quoted = usda(&format!(
        "    def BasisCurves \"C\" (\n        doc = \"a \\\" {deep} \\\" b\"\n    )\n    {{\n        \
         uniform token type = \"linear\"\n        int[] curveVertexCounts = [2]\n        \
         point3f[] points = [(0, 0, 0), (0, 1, 0)]\n    }}"
    ));
    let g = read(&quoted).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(g.counts, vec![2]);
    let err = read(&format!("#usda 1.0\n{deep}\n")).unwrap_err();
    assert!(err.contains("nested 1100 deep"), "{err}");
    // As many brackets one after another as were nested above: a long curve, not deep.
    let points: Vec<String> = (0..1100).map(|i| format!("(0, {i}, 0)")).collect();
    let long = usda(&format!(
        "    def BasisCurves \"C\"\n    {{\n        uniform token type = \"linear\"\n        \
         int[] curveVertexCounts = [1100]\n        point3f[] points = [{}]\n    }}",
        points.join(", ")
    ));
    assert_eq!(read(&long).unwrap().counts, vec![1100]);
}

/// A uniform cubic B-spline reproduces a quadratic up to a constant: through control
/// points (i, i²) it is (u, u² + 1/3) for the curve parameter u, at every sample (the
/// basis worked out: (p₀ + 4p₁ + p₂)/6 at a segment's start). Four control points make
/// one segment; pinned, its phantom ends 2p₀ − p₁ and 2pₙ − pₙ₋₁ take it through its
/// first and last control points.
#[test]
fn a_bspline_reproduces_a_quadratic_and_pinned_meets_its_ends() {
    let curve = |n: usize, wrap: &str| {
        let pts: Vec<String> = (0..n).map(|i| format!("({i}, {}, 0)", i * i)).collect();
        usda(&format!(
            "    def BasisCurves \"C\"\n    {{\n        uniform token type = \"cubic\"\n        \
             uniform token basis = \"bspline\"\n        uniform token wrap = \"{wrap}\"\n        \
             int[] curveVertexCounts = [{n}]\n        point3f[] points = [{}]\n    }}",
            pts.join(", ")
        ))
    };
    let g = read(&curve(5, "nonperiodic")).unwrap();
    let samples = CUBIC_SAMPLES as f32;
    assert_eq!(g.counts, vec![2 * CUBIC_SAMPLES as u32 + 1]);
    for (k, p) in g.points.iter().enumerate() {
        let u = 1.0 + k as f32 / samples;
        let expected = Vec3::new(u, u * u + 1.0 / 3.0, 0.0);
        assert!(
            p.distance(expected) < 1e-4,
            "sample {k}: {p} against {expected}"
        );
    }
    assert_eq!(
        read(&curve(4, "nonperiodic")).unwrap().counts,
        vec![CUBIC_SAMPLES as u32 + 1]
    );
    assert!(read(&curve(3, "nonperiodic"))
        .unwrap_err()
        .contains("at least 4"));
    let g = read(&curve(5, "pinned")).unwrap();
    assert_eq!(g.counts, vec![4 * CUBIC_SAMPLES as u32 + 1]);
    assert!(g.points[0].distance(Vec3::ZERO) < 1e-5, "{}", g.points[0]);
    let last = *g.points.last().unwrap();
    assert!(last.distance(Vec3::new(4.0, 16.0, 0.0)) < 1e-4, "{last}");
}

/// A cubic prim's widths for its second curve, by each interpolation, worked out by
/// hand: two Bézier curves of one segment each; `vertex` widths (10, 10, 10, 10) and
/// (1, 2, 3, 4) give the second curve 1 + 3t (control values evenly spaced are
/// evaluated to a line); `varying` (5, 6) and (7, 9) at the segments' ends give 7 + 2t;
/// `uniform` (0.5, 0.25) gives 0.25.
#[test]
fn a_cubic_prims_widths_follow_each_interpolation_per_curve() {
    let prim = |widths: &str| {
        usda(&format!(
            "    def BasisCurves \"C\"\n    {{\n        uniform token type = \"cubic\"\n        \
             uniform token basis = \"bezier\"\n        int[] curveVertexCounts = [4, 4]\n        \
             point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0), (0, 3, 0), (1, 0, 0), \
             (1, 1, 0), (1, 2, 0), (1, 3, 0)]\n        {widths}\n    }}"
        ))
    };
    let second = |widths: &str| -> Vec<f32> {
        let g = read(&prim(widths)).unwrap_or_else(|e| panic!("{widths}: {e}"));
        let w = g.widths.unwrap();
        assert_eq!(w.len(), 2 * (CUBIC_SAMPLES + 1));
        w[CUBIC_SAMPLES + 1..].to_vec()
    };
    let t = |k: usize| k as f32 / CUBIC_SAMPLES as f32;
    let check = |got: Vec<f32>, f: &dyn Fn(f32) -> f32, what: &str| {
        for (k, w) in got.iter().enumerate() {
            assert!(
                (w - f(t(k))).abs() < 1e-5,
                "{what}, sample {k}: {w} against {}",
                f(t(k))
            );
        }
    };
    check(
        second("float[] widths = [10, 10, 10, 10, 1, 2, 3, 4] (interpolation = \"vertex\")"),
        &|t| 1.0 + 3.0 * t,
        "vertex",
    );
    check(
        second("float[] widths = [5, 6, 7, 9] (interpolation = \"varying\")"),
        &|t| 7.0 + 2.0 * t,
        "varying",
    );
    check(
        second("float[] widths = [0.5, 0.25] (interpolation = \"uniform\")"),
        &|_| 0.25,
        "uniform",
    );
    // Too few values: the error names how many the prim's curves need.
    for (widths, needs) in [
        (
            "float[] widths = [0.5] (interpolation = \"uniform\")",
            "has 1 value; 2 curves of 8 control points need exactly 2",
        ),
        (
            "float[] widths = [1, 2, 3, 4, 5, 6] (interpolation = \"vertex\")",
            "has 6 values; 2 curves of 8 control points need exactly 8",
        ),
        (
            "float[] widths = [1, 2, 3] (interpolation = \"varying\")",
            "has 3 values; 2 curves of 8 control points need exactly 4",
        ),
    ] {
        let err = read(&prim(widths)).unwrap_err();
        assert!(err.contains(needs), "{widths}: {err}");
    }
    // Linear curves of three points take three `varying` values each.
    let linear = usda(
        "    def BasisCurves \"C\"\n    {\n        uniform token type = \"linear\"\n        \
         int[] curveVertexCounts = [3, 3]\n        point3f[] points = [(0, 0, 0), (0, 1, 0), \
         (0, 2, 0), (1, 0, 0), (1, 1, 0), (1, 2, 0)]\n        \
         float[] widths = [1, 2, 3, 4, 5, 6] (interpolation = \"varying\")\n    }",
    );
    assert_eq!(
        read(&linear).unwrap().widths,
        Some(vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    );
}
