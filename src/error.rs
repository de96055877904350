//! The library's error type: every failure a user can cause or act on, named.

use std::path::PathBuf;

use ash::vk;

/// Result alias used throughout the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in the renderer and simulator.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("the Vulkan loader could not be loaded ({0}); install libvulkan1 and a Vulkan driver (e.g. mesa-vulkan-drivers)")]
    Loader(#[from] ash::LoadingError),

    #[error("Vulkan call {call} failed: {result}")]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },

    #[error("the Khronos validation layer (VK_LAYER_KHRONOS_validation) is not installed; install vulkan-validationlayers or run without --validate")]
    ValidationLayerMissing,

    #[error("no usable Vulkan device:\n{0}")]
    NoSuitableDevice(String),

    #[error("allocating GPU memory for `{name}` failed: {source}")]
    Allocation {
        name: String,
        #[source]
        source: gpu_allocator::AllocationError,
    },

    #[error("shader compilation failed: {0}")]
    ShaderCompile(String),

    #[error("GPU work did not finish within {0} seconds")]
    Timeout(u64),

    #[error("cannot read model {path}: {message}")]
    Model { path: PathBuf, message: String },

    #[error("{0}")]
    Window(String),

    #[error("{count} validation message(s); the first: {first}")]
    Validation { count: usize, first: String },

    #[error("invalid parameter: {0}")]
    Parameter(String),

    #[error("cannot write image {path}: {message}")]
    ImageWrite { path: PathBuf, message: String },
}

/// Attaches the name of the failing Vulkan call to a raw `vk::Result`.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}
