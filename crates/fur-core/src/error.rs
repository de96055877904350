//! The library's error type: every failure a user can cause or act on, named.

use std::path::PathBuf;

/// Result alias used throughout the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in the renderer and simulator.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("the Vulkan loader could not be loaded ({0}); install libvulkan1 and a Vulkan driver (e.g. mesa-vulkan-drivers)")]
    Loader(String),

    #[error("Vulkan call {call} failed: {result}{}", hint(result.code))]
    Vulkan {
        call: &'static str,
        result: VulkanResult,
    },

    #[error("the Khronos validation layer (VK_LAYER_KHRONOS_validation) is not installed; install vulkan-validationlayers or run without --validate")]
    ValidationLayerMissing,

    #[error("no usable Vulkan device:\n{0}")]
    NoSuitableDevice(String),

    /// `--device` named no device, several, or one fur cannot run on; with the list.
    #[error("{0}")]
    DeviceChoice(String),

    #[error("allocating {} of GPU memory for `{name}` failed (out of device memory?): {source}", size_text(*.bytes))]
    Allocation {
        name: String,
        bytes: u64,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },

    #[error("shader compilation failed: {0}")]
    ShaderCompile(String),

    #[error("GPU work did not finish within {0} seconds")]
    Timeout(u64),

    #[error("cannot read model {path}: {message}")]
    Model { path: PathBuf, message: String },

    /// A texture image that cannot be read, decoded or used.
    #[error("cannot read texture {path}: {message}")]
    Texture { path: PathBuf, message: String },

    /// A groom file (guide curves) that cannot be read, decoded or bound to the body.
    #[error("cannot read groom {path}: {message}")]
    Groom { path: PathBuf, message: String },

    #[error("{0}")]
    Window(String),

    #[error("{count} validation message(s); the first: {first}")]
    Validation { count: usize, first: String },

    #[error("invalid parameter: {0}")]
    Parameter(String),

    #[error("cannot write image {path}: {message}")]
    ImageWrite { path: PathBuf, message: String },

    /// A file-system operation (write, create a folder, rename) on a path failed.
    #[error("cannot {operation} {path}: {message}")]
    Io {
        operation: &'static str,
        path: PathBuf,
        message: String,
    },

    #[error("interrupted")]
    Interrupted,

    /// A scene file that cannot be read, parsed or applied; line 0 when no line applies.
    #[error("scene file {}: {message}", location(path, *line, *column))]
    SceneFile {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },

    #[error("leak: {0}")]
    Leak(String),
}

/// A Vulkan result code, named (the core has no Vulkan bindings: the GPU layer makes
/// these from its `VkResult`s).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VulkanResult {
    /// The `VkResult` value.
    pub code: i32,
    /// Its name (`ERROR_DEVICE_LOST`).
    pub name: String,
}

impl std::fmt::Display for VulkanResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name)
    }
}

impl VulkanResult {
    pub const ERROR_OUT_OF_HOST_MEMORY: i32 = -1;
    pub const ERROR_OUT_OF_DEVICE_MEMORY: i32 = -2;
    pub const ERROR_DEVICE_LOST: i32 = -4;
}

impl Error {
    /// An [`Error::Io`] from an `std::io::Error`.
    pub fn io(operation: &'static str, path: &std::path::Path, error: std::io::Error) -> Self {
        Error::Io {
            operation,
            path: path.to_path_buf(),
            message: error.to_string(),
        }
    }
}

/// `path:line:column`, or the path alone without a line.
fn location(path: &std::path::Path, line: usize, column: usize) -> String {
    if line == 0 {
        path.display().to_string()
    } else {
        format!("{}:{line}:{column}", path.display())
    }
}

/// A byte count for people: `2 GiB`, `3.5 MiB`, `120 bytes`.
pub fn size_text(bytes: u64) -> String {
    const GIB: f64 = (1u64 << 30) as f64;
    const MIB: f64 = (1u64 << 20) as f64;
    let b = bytes as f64;
    if b >= GIB {
        format!("{} GiB", trim_number(b / GIB))
    } else if b >= MIB {
        format!("{} MiB", trim_number(b / MIB))
    } else {
        format!("{bytes} bytes")
    }
}

fn trim_number(x: f64) -> String {
    let text = format!("{x:.1}");
    text.strip_suffix(".0").map_or(text.clone(), str::to_string)
}

/// What a Vulkan error means for the user.
fn hint(code: i32) -> &'static str {
    match code {
        VulkanResult::ERROR_DEVICE_LOST => {
            " (the GPU stopped responding or reset; the work was too large or the driver failed)"
        }
        VulkanResult::ERROR_OUT_OF_DEVICE_MEMORY | VulkanResult::ERROR_OUT_OF_HOST_MEMORY => {
            " (out of memory: use a smaller image, fewer samples or hairs)"
        }
        _ => "",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_and_device_errors_say_what_and_how_big() {
        let oom = Error::Allocation {
            name: "target.color".into(),
            bytes: 3 << 20,
            source: "out of memory".into(),
        };
        let text = oom.to_string();
        assert!(
            text.contains("3 MiB") && text.contains("target.color"),
            "{text}"
        );
        let result = |code: i32, name: &str| VulkanResult {
            code,
            name: name.into(),
        };
        let lost = Error::Vulkan {
            call: "vkQueueSubmit",
            result: result(VulkanResult::ERROR_DEVICE_LOST, "ERROR_DEVICE_LOST"),
        };
        assert!(lost.to_string().contains("stopped responding"), "{lost}");
        let full = Error::Vulkan {
            call: "vkAllocateMemory",
            result: result(
                VulkanResult::ERROR_OUT_OF_DEVICE_MEMORY,
                "ERROR_OUT_OF_DEVICE_MEMORY",
            ),
        };
        assert!(full.to_string().contains("out of memory"), "{full}");
    }
}
