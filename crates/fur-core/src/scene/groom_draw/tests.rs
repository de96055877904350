use super::*;

/// `n` curved guides of 5 points, rooted a little off the sphere (radius 1) at
/// scattered directions, as a groom file would give them.
fn guides(n: usize, lift: f32) -> Guides {
    let mut points = Vec::new();
    for g in 0..n {
        let t = g as f32 * 2.399;
        let z = 1.0 - 2.0 * (g as f32 + 0.5) / n as f32;
        let r = (1.0 - z * z).sqrt();
        let d = Vec3::new(r * t.cos(), z, r * t.sin());
        let side = d.any_orthonormal_vector();
        for k in 0..5 {
            let s = k as f32 * 0.05;
            points.push(d * (1.0 + lift + s) + side * (s * s));
        }
    }
    Guides {
        counts: vec![5; n],
        points,
        widths: None,
        colors: None,
        notes: Vec::new(),
    }
}

fn groom(segments: u32) -> GroomParams {
    GroomParams {
        segments,
        ..Default::default()
    }
}

// Each guide is one master hair of its own: rooted on the surface where it binds, its
// shape the guide's, resampled; the body keeps its triangles and its own vertices.
#[test]
fn each_guide_is_a_master_hair_rooted_on_the_surface() {
    let body = Mesh::icosphere(3);
    let g = guides(40, 0.01);
    let drawn = DrawnGroom::new(body.clone(), None, &g, &groom(4), Outside::Bald).unwrap();
    let n = body.vertex_count();
    assert_eq!(drawn.body_vertices, n);
    assert_eq!(drawn.mesh.vertex_count(), n + 40);
    assert_eq!(
        drawn.mesh.indices, body.indices,
        "the body's surface is unchanged"
    );
    assert_eq!(drawn.strands.count(), n + 40);
    assert_eq!(drawn.patches.count(), 40);
    assert_eq!(
        drawn.patches.masks,
        vec![1; 40],
        "a patch owns its first corner only"
    );
    for (i, curve) in g.curves().enumerate() {
        let v = n + i;
        assert_eq!(drawn.patches.indices[3 * i..3 * i + 3], [v as u32; 3]);
        let hair = drawn.strands.strand(v);
        let root = drawn.mesh.positions[v];
        assert_eq!(hair[0], root);
        // On the sphere's surface (its flat facets lie within 1.3 % of radius 1).
        assert!((root.length() - 1.0).abs() < 0.013, "root {root}");
        let expected = resample(curve, 4);
        for (p, q) in hair.iter().zip(&expected) {
            let moved = *p - root - (*q - expected[0]);
            assert!(moved.length() < 1e-6, "guide {i}: {p} against {q}");
        }
    }
    // The body's own vertices are bald stubs.
    let longest_stub = (0..n)
        .map(|i| drawn.strands.strand(i)[4].distance(drawn.strands.strand(i)[0]))
        .fold(0.0, f32::max);
    assert!(longest_stub < 1e-3 * 0.25, "stub of {longest_stub}");
    assert_eq!(drawn.guide_strands().count(), 40);
    assert_eq!(drawn.guide_strands().strand(3), drawn.strands.strand(n + 3));
}

// Outside the guides the body takes the grown hair when asked.
#[test]
fn the_body_can_keep_its_grown_hair() {
    let body = Mesh::icosphere(2);
    let drawn = DrawnGroom::new(
        body.clone(),
        None,
        &guides(8, 0.0),
        &groom(4),
        Outside::Grow,
    )
    .unwrap();
    let grown = Strands::grow(&body, &groom(4)).unwrap();
    let v = grown.positions.len();
    assert_eq!(drawn.strands.positions[..v], grown.positions[..]);
}

// A guide too far from the body refuses the groom, as in blend mode.
#[test]
fn a_groom_for_another_body_is_refused() {
    let err = DrawnGroom::new(
        Mesh::icosphere(2),
        None,
        &guides(8, 0.5),
        &groom(4),
        Outside::Bald,
    )
    .err()
    .unwrap();
    assert!(err.contains("guide roots lie farther"), "{err}");
}

// A guide's root on a textured body takes the blend of its triangle's corner UVs.
#[test]
fn a_guide_takes_its_triangles_texture_coordinates() {
    let mut body = Mesh::icosphere(2);
    body.uvs = body
        .indices
        .iter()
        .map(|&i| {
            let p = body.positions[i as usize];
            Vec2::new(p.x * 0.5 + 0.5, p.y * 0.5 + 0.5)
        })
        .collect();
    let drawn = DrawnGroom::new(body, None, &guides(10, 0.0), &groom(4), Outside::Bald).unwrap();
    assert_eq!(drawn.patches.uvs.len(), 30);
    for (i, uv) in drawn.patches.uvs.chunks_exact(3).enumerate() {
        let root = drawn.mesh.positions[drawn.body_vertices + i];
        // The UVs are linear in position, so the blend is the root's own.
        let own = Vec2::new(root.x * 0.5 + 0.5, root.y * 0.5 + 0.5);
        assert!(
            uv.iter().all(|u| u.distance(own) < 1e-5),
            "{uv:?} against {own}"
        );
    }
}

