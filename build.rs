//! Checks that the system's shaderc is there before the `shaderc-sys` crate looks for it.
//!
//! `fur` links the system's shared `libshaderc` (Debian's `libshaderc-dev`; the library is
//! self-contained on Debian 12 and 13 alike, so no glslang or SPIRV-Tools libraries are
//! named here and their versions do not matter). Without it, `shaderc-sys` would quietly
//! fall back to building shaderc from source and fail much later with a CMake error, so this
//! script stops first with the package to install. With the `shaderc-from-source` feature,
//! or with `SHADERC_LIB_DIR` / `VULKAN_SDK` set, it leaves the search to `shaderc-sys`.

use std::env;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    for var in ["SHADERC_LIB_DIR", "VULKAN_SDK"] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    if env::var_os("CARGO_FEATURE_SHADERC_FROM_SOURCE").is_some()
        || env::var_os("SHADERC_LIB_DIR").is_some()
        || env::var_os("VULKAN_SDK").is_some()
        || env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux")
    {
        return;
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let debian_arch = if arch == "x86" { "i386" } else { arch.as_str() };
    let dirs: Vec<PathBuf> = [
        format!("/usr/lib/{debian_arch}-linux-gnu"),
        "/usr/lib64".into(),
        "/usr/lib".into(),
    ]
    .into_iter()
    .map(PathBuf::from)
    .collect();
    let found = dirs.iter().any(|dir| {
        ["libshaderc.so", "libshaderc_shared.so"]
            .iter()
            .any(|f| dir.join(f).exists())
    });
    if !found && !pkg_config_knows("shaderc") {
        let looked: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        panic!(
            "\n\nshaderc's shared library (libshaderc.so) is missing: looked in {} and asked \
             pkg-config for `shaderc`.\n\
             Install it: Debian/Ubuntu `apt-get install libshaderc-dev`, Fedora `dnf install \
             libshaderc-devel`, Arch `pacman -S shaderc`;\n\
             or point SHADERC_LIB_DIR at a directory holding it, or build shaderc from source \
             with `cargo build --features shaderc-from-source` (needs cmake, python3, a C++ \
             compiler).\n",
            looked.join(", ")
        );
    }
}

/// Whether `pkg-config` finds a package (false when pkg-config itself is absent).
fn pkg_config_knows(package: &str) -> bool {
    let pkg_config = env::var("PKG_CONFIG").unwrap_or_else(|_| "pkg-config".into());
    std::process::Command::new(Path::new(&pkg_config))
        .args(["--exists", package])
        .status()
        .is_ok_and(|status| status.success())
}
