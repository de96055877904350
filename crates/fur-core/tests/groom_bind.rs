//! Guide curves on a body: roots bound to the nearest surface point, master hairs
//! blended from the nearest guides, the groomed region and its outside, the refusals.

use fur_core::groom_file::Guides;
use fur_core::scene::{
    closest_on_triangle, nearest_surface_point, resample, GroomParams, Mesh, Outside, Strands,
    BALD_FRACTION, BIND_LIMIT, BIND_TOLERANCE,
};
use glam::Vec3;
use proptest::prelude::*;

fn groom() -> GroomParams {
    GroomParams {
        segments: 8,
        segment_length: 0.05,
        curl: 0.4,
        ..Default::default()
    }
}

proptest! {
    /// No point of the triangle (a fine barycentric grid) is nearer than the one found.
    #[test]
    fn the_closest_point_on_a_triangle_is_the_closest(
        p in prop::array::uniform3(-2.0f32..2.0),
        t in prop::array::uniform9(-1.0f32..1.0),
    ) {
        let (a, b, c) = (Vec3::from_slice(&t[0..3]), Vec3::from_slice(&t[3..6]), Vec3::from_slice(&t[6..9]));
        prop_assume!((b - a).cross(c - a).length() > 1e-3);
        let p = Vec3::from(p);
        let w = closest_on_triangle(p, a, b, c);
        prop_assert!(w.min_element() >= -1e-6 && (w.element_sum() - 1.0).abs() < 1e-5);
        let found = (w.x * a + w.y * b + w.z * c).distance(p);
        let n = 40;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let q = a + u * (b - a) + v * (c - a);
                prop_assert!(found <= q.distance(p) + 1e-5, "{found} > {}", q.distance(p));
            }
        }
    }
}

#[test]
fn resampling_keeps_the_length_and_spaces_evenly() {
    let poly = [Vec3::ZERO, Vec3::X, Vec3::X + 3.0 * Vec3::Y];
    let r = resample(&poly, 8);
    assert_eq!(r.len(), 9);
    assert_eq!(r[0], poly[0]);
    assert!(r[8].distance(poly[2]) < 1e-6);
    for w in r.windows(2) {
        assert!((w[0].distance(w[1]) - 0.5).abs() < 1e-5);
    }
}

/// A guide with a repeated point (a zero-length segment, as files hold) resamples to
/// finite points along the same path.
#[test]
fn a_repeated_point_resamples_to_finite_points() {
    let poly = [Vec3::ZERO, Vec3::ZERO, Vec3::X, Vec3::X, 2.0 * Vec3::X];
    let r = resample(&poly, 4);
    for (k, p) in r.iter().enumerate() {
        assert!(p.is_finite(), "{r:?}");
        assert!(p.distance(0.5 * k as f32 * Vec3::X) < 1e-6, "{r:?}");
    }
}

/// The masters of a body, written out as guides and read back in, are the same hairs:
/// every root binds to its own vertex and takes its own guide alone.
#[test]
fn masters_taken_as_guides_give_the_same_masters() {
    let mesh = Mesh::icosphere(2);
    let grown = Strands::grow(&mesh, &groom()).unwrap();
    let guides = grown.to_guides(Some(0.001));
    let (back, report) = Strands::from_guides(&mesh, &guides, &groom(), Outside::Bald).unwrap();
    assert_eq!(report.groomed_vertices, mesh.vertex_count());
    assert_eq!(report.far_roots, 0);
    let length = grown.hair_length();
    let worst = grown
        .positions
        .iter()
        .zip(&back.positions)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(
        worst < 1e-5 * length,
        "off by {worst} of a hair {length} long"
    );
}

/// A groom on the upper half of a sphere: vertices there blend the guides (each hair
/// as long as the guides, pointing out of the body), vertices far below are bald stubs
/// or, by choice, grown hair.
#[test]
fn a_partial_groom_grooms_its_region_and_leaves_the_rest_bald_or_grown() {
    let mesh = Mesh::uv_sphere(1.0, 24, 48);
    let dense = Mesh::icosphere(3);
    // Straight guides 0.3 long along the normal, on the upper cap of a finer sphere.
    let mut guides = Guides::default();
    for (p, n) in dense.positions.iter().zip(&dense.normals) {
        if p.y > 0.3 {
            guides.counts.push(4);
            guides
                .points
                .extend((0..4).map(|k| *p + *n * 0.1 * k as f32));
        }
    }
    let (s, report) = Strands::from_guides(&mesh, &guides, &groom(), Outside::Bald).unwrap();
    assert!(report.groomed_vertices > 0 && report.groomed_vertices < mesh.vertex_count());
    let v = s.vertices_per_strand as usize;
    for (i, (p, n)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
        let hair = &s.positions[i * v..(i + 1) * v];
        let length: f32 = hair.windows(2).map(|w| w[0].distance(w[1])).sum();
        assert_eq!(hair[0], *p);
        if p.y > 0.45 {
            assert!(
                (length - 0.3).abs() < 0.01,
                "vertex {i} at {p}: length {length}"
            );
            let out = (hair[v - 1] - hair[0]).normalize().dot(n.normalize());
            assert!(
                out > 0.99,
                "vertex {i}: the hair leans {out} off the normal"
            );
        }
        if p.y < 0.0 {
            assert!(
                length <= BALD_FRACTION * 0.3 * 1.01,
                "vertex {i}: bald but {length} long"
            );
        }
    }
    let (grown, _) = Strands::from_guides(&mesh, &guides, &groom(), Outside::Grow).unwrap();
    let own = Strands::grow(&mesh, &groom()).unwrap();
    let low = mesh.positions.iter().position(|p| p.y < -0.9).unwrap();
    assert_eq!(grown.strand(low), own.strand(low));
}

