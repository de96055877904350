//! The kernels' shared constants.
use super::kernel_defines;
use crate::gpu::shader::compile;

/// The kernels take what they share with Rust from `kernel_defines` only: without
/// it they do not compile, and every name it defines is one the kernel uses.
#[test]
fn the_kernels_take_their_shared_constants_from_rust() {
    for kernel in ["simulate.comp", "simulate_rest.comp"] {
        let mut defines = kernel_defines();
        defines.push(("STRAND_VERTICES", "17".into()));
        let words = compile(kernel, &defines).unwrap_or_else(|e| panic!("{kernel}: {e}"));
        assert_eq!(words[0], 0x0723_0203, "{kernel}: not SPIR-V");
    }
    let error = compile("simulate.comp", &[]).unwrap_err().to_string();
    assert!(error.contains("kernel_defines"), "{error}");
    let source = [
        crate::gpu::shader::source("simulate.comp").unwrap(),
        crate::gpu::shader::source("collide.glsl").unwrap(),
        crate::gpu::shader::source("sim_common.glsl").unwrap(),
    ]
    .concat();
    // The bindings' numbers (`SB_*`) are each used once, in their layout declaration,
    // which `the_kernels_agree_with_the_rust_layouts` checks binding by binding.
    for (name, value) in kernel_defines()
        .into_iter()
        .filter(|(name, _)| !name.starts_with("SB_"))
    {
        let uses = source.matches(name).count();
        assert!(
            uses >= 2,
            "{name} = {value} is defined but used {uses} times"
        );
        assert!(
            !source.contains(&format!("const uint {name} ="))
                && !source.contains(&format!("const float {name} =")),
            "{name} is typed in GLSL too"
        );
    }
}
