use super::*;

#[test]
fn strands_have_the_requested_segment_length_and_start_at_the_root() {
    let mesh = Mesh::icosphere(1);
    let groom = GroomParams {
        curl: 0.5,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    assert_eq!(strands.count(), mesh.vertex_count());
    for s in 0..strands.count() {
        let strand = strands.strand(s);
        assert_eq!(strand[0], mesh.positions[s]);
        for w in strand.windows(2) {
            assert!(((w[1] - w[0]).length() - groom.segment_length).abs() < 1e-5);
        }
        // Hairs grow outwards.
        assert!((strand[1] - strand[0]).dot(mesh.normals[s]) > 0.0);
    }
}

#[test]
fn bad_groom_is_rejected() {
    let mesh = Mesh::icosphere(0);
    for groom in [
        GroomParams {
            segments: 0,
            ..Default::default()
        },
        GroomParams {
            segments: 64,
            ..Default::default()
        },
        GroomParams {
            segment_length: -1.0,
            ..Default::default()
        },
        GroomParams {
            segment_length: f32::NAN,
            ..Default::default()
        },
    ] {
        assert!(matches!(
            Strands::grow(&mesh, &groom),
            Err(Error::Parameter(_))
        ));
    }
}

/// A mesh of lone vertices (no triangles): `(position, normal)` each.
fn lone_vertices(vertices: &[(Vec3, Vec3)]) -> Mesh {
    Mesh {
        positions: vertices.iter().map(|v| v.0).collect(),
        normals: vertices.iter().map(|v| v.1).collect(),
        indices: Vec::new(),
        uvs: Vec::new(),
        texture: None,
    }
}

/// Checks strand `s` against the polyline from its root whose segment `k` has length
/// `length` along `direction(k)` (normalised here).
fn assert_strand(
    strands: &Strands,
    s: usize,
    length: f32,
    direction: impl Fn(usize) -> Vec3,
    what: &str,
) {
    let strand = strands.strand(s);
    for k in 0..strand.len() - 1 {
        let want = strand[k] + direction(k).normalize() * length;
        assert!(
            (strand[k + 1] - want).length() < 1e-6,
            "{what}: strand {s}, vertex {}: {}, not {want}",
            k + 1,
            strand[k + 1]
        );
    }
}

/// Where the surface is perpendicular to the comb, segment k of S leans towards the
/// comb by tan⁻¹(strength × |comb| × (k + ½) / S): the tip leans most, and the comb
/// direction's length scales the strength.
#[test]
fn hair_leans_towards_the_comb_more_towards_the_tip() {
    let mesh = lone_vertices(&[(Vec3::new(0.5, -0.25, 2.0), Vec3::Z)]);
    for (comb_direction, comb_strength) in [(Vec3::X, 0.8), (Vec3::X * 2.0, 0.4)] {
        let groom = GroomParams {
            segments: 4,
            segment_length: 0.1,
            comb_direction,
            comb_strength,
            flow: crate::scene::Flow::Direction,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        assert_eq!(strands.strand(0)[0], mesh.positions[0]);
        assert_strand(
            &strands,
            0,
            0.1,
            |k| Vec3::new(0.8 * (k as f32 + 0.5) / 4.0, 0.0, 1.0),
            "perpendicular comb",
        );
    }
}

/// Where the surface faces along the comb (its projection vanishes), the hair leans
/// across it instead, towards the model's back: for the comb (0, −1, −1) that is
/// (0, 1, −1)/√2, the direction perpendicular to the comb with the most −z, by the
/// comb's full length (√2).
#[test]
fn hair_on_a_surface_facing_along_the_comb_leans_towards_the_back() {
    let comb = Vec3::new(0.0, -1.0, -1.0);
    let mesh = lone_vertices(&[(Vec3::ZERO, comb.normalize())]);
    let groom = GroomParams {
        segments: 3,
        segment_length: 0.2,
        comb_direction: comb,
        comb_strength: 0.5,
        flow: crate::scene::Flow::Direction,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    assert_strand(
        &strands,
        0,
        0.2,
        |k| comb.normalize() + 0.5 * (k as f32 + 0.5) / 3.0 * Vec3::new(0.0, 1.0, -1.0),
        "facing along the comb",
    );
}

/// Between the two cases the comb blends: with the comb (3, 0, 4) over a surface
/// facing +z, the comb's unit direction (0.6, 0, 0.8) has the tangential part
/// (0.6, 0, 0), of length 0.6; the direction across it closest to −z is
/// (0.8, 0, −0.6), tangential part (0.8, 0, 0), weighted by 1 − 0.6; both times the
/// comb's length 5: (0.6 + 0.4 × 0.8) × 5 = 4.6 along x.
#[test]
fn a_comb_at_an_angle_to_the_surface_blends_in_the_across_direction() {
    let mesh = lone_vertices(&[(Vec3::ZERO, Vec3::Z)]);
    let groom = GroomParams {
        segments: 2,
        segment_length: 0.1,
        comb_direction: Vec3::new(3.0, 0.0, 4.0),
        comb_strength: 0.1,
        flow: crate::scene::Flow::Direction,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    assert_strand(
        &strands,
        0,
        0.1,
        |k| Vec3::new(0.1 * (k as f32 + 0.5) / 2.0 * 4.6, 0.0, 1.0),
        "comb at an angle",
    );
}

/// A per-vertex comb field replaces the comb direction there (its length ignored,
/// the comb direction's length kept); a zero entry falls back to the comb direction;
/// a field of the wrong size is refused.
#[test]
fn a_comb_field_replaces_the_comb_direction_per_vertex() {
    let mesh = lone_vertices(&[(Vec3::ZERO, Vec3::Z), (Vec3::X, Vec3::Z)]);
    let groom = GroomParams {
        segments: 2,
        segment_length: 0.1,
        comb_direction: Vec3::Y * 2.0,
        comb_field: Some(crate::scene::BoneFlow {
            directions: vec![Vec3::X * 5.0, Vec3::ZERO],
            one_bone: vec![1.0; 2],
        }),
        comb_strength: 0.5,
        flow: crate::scene::Flow::Body,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let lean = |k: usize| 0.5 * 2.0 * (k as f32 + 0.5) / 2.0;
    assert_strand(&strands, 0, 0.1, |k| Vec3::new(lean(k), 0.0, 1.0), "field");
    assert_strand(
        &strands,
        1,
        0.1,
        |k| Vec3::new(0.0, lean(k), 1.0),
        "fallback",
    );
    for (directions, weights) in [(1, 2), (2, 1)] {
        let short = GroomParams {
            comb_field: Some(crate::scene::BoneFlow {
                directions: vec![Vec3::X; directions],
                one_bone: vec![1.0; weights],
            }),
            ..groom.clone()
        };
        assert!(matches!(
            Strands::grow(&mesh, &short),
            Err(Error::Parameter(_))
        ));
    }
}

/// With a curl c and no comb, every segment leans by tan⁻¹(c) from the normal, and
/// its lean turns about the normal (counter-clockwise seen from outside, for the
/// normal +z from +x to +y) by `curl_turns` full turns over the strand, starting from
/// the strand's own phase 2π × hash_unit(vertex): segment k of S at the angle
/// 2π (hash + turns (k + ½) / S).
#[test]
fn curl_turns_each_segment_about_the_normal() {
    let mesh = lone_vertices(&[(Vec3::ZERO, Vec3::Z), (Vec3::ONE, Vec3::Z)]);
    let groom = GroomParams {
        segments: 6,
        segment_length: 0.1,
        comb_strength: 0.0,
        curl: 0.5,
        curl_turns: 1.5,
        flow: crate::scene::Flow::Direction,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    for s in 0..2 {
        let angle =
            |k: usize| std::f32::consts::TAU * (hash_unit(s as u32) + 1.5 * (k as f32 + 0.5) / 6.0);
        assert_strand(
            &strands,
            s,
            0.1,
            |k| Vec3::new(0.5 * angle(k).cos(), 0.5 * angle(k).sin(), 1.0),
            "curl",
        );
    }
    // The two strands' phases differ.
    assert!((strands.strand(0)[1] - strands.strand(1)[1] + Vec3::ONE).length() > 1e-3);
}

/// With a thickness limit, each hair is at most the limit times the body's local
/// half-thickness long (a unit sphere's is about 1), in equal segments; a limit
/// above the full length leaves every hair `segments × segment_length` long.
#[test]
fn the_thickness_limit_shortens_hairs_on_thin_parts() {
    let mesh = Mesh::icosphere(2);
    let half = mesh.half_thickness().unwrap();
    assert!(half.iter().all(|h| (h - 1.0).abs() < 0.1), "{half:?}");
    for (limit, full) in [(0.05, false), (1.0, true)] {
        let groom = GroomParams {
            segments: 8,
            segment_length: 0.016,
            thickness_limit: limit,
            ..Default::default()
        };
        let strands = Strands::grow(&mesh, &groom).unwrap();
        for (s, h) in half.iter().enumerate() {
            let want = if full { 0.128 } else { limit * h };
            for w in strands.strand(s).windows(2) {
                let segment = (w[1] - w[0]).length();
                // Within 0.1 %: the grower measures the thickness from its own
                // f32 sums (measured up to 3.3e-4 off); a wrong limit or unequal
                // segments are off by far more.
                assert!(
                    (segment / (want / 8.0) - 1.0).abs() < 1e-3,
                    "limit {limit}, strand {s}: segment {segment}, hair should be {want}"
                );
            }
        }
    }
}

/// `segments + 1` vertices per strand; `count`, `strand` and `hair_length` (the
/// longest polyline) of strands written by hand.
#[test]
fn strands_are_counted_sliced_and_measured() {
    assert_eq!(
        GroomParams {
            segments: 5,
            ..Default::default()
        }
        .vertices_per_strand(),
        6
    );
    let strands = Strands {
        vertices_per_strand: 3,
        positions: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::ONE,
            Vec3::new(1.0, 1.0, 4.0),
            Vec3::new(1.0, 1.0, 4.0),
        ],
    };
    assert_eq!(strands.count(), 2);
    assert_eq!(strands.strand(0), &strands.positions[..3]);
    assert_eq!(strands.strand(1), &strands.positions[3..]);
    assert_eq!(strands.hair_length(), 3.0);
    let grown = Strands::grow(
        &Mesh::icosphere(0),
        &GroomParams {
            segments: 5,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(grown.vertices_per_strand, 6);
    assert_eq!(grown.positions.len(), 6 * Mesh::icosphere(0).vertex_count());
}

/// Every groom number out of its range is refused (zero length, negative, NaN or
/// infinite), the ends of the ranges are accepted.
#[test]
fn groom_numbers_are_checked_at_their_ends() {
    let ok = GroomParams::default();
    let zero = GroomParams {
        comb_strength: 0.0,
        curl: 0.0,
        curl_turns: 0.0,
        thickness_limit: 0.0,
        segments: 63,
        ..ok.clone()
    };
    zero.validate().unwrap();
    GroomParams {
        segments: 1,
        ..ok.clone()
    }
    .validate()
    .unwrap();
    let mut bad = vec![GroomParams {
        segment_length: 0.0,
        ..ok.clone()
    }];
    for v in [-1.0, f32::NAN, f32::INFINITY] {
        bad.push(GroomParams {
            comb_strength: v,
            ..ok.clone()
        });
        bad.push(GroomParams {
            curl: v,
            ..ok.clone()
        });
        bad.push(GroomParams {
            curl_turns: v,
            ..ok.clone()
        });
        bad.push(GroomParams {
            thickness_limit: v,
            ..ok.clone()
        });
    }
    for v in [f32::NAN, f32::INFINITY] {
        bad.push(GroomParams {
            comb_direction: Vec3::new(0.0, v, 0.0),
            ..ok.clone()
        });
        bad.push(GroomParams {
            segment_length: v,
            ..ok.clone()
        });
    }
    for groom in bad {
        assert!(
            matches!(groom.validate(), Err(Error::Parameter(_))),
            "{groom:?} accepted"
        );
    }
}

/// `hash_unit` spreads consecutive integers evenly over [0, 1): 16 buckets each get
/// their share of 2¹⁴ values within 15 % (5 standard deviations), neighbours are
/// uncorrelated (the mean product of consecutive values is ¼ within 0.01), and
/// values repeat no more often than random ones would.
#[test]
fn hash_unit_spreads_evenly_over_the_unit_interval() {
    let n = 1u32 << 14;
    let values: Vec<f32> = (0..n).map(hash_unit).collect();
    assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
    let mut buckets = [0u32; 16];
    for v in &values {
        buckets[(v * 16.0) as usize] += 1;
    }
    let share = n as f32 / 16.0;
    for (b, count) in buckets.iter().enumerate() {
        assert!(
            (*count as f32 - share).abs() < 0.15 * share,
            "bucket {b}: {count} of {n}"
        );
    }
    let product = values.windows(2).map(|w| w[0] * w[1]).sum::<f32>() / (n - 1) as f32;
    assert!((product - 0.25).abs() < 0.01, "{product}");
    // Values are 24-bit fractions: 2¹⁴ random ones share one about 2²⁸ / 2²⁵ = 8
    // times; a hash that loses input bits shares thousands.
    let mut sorted = values.clone();
    sorted.sort_by(f32::total_cmp);
    let shared = sorted.windows(2).filter(|w| w[0] == w[1]).count();
    assert!(shared < 64, "{shared} values shared");
}

/// Only a groom file in draw mode is drawn guide by guide: grown fur and a blended
/// groom are not.
#[test]
fn only_a_groom_in_draw_mode_is_drawn_as_it_is() {
    let source = |mode| super::super::GroomSource {
        path: "guides.usda".into(),
        outside: super::super::Outside::Bald,
        mode,
    };
    let with = |source| GroomParams {
        source,
        ..GroomParams::default()
    };
    assert_eq!(with(None).drawn_source(), None);
    assert_eq!(
        with(Some(source(super::super::GroomMode::Blend))).drawn_source(),
        None
    );
    let draw = source(super::super::GroomMode::Draw);
    assert_eq!(with(Some(draw.clone())).drawn_source(), Some(&draw));
}

/// The coat's height: hairs standing straight up stand their full length; combed ones,
/// which lean over, less; hand-placed strands average exactly.
#[test]
fn the_coat_height_is_how_far_the_tips_stand_off_the_skin() {
    let plane = Mesh::grid(4, 4, 1.0);
    let standing = GroomParams {
        segments: 5,
        segment_length: 0.1,
        comb_strength: 0.0,
        ..Default::default()
    };
    let height = Strands::grow(&plane, &standing).unwrap().coat_height();
    assert!((height - 0.5).abs() < 1e-5, "standing hairs: {height}");
    let combed = GroomParams {
        comb_strength: 4.0,
        ..standing
    };
    let lower = Strands::grow(&plane, &combed).unwrap().coat_height();
    assert!(lower < 0.45 && lower > 0.0, "combed hairs: {lower}");
    // One strand up 1 along its first segment, one leaning back below the skin (0).
    let strands = Strands {
        vertices_per_strand: 3,
        positions: vec![
            Vec3::ZERO,
            Vec3::Y,
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(-2.0, 0.0, 0.0),
        ],
    };
    assert!((strands.coat_height() - 0.5).abs() < 1e-6);
}
