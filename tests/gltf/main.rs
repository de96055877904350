//! glTF bodies from the command line: an animated body renders, an open one is warned
//! about, a broken one is refused by name, the built-in critter exported and read back
//! (the reading itself is tested in
//! `crates/fur-core/tests/gltf/`, without a device).

#[path = "../../crates/fur-core/tests/gltf/doc.rs"]
mod doc;

use doc::*;

/// `fur render` of `model` playing clip `animation`, a 32×24 image to `out`.
fn render_animated(
    model: &std::path::Path,
    animation: &str,
    out: &std::path::Path,
) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args([
            "render",
            "--width",
            "32",
            "--height",
            "24",
            "--animation",
            animation,
        ])
        .arg("--model")
        .arg(model)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// A skinned body whose mesh is open (one triangle on one bone) renders, with the same
/// warning as an open OBJ: its distance field's sign is estimated near the holes.
#[test]
fn an_open_skinned_body_gets_the_open_mesh_warning() {
    let dir = Scratch::new("open-skin");
    let weights: Vec<f32> = [1.0, 0.0, 0.0, 0.0].repeat(3);
    let path = dir.write("open.glb", one_bone(&[0; 12], &weights, &[0.0, 1.0]));
    let out = render_animated(&path, "wave", &dir.0.join("open.png"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("open.glb") && stderr.contains("is not a closed"),
        "{stderr}"
    );
}

/// `fur export-model --model critter` into `path`, which must succeed.
fn export_critter(path: &std::path::Path) {
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["export-model", "--model", "critter"])
        .arg(path)
        .status()
        .unwrap();
    assert!(status.success());
}

/// `fur render --model` takes glTF files, and a broken one is a clean error naming the
/// file and the problem (exit 1, no panic), like a broken OBJ.
#[test]
fn the_command_line_refuses_a_broken_glb_by_name() {
    let dir = std::env::temp_dir().join(format!("fur-broken-glb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("critter.glb");
    export_critter(&good);
    let bytes = std::fs::read(&good).unwrap();
    let broken = dir.join("truncated.glb");
    std::fs::write(&broken, &bytes[..bytes.len() / 2]).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["render", "--width", "32", "--height", "24", "--model"])
        .arg(&broken)
        .arg("--out")
        .arg(dir.join("out.png"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("truncated.glb") && stderr.contains("truncated"),
        "{stderr}"
    );
    // An unknown clip names the clips there are.
    let out = render_animated(&good, "gallop", &dir.join("out.png"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("gallop") && stderr.contains("Walk") && stderr.contains("Idle"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `fur export-model --model critter critter.glb` writes the built-in creature, and
/// loading the file gives the same body, skin and animation.
#[test]
fn the_built_in_critter_round_trips_through_export_model() {
    let dir = std::env::temp_dir().join(format!("fur-critter-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("critter.glb");
    export_critter(&path);
    let (mesh, rig) = fur_core::scene::critter();
    let body = fur_core::scene::load_gltf(&path).unwrap();
    assert!(body.warnings.is_empty(), "{:?}", body.warnings);
    assert_eq!(body.rig.as_ref(), Some(&rig), "the rig changed on the way");
    assert_eq!(body.mesh.indices, mesh.indices);
    assert_eq!(body.mesh.uvs, mesh.uvs);
    let moved = body
        .mesh
        .positions
        .iter()
        .zip(&mesh.positions)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(moved < 1e-5, "rest positions moved by {moved}");
    let clips: Vec<&str> = rig.clips.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(clips, ["Walk", "Idle"]);
    let _ = std::fs::remove_dir_all(&dir);
}
