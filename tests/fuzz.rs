//! Property-based fuzzing of the parsers that read user input: the OBJ loader and the
//! viewer's script parser. Fixed seeds and case counts keep CI deterministic and under
//! a minute; `FUR_FUZZ_CASES=200000 cargo test --release --test fuzz` runs longer. No
//! input may panic, and whatever parses must be usable.

use fur::viewer::Script;
use fur_core::scene::Mesh;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

fn runner(default_cases: u32) -> TestRunner {
    let cases = std::env::var("FUR_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default_cases);
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]))
}

/// Numbers as OBJ files write them, and as they should not.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        40 => (-5.0f32..5.0).prop_map(|v| v.to_string()),
        1 => Just("nan".to_string()),
        1 => Just("inf".to_string()),
        1 => Just("-inf".to_string()),
        1 => Just("1e38".to_string()),
        1 => Just("1e-45".to_string()),
        1 => Just("".to_string()),
        1 => "[a-z]{1,3}",
    ]
}

/// A face index: in range, negative (relative), zero, huge, or with texture and
/// normal parts.
fn index() -> impl Strategy<Value = String> {
    prop_oneof![
        20 => (1i64..8).prop_map(|i| i.to_string()),
        3 => (-8i64..0).prop_map(|i| i.to_string()),
        1 => Just("0".to_string()),
        1 => Just("4294967296".to_string()),
        2 => (1i64..8, 1i64..4).prop_map(|(v, n)| format!("{v}//{n}")),
        2 => (1i64..8, 1i64..4, 1i64..4).prop_map(|(v, t, n)| format!("{v}/{t}/{n}")),
    ]
}

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (number(), number(), number()).prop_map(|(x, y, z)| format!("v {x} {y} {z}")),
        1 => (number(), number(), number()).prop_map(|(x, y, z)| format!("vn {x} {y} {z}")),
        1 => (number(), number()).prop_map(|(u, v)| format!("vt {u} {v}")),
        4 => prop::collection::vec(index(), 0..6).prop_map(|ids| format!("f {}", ids.join(" "))),
        1 => prop::collection::vec(index(), 0..4).prop_map(|ids| format!("l {}", ids.join(" "))),
        1 => "[ -~]{0,20}".prop_map(|t| format!("# {t}")),
        1 => "(o|g|s|usemtl|mtllib) [a-z]{0,8}",
        1 => "[ -~]{0,30}",
    ]
}

/// An OBJ file: a few good vertices, then faces over them mixed with any other lines
/// (broken numbers, bad indices, comments, groups, garbage). Some vertices repeat or lie
/// on one line (0, 1 and 2 along the diagonal), so faces of zero area with three
/// distinct indices come up too.
fn obj_file() -> impl Strategy<Value = String> {
    let vertex = prop_oneof![
        6 => (-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0)
            .prop_map(|(x, y, z)| format!("v {x} {y} {z}")),
        1 => Just("v 0 0 0".to_string()),
        1 => Just("v 1 1 1".to_string()),
        1 => Just("v 2 2 2".to_string()),
    ];
    let face = prop::collection::vec(1u32..6, 3..6).prop_map(|ids| {
        format!(
            "f {}",
            ids.iter().map(u32::to_string).collect::<Vec<_>>().join(" ")
        )
    });
    let body = prop::collection::vec(prop_oneof![6 => face, 1 => line()], 1..20);
    (prop::collection::vec(vertex, 5..8), body)
        .prop_map(|(vertices, body)| format!("{}\n{}\n", vertices.join("\n"), body.join("\n")))
}

/// Whatever loads is a usable mesh: indices in range, finite positions, unit normals,
/// no degenerate triangles.
fn check_mesh(mesh: &Mesh) -> Result<(), TestCaseError> {
    prop_assert!(!mesh.indices.is_empty() && mesh.indices.len() % 3 == 0);
    prop_assert_eq!(mesh.positions.len(), mesh.normals.len());
    prop_assert!(mesh
        .indices
        .iter()
        .all(|&i| (i as usize) < mesh.positions.len()));
    prop_assert!(mesh.positions.iter().all(|p| p.is_finite()));
    prop_assert!(mesh
        .normals
        .iter()
        .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-3));
    for t in mesh.indices.chunks_exact(3) {
        prop_assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
        // Distinct indices are not enough: the triangle must have an area.
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
        prop_assert!(
            (b - a).cross(c - a).length_squared() > 0.0,
            "zero-area triangle {:?}: {} {} {}",
            t,
            a,
            b,
            c
        );
    }
    Ok(())
}

