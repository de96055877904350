//! Links the system's shaderc with the glslang and SPIRV-Tools libraries it needs.
//!
//! Debian's `libshaderc_combined.a` leaves glslang's and SPIRV-Tools' symbols undefined,
//! so with the default features this script adds them as static libraries. With the
//! `shaderc-from-source` feature the `shaderc-sys` crate builds everything itself and this
//! script does nothing.

use std::env;
use std::path::Path;

/// Static libraries Debian's shaderc needs, in link order (dependents first).
const SYSTEM_LIBS: &[&str] = &[
    "glslang",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "SPIRV",
    "glslang-default-resource-limits",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    if env::var_os("CARGO_FEATURE_SHADERC_FROM_SOURCE").is_some() {
        return;
    }
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let dir = env::var("SHADERC_LIB_DIR").unwrap_or_else(|_| format!("/usr/lib/{arch}-linux-gnu"));
    let missing: Vec<&str> = SYSTEM_LIBS
        .iter()
        .copied()
        .filter(|lib| !Path::new(&dir).join(format!("lib{lib}.a")).exists())
        .collect();
    if !missing.is_empty() {
        panic!(
            "shaderc's static dependencies are missing from {dir}: {}.\n\
             On Debian/Ubuntu install them with `apt-get install libshaderc-dev glslang-dev spirv-tools`,\n\
             or build shaderc from source with `cargo build --features shaderc-from-source`.",
            missing.join(", ")
        );
    }
    println!("cargo:rustc-link-search=native={dir}");
    for lib in SYSTEM_LIBS {
        println!("cargo:rustc-link-lib=static={lib}");
    }
}
