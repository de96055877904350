//! GLSL → SPIR-V with shaderc. Sources are embedded in the binary; `#include` resolves
//! against the same embedded set, and errors name the file and line.

use std::sync::Arc;

use ash::vk;

use super::Device;
use crate::error::{Error, Result, VkContext};

// `SOURCES`: every file of `shaders/` by name, embedded (the table is written by
// build.rs).
include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The embedded source `name`, or one made from Rust declarations (`frame_block.glsl`).
pub fn source(name: &str) -> Option<&'static str> {
    SOURCES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
        .or_else(|| generated(name))
}

/// The sources made from Rust declarations rather than typed in `shaders/`: the
/// `Frame` uniform block's structs (`fur_core::render::frame_block::glsl`).
fn generated(name: &str) -> Option<&'static str> {
    static FRAME_BLOCK: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    match name {
        "frame_block.glsl" => Some(FRAME_BLOCK.get_or_init(fur_core::render::frame_block::glsl)),
        _ => None,
    }
}

fn kind_of(name: &str) -> Result<shaderc::ShaderKind> {
    let ext = name.rsplit('.').next().unwrap_or_default();
    Ok(match ext {
        "vert" => shaderc::ShaderKind::Vertex,
        "tesc" => shaderc::ShaderKind::TessControl,
        "tese" => shaderc::ShaderKind::TessEvaluation,
        "geom" => shaderc::ShaderKind::Geometry,
        "frag" => shaderc::ShaderKind::Fragment,
        "comp" => shaderc::ShaderKind::Compute,
        _ => {
            return Err(Error::ShaderCompile(format!(
                "{name}: unknown shader stage"
            )))
        }
    })
}

/// An embedded shader and its `#define`s (the test defines included): what its SPIR-V
/// depends on.
type Variant = (String, Vec<(String, String)>);

/// The SPIR-V of every embedded shader variant this process has compiled. Sessions,
/// benchmark cases and tests build the same pipelines many times, and shaderc is the
/// slowest part of building them. The embedded sources never change, and the variants
/// are the finite product of each shader's defines, so the cache is bounded.
static COMPILED: std::sync::Mutex<Vec<(Variant, Arc<Vec<u32>>)>> =
    std::sync::Mutex::new(Vec::new());

/// Compiles the embedded shader `name` with the given `#define`s to SPIR-V words,
/// once a process.
///
/// Building pipelines is the longest stretch between frames, so Ctrl-C is checked here
/// too: a run interrupted while it sets up stops within one shader compilation.
pub fn compile(name: &str, defines: &[(&str, String)]) -> Result<Arc<Vec<u32>>> {
    fur_core::interrupt::check()?;
    let text =
        source(name).ok_or_else(|| Error::ShaderCompile(format!("{name}: no such shader")))?;
    let mut all: Vec<(String, String)> = defines
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    TEST_DEFINES.with(|d| all.extend(d.borrow().iter().cloned()));
    let variant = (name.to_string(), all);
    let cached = |compiled: &Vec<(Variant, Arc<Vec<u32>>)>| {
        compiled
            .iter()
            .find(|(v, _)| *v == variant)
            .map(|(_, words)| words.clone())
    };
    // A poisoned lock only means another thread panicked mid-lookup; the list itself
    // is always whole.
    let lock = || COMPILED.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(words) = cached(&lock()) {
        return Ok(words);
    }
    // Compiled without the lock held: threads compiling different shaders do not wait
    // on each other; two compiling the same one both get the same words.
    let words = Arc::new(compile_source(name, text, defines)?);
    let mut compiled = lock();
    if let Some(words) = cached(&compiled) {
        return Ok(words);
    }
    compiled.push((variant, words.clone()));
    Ok(words)
}