/// The usable-mesh check rejects a triangle of three distinct vertices on one line, and
/// the loader drops such a face (and one naming a vertex twice) and keeps the rest.
#[test]
fn zero_area_faces_are_dropped_and_would_be_caught() {
    let collinear = Mesh {
        positions: vec![glam::Vec3::ZERO, glam::Vec3::ONE, glam::Vec3::splat(2.0)],
        normals: vec![glam::Vec3::Y; 3],
        indices: vec![0, 1, 2],
        uvs: Vec::new(),
        texture: None,
    };
    assert!(check_mesh(&collinear).is_err());
    let mesh = Mesh::parse_obj(b"v 0 0 0\nv 1 1 1\nv 2 2 2\nv 0 1 0\nf 1 2 3\nf 1 1 4\nf 1 2 4\n")
        .unwrap();
    assert_eq!(mesh.triangle_count(), 1);
    check_mesh(&mesh).unwrap();
}

#[test]
fn obj_text_never_panics_the_loader() {
    let parsed = std::cell::Cell::new(0u32);
    let mut runner = runner(3000);
    let cases = runner.config().cases;
    runner
        .run(&obj_file(), |text| {
            if let Ok(mesh) = Mesh::parse_obj(text.as_bytes()) {
                check_mesh(&mesh)?;
                parsed.set(parsed.get() + 1);
            }
            Ok(())
        })
        .unwrap();
    // The generator reaches the loader's success path too, not only its errors.
    assert!(
        parsed.get() * 20 > cases,
        "only {} of {cases} generated files loaded",
        parsed.get()
    );
}

#[test]
fn degenerate_file_normals_fall_back_to_face_normals() {
    for vn in ["nan 0 0", "0 0 0", "inf 1 0"] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn {vn}\nf 1//1 2//1 3//1\n");
        let mesh = Mesh::parse_obj(text.as_bytes()).unwrap();
        check_mesh(&mesh).unwrap();
        assert!(
            mesh.normals.iter().all(|n| n.z > 0.99),
            "vn {vn}: {:?}",
            mesh.normals
        );
    }
}

#[test]
fn arbitrary_bytes_never_panic_the_loader() {
    runner(3000)
        .run(&prop::collection::vec(any::<u8>(), 0..600), |bytes| {
            if let Ok(mesh) = Mesh::parse_obj(&bytes) {
                check_mesh(&mesh)?;
            }
            Ok(())
        })
        .unwrap();
}

fn script_item() -> impl Strategy<Value = String> {
    let action = prop_oneof![
        "(resize|orbit|zoom|move|wind|shake|pause|minimize|screenshot)=[ -~]{0,12}",
        "(resize=[0-9]{1,5}x[0-9]{1,5}|orbit=-?[0-9]{1,3},-?[0-9]{1,3}|zoom=[0-9.e-]{1,6}|wind=(on|off|1|maybe))",
        "[ -~]{0,16}",
    ];
    (
        prop_oneof!["[0-9]{1,20}", "-?[0-9]{1,3}", "[ -~]{0,4}"],
        action,
    )
        .prop_map(|(frame, action)| format!("{frame}:{action}"))
}

#[test]
fn scripts_never_panic_the_parser() {
    runner(5000)
        .run(&prop::collection::vec(script_item(), 0..8), |items| {
            let text = items.join(";");
            if let Ok(script) = Script::parse(&text) {
                // Parsed steps are sorted by frame and survive the frame check.
                prop_assert!(script.events.windows(2).all(|w| w[0].0 <= w[1].0));
                let _ = script.check_within(100);
            }
            Ok(())
        })
        .unwrap();
}