// On a skinned body a guide's root skins with its triangle's corners' weights blended:
// at most four joints, summing to one, and its bind position the same blend.
#[test]
fn a_guide_root_skins_with_its_triangles_blended_weights() {
    let (body, rig) = crate::scene::critter();
    // Guides rooted at triangle centres, so three corners' skins blend.
    let mut points = Vec::new();
    let triangles: Vec<usize> = (0..body.triangle_count()).step_by(97).collect();
    for &t in &triangles {
        let c = [0, 1, 2].map(|k| body.indices[3 * t + k] as usize);
        let centre = c.iter().map(|&i| body.positions[i]).sum::<Vec3>() / 3.0;
        let n = c.iter().map(|&i| body.normals[i]).sum::<Vec3>().normalize();
        points.extend([centre, centre + n * 0.05]);
    }
    let g = Guides {
        counts: vec![2; triangles.len()],
        points,
        widths: None,
        colors: None,
        notes: Vec::new(),
    };
    let drawn = DrawnGroom::new(
        body.clone(),
        Some(rig.clone()),
        &g,
        &groom(2),
        Outside::Bald,
    )
    .unwrap();
    let skin = drawn.rig.unwrap();
    let n = body.vertex_count();
    skin.validate(drawn.mesh.vertex_count()).unwrap();
    let mut blended = 0;
    for (i, &t) in triangles.iter().enumerate() {
        let v = n + i;
        let c = [0, 1, 2].map(|k| body.indices[3 * t + k] as usize);
        let w = skin.weights[v];
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{w:?}");
        // Each joint's weight is its share of the corners' (a third each at the
        // centre) among the four heaviest.
        let share = |j: u16| -> f32 {
            c.iter()
                .map(|&k| {
                    (0..4)
                        .filter(|&s| rig.influences[k][s] == j)
                        .map(|s| rig.weights[k][s] / 3.0)
                        .sum::<f32>()
                })
                .sum()
        };
        let kept: f32 = (0..4)
            .filter(|&s| w[s] > 0.0)
            .map(|s| share(skin.influences[v][s]))
            .sum();
        for s in (0..4).filter(|&s| w[s] > 0.0) {
            let expected = share(skin.influences[v][s]) / kept;
            assert!((w[s] - expected).abs() < 1e-4, "vertex {v}: {w:?}");
        }
        if c.iter().any(|&k| rig.influences[k] != rig.influences[c[0]]) {
            blended += 1;
        }
        let bind = c.iter().map(|&k| rig.bind_positions[k]).sum::<Vec3>() / 3.0;
        assert!(skin.bind_positions[v].distance(bind) < 1e-4);
    }
    assert!(
        blended > 0,
        "no guide sat between differently skinned corners"
    );
    // A new session of the same body starts from the body's own rig.
    let own = skin.body_only(n);
    own.validate(n).unwrap();
    assert_eq!(own.weights, rig.weights);
    assert_eq!(own.bind_positions, rig.bind_positions);
}

// Worked by hand: corners skinned to joints (1, 2, 3, 4 at .4, .3, .2, .1), (5, 6 at
// .5 each) and (1 alone), blended at (.5, .3, .2): joint 1 weighs .2 + .2 = .4, joints
// 2, 5 and 6 .15 each, 3 .1 and 4 .05; the four heaviest (ties by joint) keep .85 in
// all, so their weights are .4 / .85 and .15 / .85.
#[test]
fn a_blended_skin_keeps_the_four_heaviest_joints_renormalised() {
    let (_, mut rig) = crate::scene::critter();
    rig.influences[0] = [1, 2, 3, 4];
    rig.weights[0] = [0.4, 0.3, 0.2, 0.1];
    rig.influences[1] = [5, 6, 0, 0];
    rig.weights[1] = [0.5, 0.5, 0.0, 0.0];
    rig.influences[2] = [1, 0, 0, 0];
    rig.weights[2] = [1.0, 0.0, 0.0, 0.0];
    let n = rig.weights.len();
    let b = Vec3::new(0.5, 0.3, 0.2);
    blend_skin(&mut rig, [0, 1, 2], b);
    assert_eq!(rig.influences[n], [1, 2, 5, 6]);
    let expected = [0.4 / 0.85, 0.15 / 0.85, 0.15 / 0.85, 0.15 / 0.85];
    for (w, e) in rig.weights[n].iter().zip(expected) {
        assert!((w - e).abs() < 1e-6, "{:?}", rig.weights[n]);
    }
    let bind =
        0.5 * rig.bind_positions[0] + 0.3 * rig.bind_positions[1] + 0.2 * rig.bind_positions[2];
    assert!(rig.bind_positions[n].distance(bind) < 1e-6);
}

// What the user is told: the file's notes, and the roots bound from farther than the
// tolerance with the farthest in bounding radii; nothing for a groom that fits.
#[test]
fn a_drawn_groom_warns_of_its_notes_and_far_roots() {
    let fits = DrawnGroom::new(
        Mesh::icosphere(2),
        None,
        &guides(8, 0.0),
        &groom(4),
        Outside::Bald,
    )
    .unwrap();
    assert_eq!(fits.warnings(), Vec::<String>::new());
    let mut lifted = guides(8, 0.05);
    lifted.notes.push("a note from the file".into());
    let far = DrawnGroom::new(Mesh::icosphere(2), None, &lifted, &groom(4), Outside::Bald).unwrap();
    let warnings = far.warnings();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert_eq!(warnings[0], "a note from the file");
    assert!(
        warnings[1].starts_with("8 of 8 guide roots lie farther than 0.02 bounding radii")
            && warnings[1].contains("(the farthest 0.0"),
        "{warnings:?}"
    );
}
