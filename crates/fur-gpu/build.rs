//! Embeds the shaders and links the system's shaderc with the glslang and SPIRV-Tools
//! libraries it needs.
//!
//! Every file of `shaders/` is embedded: the script writes the table of them
//! (`$OUT_DIR/shaders.rs`, included by `src/gpu/shader.rs`), so a new shader is a new
//! file and nothing else.
//!
//! `fur` links Debian's static `libshaderc_combined.a`, which leaves glslang's and
//! SPIRV-Tools' symbols undefined, so this script adds those static libraries: the ones
//! every glslang has, and the ones only some versions ship (glslang 14 dropped
//! `OGLCompiler`; Debian 12 has glslang 12, Debian 13 glslang 15), each probed in the
//! library directory. (Linking the shared `libshaderc.so` instead is no simpler: Debian
//! 12's leaves 36 glslang symbols undefined without naming a library that has them.)
//! A missing library stops the build with its name and the package that ships it. With
//! the `shaderc-from-source` feature the `shaderc-sys` crate builds everything itself and
//! this script does nothing.

use std::env;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A static library the link needs, and the Debian/Ubuntu package that ships it.
struct Lib {
    name: &'static str,
    package: &'static str,
    /// Only some versions ship it; linked where it exists.
    optional: bool,
}

const fn lib(name: &'static str, package: &'static str, optional: bool) -> Lib {
    Lib {
        name,
        package,
        optional,
    }
}

/// In link order: dependents first.
const SYSTEM_LIBS: &[Lib] = &[
    lib("shaderc_combined", "libshaderc-dev", false),
    lib("glslang", "glslang-dev", false),
    lib("MachineIndependent", "glslang-dev", true),
    lib("GenericCodeGen", "glslang-dev", true),
    lib("OSDependent", "glslang-dev", true),
    lib("OGLCompiler", "glslang-dev", true),
    lib("SPIRV", "glslang-dev", true),
    lib("glslang-default-resource-limits", "glslang-dev", false),
    lib("SPIRV-Tools-opt", "spirv-tools", false),
    lib("SPIRV-Tools", "spirv-tools", false),
];

/// Writes `$OUT_DIR/shaders.rs`: `SOURCES`, every file of `shaders/` by name, sorted.
fn embed_shaders() {
    // The repository's top-level `shaders/`, beside the crates that use them.
    let dir =
        PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets it")).join("../../shaders");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|path| path.is_file())
        .collect();
    files.sort();
    let mut table = String::from(
        "/// Every shader source shipped in `shaders/`, by file name.\n\
         pub const SOURCES: &[(&str, &str)] = &[\n",
    );
    for path in &files {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .expect("a UTF-8 name");
        writeln!(
            table,
            "    ({name:?}, include_str!({:?})),",
            path.display().to_string()
        )
        .expect("writing to a String");
    }
    table.push_str("];\n");
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets it")).join("shaders.rs");
    std::fs::write(&out, table).unwrap_or_else(|e| panic!("cannot write {}: {e}", out.display()));
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    embed_shaders();
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    if env::var_os("CARGO_FEATURE_SHADERC_FROM_SOURCE").is_some() {
        return;
    }
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let debian_arch = if arch == "x86" { "i386" } else { arch.as_str() };
    let dir =
        env::var("SHADERC_LIB_DIR").unwrap_or_else(|_| format!("/usr/lib/{debian_arch}-linux-gnu"));
    let present = |lib: &Lib| Path::new(&dir).join(format!("lib{}.a", lib.name)).exists();
    let missing: Vec<&Lib> = SYSTEM_LIBS
        .iter()
        .filter(|l| !l.optional && !present(l))
        .collect();
    if !missing.is_empty() {
        let names: Vec<String> = missing.iter().map(|l| format!("lib{}.a", l.name)).collect();
        let mut packages: Vec<&str> = missing.iter().map(|l| l.package).collect();
        packages.dedup();
        panic!(
            "\n\nshaderc's static libraries are missing from {dir}: {}.\n\
             On Debian or Ubuntu: `apt-get install {}` (or run `.ci/install-deps`).\n\
             Elsewhere, point SHADERC_LIB_DIR at a directory holding them, or build shaderc \
             from source with `cargo build --features shaderc-from-source` (needs cmake, \
             python3 and a C++ compiler).\n",
            names.join(", "),
            packages.join(" ")
        );
    }
    println!("cargo:rustc-link-search=native={dir}");
    // shaderc-sys links shaderc_combined itself; the rest follow it.
    for lib in SYSTEM_LIBS.iter().skip(1).filter(|l| present(l)) {
        println!("cargo:rustc-link-lib=static={}", lib.name);
    }
}