/// A small valid `.glb`: a rigged quad (two joints, a clip of each interpolation, UVs).
fn small_glb() -> Vec<u8> {
    use fur_core::scene::{Channel, Clip, Interpolation, Joint, Node, Property, Rig, Transform};
    use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
    let nodes = vec![
        Node {
            name: "root".into(),
            parent: None,
            rest: Transform::default(),
        },
        Node {
            name: "tip".into(),
            parent: Some(0),
            rest: Transform {
                translation: Vec3::Y,
                rotation: Quat::from_rotation_z(0.3),
                scale: Vec3::ONE,
            },
        },
    ];
    let tip = nodes[1].rest.matrix();
    let rig = Rig {
        nodes,
        joints: vec![
            Joint {
                node: 0,
                inverse_bind: Mat4::IDENTITY,
            },
            Joint {
                node: 1,
                inverse_bind: tip.inverse(),
            },
        ],
        influences: vec![[0, 1, 0, 0]; 4],
        weights: vec![
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.5, 0.5, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
        ],
        bind_positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
        bind_normals: vec![Vec3::Z; 4],
        clips: vec![Clip {
            name: "c".into(),
            channels: [
                Interpolation::Step,
                Interpolation::Linear,
                Interpolation::CubicSpline,
            ]
            .into_iter()
            .map(|interpolation| Channel {
                node: 1,
                property: Property::Rotation,
                interpolation,
                times: vec![0.0, 1.0],
                values: vec![
                    Vec4::W;
                    if interpolation == Interpolation::CubicSpline {
                        6
                    } else {
                        2
                    }
                ],
            })
            .collect(),
        }],
        scale: 1.0,
    };
    let indices = vec![0, 1, 2, 2, 1, 3];
    let mesh = Mesh {
        positions: rig.bind_positions.clone(),
        normals: vec![Vec3::Z; 4],
        uvs: indices
            .iter()
            .map(|&i| Vec2::new((i % 2) as f32, (i / 2) as f32))
            .collect(),
        indices,
        texture: None,
    };
    fur_core::scene::write_glb(&mesh, Some(&rig)).unwrap()
}

/// One change to a file's bytes; positions are taken modulo its length.
#[derive(Clone, Debug)]
enum Mutation {
    Flip(prop::sample::Index, u8),
    Truncate(prop::sample::Index),
    Insert(prop::sample::Index, Vec<u8>),
    /// Replaces one ASCII digit (of the JSON: counts, offsets, indices) with another.
    Digit(prop::sample::Index, u8),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<prop::sample::Index>(), 1u8..=255).prop_map(|(i, x)| Mutation::Flip(i, x)),
        1 => any::<prop::sample::Index>().prop_map(Mutation::Truncate),
        1 => (any::<prop::sample::Index>(), prop::collection::vec(any::<u8>(), 1..9))
            .prop_map(|(i, b)| Mutation::Insert(i, b)),
        4 => (any::<prop::sample::Index>(), b'0'..=b'9').prop_map(|(i, d)| Mutation::Digit(i, d)),
    ]
}

fn mutate(mut bytes: Vec<u8>, mutations: &[Mutation]) -> Vec<u8> {
    for m in mutations {
        if bytes.is_empty() {
            break;
        }
        match m {
            Mutation::Flip(i, x) => {
                let i = i.index(bytes.len());
                bytes[i] ^= x;
            }
            Mutation::Truncate(i) => bytes.truncate(i.index(bytes.len())),
            Mutation::Insert(i, extra) => {
                let i = i.index(bytes.len());
                bytes.splice(i..i, extra.iter().copied());
            }
            Mutation::Digit(i, d) => {
                let digits: Vec<usize> = (0..bytes.len())
                    .filter(|&k| bytes[k].is_ascii_digit())
                    .collect();
                if !digits.is_empty() {
                    bytes[digits[i.index(digits.len())]] = *d;
                }
            }
        }
    }
    bytes
}

#[test]
fn mutated_glb_files_never_panic_the_gltf_loader() {
    let original = small_glb();
    let dir = std::env::temp_dir().join(format!("fur-fuzz-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mutated.glb");
    std::fs::write(&path, &original).unwrap();
    let body = fur_core::scene::load_gltf(&path).expect("the unmutated file loads");
    assert!(body.rig.is_some());
    let loaded = std::cell::Cell::new(0u32);
    let mut runner = runner(2000);
    let cases = runner.config().cases;
    let result = runner.run(&prop::collection::vec(mutation(), 1..4), |mutations| {
        std::fs::write(&path, mutate(original.clone(), &mutations)).unwrap();
        if let Ok(body) = fur_core::scene::load_gltf(&path) {
            check_mesh(&body.mesh)?;
            if let Some(rig) = &body.rig {
                prop_assert!(
                    rig.validate(body.mesh.vertex_count()).is_ok(),
                    "{:?}",
                    rig.validate(body.mesh.vertex_count())
                );
            }
            loaded.set(loaded.get() + 1);
        }
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&dir);
    result.unwrap();
    // Many mutations (of key values, weights, positions) still load: the checks of a
    // loaded body run too.
    assert!(
        loaded.get() * 20 > cases,
        "only {} of {cases} mutated files loaded",
        loaded.get()
    );
}
