//! The error type (the core's, [`fur_core::error`]) and what the Vulkan layer adds to
//! it: Vulkan results named and attached to the failing call.

use ash::vk;

pub use fur_core::error::*;

/// A `vk::Result` as the core's [`VulkanResult`].
pub fn vulkan_result(result: vk::Result) -> VulkanResult {
    VulkanResult {
        code: result.as_raw(),
        name: format!("{result:?}"),
    }
}

/// The error of Vulkan call `call` failing with `result`.
pub fn vulkan(call: &'static str, result: vk::Result) -> Error {
    Error::Vulkan {
        call,
        result: vulkan_result(result),
    }
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
}