/// One straight guide `length` long at each vertex of `mesh`, its root `lift` off the
/// surface along the vertex normal.
fn lifted_guides(mesh: &Mesh, lift: f32, length: f32) -> Guides {
    let mut g = Guides::default();
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        g.counts.push(2);
        g.points.extend([*p + *n * lift, *p + *n * (lift + length)]);
    }
    g
}

#[test]
fn roots_off_the_surface_are_reported_and_far_ones_refused() {
    let mesh = Mesh::icosphere(2);
    let (_, radius) = mesh.bounds();
    let guides = |lift: f32| lifted_guides(&mesh, lift * radius, 0.2);
    let (_, report) = Strands::from_guides(&mesh, &guides(0.0), &groom(), Outside::Bald).unwrap();
    assert_eq!(report.far_roots, 0);
    let lift = 2.0 * BIND_TOLERANCE;
    let (_, report) = Strands::from_guides(&mesh, &guides(lift), &groom(), Outside::Bald).unwrap();
    assert_eq!(report.far_roots, mesh.vertex_count());
    let warnings = report.warnings(radius);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let count = format!(
        "{} of {} guide roots",
        mesh.vertex_count(),
        mesh.vertex_count()
    );
    assert!(warnings[0].contains(&count), "{warnings:?}");
    // Roots on the surface: nothing to say.
    let (_, on) = Strands::from_guides(&mesh, &guides(0.0), &groom(), Outside::Bald).unwrap();
    assert!(on.warnings(radius).is_empty(), "{:?}", on.warnings(radius));
    let err = Strands::from_guides(&mesh, &guides(2.0 * BIND_LIMIT), &groom(), Outside::Bald)
        .unwrap_err();
    assert!(
        err.contains(&format!(
            "{} of {}",
            mesh.vertex_count(),
            mesh.vertex_count()
        )),
        "{err}"
    );
}

#[test]
fn a_root_binds_to_the_nearest_surface_point_with_its_normal() {
    let mesh = Mesh::grid(4, 4, 1.0);
    let p = Vec3::new(0.13, 0.2, -0.31);
    let s = nearest_surface_point(&mesh, p);
    assert!((s.distance - 0.2).abs() < 1e-6);
    assert!(s.point.distance(Vec3::new(0.13, 0.0, -0.31)) < 1e-6);
    assert!(s.normal.distance(Vec3::Y) < 1e-6);
}

/// Twelve straight guides around a sphere groom all of it: each blended hair is carried
/// into its own vertex's frame, so it stands straight along that vertex's normal
/// although the nearest guides' normals are up to ~40° away.
#[test]
fn sparse_straight_guides_make_every_hair_stand_along_its_own_normal() {
    let mesh = Mesh::uv_sphere(1.0, 16, 32);
    let guide_body = Mesh::icosphere(0);
    let mut guides = Guides::default();
    for (p, n) in guide_body.positions.iter().zip(&guide_body.normals) {
        guides.counts.push(3);
        guides
            .points
            .extend((0..3).map(|k| *p + *n * 0.15 * k as f32));
    }
    let (s, report) = Strands::from_guides(&mesh, &guides, &groom(), Outside::Bald).unwrap();
    assert_eq!(report.groomed_vertices, mesh.vertex_count());
    let mut worst: f32 = 1.0;
    for (i, n) in mesh.normals.iter().enumerate() {
        let hair = s.strand(i);
        let along = (hair[hair.len() - 1] - hair[0]) / 0.3;
        worst = worst.min(along.dot(n.normalize()));
    }
    assert!(worst > 0.9999, "a hair leans off its normal: cos {worst}");
}

/// The binding's limits are in bounding radii: on a body three times the unit sphere
/// (the limits in scene units then differ from the unit sphere's by more than the
/// tolerance does from the limit), roots lifted by twice the reporting tolerance are
/// reported and bound, and roots past the refusal limit are refused.
#[test]
fn the_binding_limits_scale_with_the_body() {
    let mut mesh = Mesh::icosphere(2);
    for p in &mut mesh.positions {
        *p *= 3.0;
    }
    let (_, radius) = mesh.bounds();
    // The bounding radius: half the box's diagonal, 3√3.
    assert!((radius - 3.0 * 3f32.sqrt()).abs() < 1e-3, "radius {radius}");
    let guides = |lift: f32| lifted_guides(&mesh, lift * radius, 0.5);
    let (_, report) = Strands::from_guides(
        &mesh,
        &guides(2.0 * BIND_TOLERANCE),
        &groom(),
        Outside::Bald,
    )
    .unwrap();
    assert_eq!(report.far_roots, mesh.vertex_count());
    let (_, near) = Strands::from_guides(
        &mesh,
        &guides(0.5 * BIND_TOLERANCE),
        &groom(),
        Outside::Bald,
    )
    .unwrap();
    assert_eq!(near.far_roots, 0);
    assert!(
        Strands::from_guides(&mesh, &guides(2.0 * BIND_LIMIT), &groom(), Outside::Bald).is_err()
    );
}

