//! Tests across the crate's layers.

use crate::gpu::shader::{compile, SOURCES};

/// Every embedded shader compiles with the defines its layer gives it (the kernels'
/// shared constants and binding numbers, the render passes' flags and binding
/// numbers, the skinning's binding numbers) and the widest variant options: a new shader needs no list to be checked.
#[test]
fn every_embedded_shader_compiles() {
    let options = [
        ("STRAND_VERTICES", "17"),
        ("TEXTURED", "1"),
        ("SHADOWS", "1"),
        ("BODY_SKINNED", "1"),
        ("COUNT_HAIRS", "1"),
        ("LINES", "1"),
        ("TILE", "8"),
        ("NEAREST", "4"),
        ("DEPTH_SAMPLES", "1"),
        ("SCATTER", "0"),
        // A CPU driver's per-tile workgroups (the GPU's are in the bindings' test).
        ("TILE_GROUP", "8u"),
    ]
    .map(|(k, v)| (k, v.to_string()));
    let layers = [
        crate::sim::kernel_defines(),
        crate::render::render_defines(),
        crate::skinning::gpu::skin_defines(),
    ];
    let mut compiled = 0;
    for (name, _) in SOURCES.iter().filter(|(n, _)| !n.ends_with(".glsl")) {
        let errors: Vec<String> = layers
            .iter()
            .filter_map(|layer| {
                let mut defines = options.to_vec();
                defines.extend(layer.iter().cloned());
                match compile(name, &defines) {
                    Ok(words) => {
                        assert_eq!(words[0], 0x0723_0203, "{name}: not SPIR-V");
                        None
                    }
                    Err(e) => Some(e.to_string()),
                }
            })
            .collect();
        assert!(
            errors.len() < layers.len(),
            "{name} compiles with no layer's defines:\n{}",
            errors.join("\n")
        );
        compiled += 1;
    }
    assert!(compiled >= 12, "only {compiled} shaders found");
}