thread_local! {
    /// Extra `#define`s for every shader compiled on this thread; see [`with_test_defines`].
    static TEST_DEFINES: std::cell::RefCell<Vec<(String, String)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Test hook: runs `f` with `defines` added to every shader this thread compiles, so a
/// test can build a deliberately broken variant of a shader (the `FUR_TEST_*` blocks in
/// `shaders/`) and check that its check rejects it. Not for anything else.
#[doc(hidden)]
pub fn with_test_defines<R>(defines: &[(&str, &str)], f: impl FnOnce() -> R) -> R {
    struct Restore(Vec<(String, String)>);
    impl Drop for Restore {
        fn drop(&mut self) {
            TEST_DEFINES.with(|d| *d.borrow_mut() = std::mem::take(&mut self.0));
        }
    }
    let added = defines.iter().map(|(k, v)| (k.to_string(), v.to_string()));
    let _restore = Restore(TEST_DEFINES.with(|d| {
        let before = d.borrow().clone();
        d.borrow_mut().extend(added);
        before
    }));
    f()
}

/// Invocations per workgroup of every compute shader: `GROUP_SIZE` in GLSL, defined
/// for every shader from here (a compile-time size, not a specialization constant, so
/// the SPIR-V carries no `WorkgroupSize` built-in, which SPIR-V 1.6 deprecates).
pub const GROUP_SIZE: u32 = 64;

/// Compiles GLSL `text` (reported as file `name`) to SPIR-V words.
pub fn compile_source(name: &str, text: &str, defines: &[(&str, String)]) -> Result<Vec<u32>> {
    let kind = kind_of(name)?;
    let compiler = shaderc::Compiler::new()
        .map_err(|e| Error::ShaderCompile(format!("cannot start shaderc: {e}")))?;
    let mut options = shaderc::CompileOptions::new()
        .map_err(|e| Error::ShaderCompile(format!("cannot create shaderc options: {e}")))?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    options.set_generate_debug_info();
    options.add_macro_definition("GROUP_SIZE", Some(&GROUP_SIZE.to_string()));
    for (key, value) in defines {
        options.add_macro_definition(key, Some(value));
    }
    TEST_DEFINES.with(|d| {
        for (key, value) in d.borrow().iter() {
            options.add_macro_definition(key, Some(value));
        }
    });
    options.set_include_callback(|requested, _, requester, _| {
        source(requested)
            .map(|content| shaderc::ResolvedInclude {
                resolved_name: requested.to_string(),
                content: content.to_string(),
            })
            .ok_or_else(|| format!("{requester}: cannot find include `{requested}`"))
    });
    let artifact = compiler
        .compile_into_spirv(text, kind, name, "main", Some(&options))
        .map_err(|e| Error::ShaderCompile(e.to_string()))?;
    Ok(artifact.as_binary().to_vec())
}

/// A `VkShaderModule` destroyed on drop.
pub struct ShaderModule {
    device: Arc<Device>,
    pub raw: vk::ShaderModule,
}

impl ShaderModule {
    /// Compiles and loads the embedded shader `name`.
    pub fn new(device: &Arc<Device>, name: &str, defines: &[(&str, String)]) -> Result<Self> {
        let code = compile(name, defines)?;
        let info = vk::ShaderModuleCreateInfo::default().code(&code);
        let raw =
            // SAFETY: `code` is a whole SPIR-V module (u32 words) just compiled by
            // shaderc, and it outlives the call.
            unsafe { device.raw.create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        device.set_name(raw, name);
        Ok(Self {
            device: device.clone(),
            raw,
        })
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: the module is owned here and destroyed once; pipelines built from it
        // keep nothing of it, so it may go whenever its owner does.
        unsafe { self.device.raw.destroy_shader_module(self.raw, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compile_errors_name_the_file_and_line() {
        let text = "#version 450\nvoid main() {\n    float x = undefined_thing;\n}\n";
        let error = compile_source("broken.frag", text, &[])
            .unwrap_err()
            .to_string();
        assert!(error.contains("broken.frag:3"), "{error}");
        assert!(error.contains("undefined_thing"), "{error}");
        let include = compile_source(
            "inc.frag",
            "#version 450\n#include \"nope.glsl\"\nvoid main() {}\n",
            &[],
        )
        .unwrap_err()
        .to_string();
        assert!(include.contains("nope.glsl"), "{include}");
    }
}