/// `--groom-outside`'s names read back as their choices, and another is refused.
#[test]
fn each_outside_choice_reads_back_from_its_name() {
    for outside in Outside::ALL {
        assert_eq!(outside.name().parse::<Outside>(), Ok(outside));
    }
    assert_ne!(Outside::Bald.name(), Outside::Grow.name());
    let err = "shaved".parse::<Outside>().unwrap_err();
    assert!(err.contains("`shaved`"), "{err}");
}

/// A vertex between guides of different shapes takes their shapes weighted by
/// 1 / d² (d: the vertex's distance to each guide's root): on a flat grid, straight
/// guides 0.2 and 0.4 long at 0.5 and 1.5 from a vertex give it a hair
/// (0.2 · 4 + 0.4 / 2.25) / (4 + 1 / 2.25) = 0.22 long; a guide past the groomed
/// region does not count in the blend. A vertex beyond the groomed
/// region (twice the roots' spacing) is bald: a stub along its normal, outwards.
#[test]
fn a_vertex_blends_its_guides_by_inverse_square_distance() {
    let mesh = Mesh::grid(16, 16, 8.0);
    let at = |x: f32, z: f32| {
        mesh.positions
            .iter()
            .position(|p| p.distance(Vec3::new(x, 0.0, z)) < 1e-4)
            .unwrap()
    };
    let (a, b, v, far) = (at(-0.5, 0.0), at(0.5, 0.0), at(-1.0, 0.0), at(4.0, 4.0));
    let mut guides = Guides::default();
    for (root, length) in [(a, 0.2), (b, 0.4)] {
        let n = mesh.normals[root].normalize();
        guides.counts.push(2);
        guides
            .points
            .extend([mesh.positions[root], mesh.positions[root] + n * length]);
    }
    let (strands, report) = Strands::from_guides(&mesh, &guides, &groom(), Outside::Bald).unwrap();
    assert!(report.groomed_vertices < mesh.vertex_count());
    let hair = strands.strand(v);
    let n = mesh.normals[v].normalize();
    let length = (hair[hair.len() - 1] - hair[0]).dot(n);
    let expected = (0.2 * 4.0 + 0.4 / 2.25) / (4.0 + 1.0 / 2.25);
    assert!(
        (length - expected).abs() < 1e-4,
        "{length} against {expected}"
    );
    // At 1.5 and 2.5 from the roots the second guide is past the region (2): the
    // vertex takes the first guide alone.
    let alone = strands.strand(at(-2.0, 0.0));
    let length = (alone[alone.len() - 1] - alone[0]).dot(n);
    assert!(
        (length - 0.2).abs() < 1e-4,
        "{length} against the first guide's 0.2"
    );
    let stub = strands.strand(far);
    let n = mesh.normals[far].normalize();
    assert!((stub[stub.len() - 1] - stub[0]).dot(n) > 0.0, "{stub:?}");
}

/// The groomed region is twice the roots' median spacing, the median of uneven
/// spacings: roots at x = −4, −3.5, −2 and 0 on a flat grid are 0.5, 0.5, 1.5 and 2
/// from their nearest, so the median is 1.5 and the region 3 (the smallest spacing would
/// give 1). A vertex 2.5 from the last root takes the guides' length; one 3.5 from it is
/// bald.
#[test]
fn the_groomed_region_is_twice_the_median_spacing_of_uneven_roots() {
    let mesh = Mesh::grid(16, 16, 8.0);
    let at = |x: f32| {
        mesh.positions
            .iter()
            .position(|p| p.distance(Vec3::new(x, 0.0, 0.0)) < 1e-4)
            .unwrap()
    };
    let mut guides = Guides::default();
    for x in [-4.0, -3.5, -2.0, 0.0] {
        let root = at(x);
        let n = mesh.normals[root].normalize();
        guides.counts.push(2);
        guides
            .points
            .extend([mesh.positions[root], mesh.positions[root] + n * 0.3]);
    }
    let (strands, _) = Strands::from_guides(&mesh, &guides, &groom(), Outside::Bald).unwrap();
    let length = |x: f32| {
        let hair = strands.strand(at(x));
        (hair[hair.len() - 1] - hair[0]).length()
    };
    assert!((length(2.5) - 0.3).abs() < 1e-4, "{} at 2.5", length(2.5));
    assert!(length(3.5) < 0.1, "{} at 3.5: not bald", length(3.5));
}
