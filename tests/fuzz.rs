//! Property-based fuzzing of the parsers that read user input: the OBJ loader and the
//! viewer's script parser. Fixed seeds and case counts keep CI deterministic and under
//! a minute; `FUR_FUZZ_CASES=200000 cargo test --release --test fuzz` runs longer. No
//! input may panic, and whatever parses must be usable.

use fur::scene::Mesh;
use fur::viewer::Script;
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
/// (broken numbers, bad indices, comments, groups, garbage).
fn obj_file() -> impl Strategy<Value = String> {
    let vertex =
        (-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0).prop_map(|(x, y, z)| format!("v {x} {y} {z}"));
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
    }
    Ok(())
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
