//! The GPU layer's error type: the core's errors ([`fur_core::Error`]: a parameter, a
//! model, a file) and what only a device can go wrong with (the loader, a Vulkan call,
//! memory, shaders, the validation layer, a window's surface).

use ash::vk;

pub use fur_core::error::size_text;
/// The core's error, by its own name where both are in scope.
pub use fur_core::Error as CoreError;

/// Result alias used throughout the GPU layer and the application.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in the renderer and simulator.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// What the core refuses or cannot read or write.
    #[error(transparent)]
    Core(#[from] CoreError),

    #[error("the Vulkan loader could not be loaded ({0}); install libvulkan1 and a Vulkan driver (e.g. mesa-vulkan-drivers)")]
    Loader(String),

    #[error("Vulkan call {call} failed: {result:?}{}", hint(*result))]
    Vulkan {
        call: &'static str,
        result: vk::Result,
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

    /// A window or its surface that cannot be made or presented to.
    #[error("{0}")]
    Window(String),

    #[error("{count} validation message(s); the first: {first}")]
    Validation { count: usize, first: String },

    #[error("leak: {0}")]
    Leak(String),
}

impl Error {
    /// The core's [`CoreError::Parameter`]: an impossible or unsupported setting.
    pub fn parameter(message: impl Into<String>) -> Self {
        Error::Core(CoreError::Parameter(message.into()))
    }

    /// Whether this is the core's [`CoreError::Parameter`].
    pub fn is_parameter(&self) -> bool {
        matches!(self, Error::Core(CoreError::Parameter(_)))
    }

    /// Whether the user stopped the work ([`CoreError::Interrupted`]).
    pub fn is_interrupted(&self) -> bool {
        matches!(self, Error::Core(CoreError::Interrupted))
    }

    /// An [`CoreError::Io`] from an `std::io::Error`.
    pub fn io(operation: &'static str, path: &std::path::Path, error: std::io::Error) -> Self {
        Error::Core(CoreError::io(operation, path, error))
    }
}

/// The error of Vulkan call `call` failing with `result`.
pub fn vulkan(call: &'static str, result: vk::Result) -> Error {
    Error::Vulkan { call, result }
}

/// Attaches the name of the failing Vulkan call to a raw `vk::Result`.
pub trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| vulkan(call, result))
    }
}

/// What a Vulkan error means for the user.
fn hint(result: vk::Result) -> &'static str {
    match result {
        vk::Result::ERROR_DEVICE_LOST => {
            " (the GPU stopped responding or reset; the work was too large or the driver failed)"
        }
        vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
            " (out of memory: use a smaller image, fewer samples or hairs)"
        }
        _ => "",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vulkan_results_keep_their_names_and_hints() {
        let lost = vulkan("vkQueueSubmit", vk::Result::ERROR_DEVICE_LOST);
        let text = lost.to_string();
        assert!(
            text.contains("ERROR_DEVICE_LOST") && text.contains("stopped responding"),
            "{text}"
        );
        let full = vulkan("vkAllocateMemory", vk::Result::ERROR_OUT_OF_DEVICE_MEMORY);
        assert!(full.to_string().contains("out of memory"), "{full}");
    }

    #[test]
    fn memory_errors_say_what_and_how_big() {
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
    }

    #[test]
    fn the_cores_errors_read_as_they_do_in_the_core() {
        let core = CoreError::Parameter("hair width must be positive".into());
        let text = core.to_string();
        assert_eq!(Error::from(core).to_string(), text);
        assert!(Error::parameter("x").is_parameter());
    }
}
