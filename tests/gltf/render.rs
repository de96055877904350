//! Rendering animated glTF bodies from the command line.

use super::*;

/// `fur render` of `model` playing clip `animation`, a 32×24 image to `out`.
pub(super) fn render_animated(
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
