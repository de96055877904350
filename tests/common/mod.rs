//! Shared helpers for the GPU tests: a validated headless device and checks.
#![allow(dead_code)]

use std::sync::Arc;

use fur::gpu::Device;

/// A lavapipe-friendly headless device with the Khronos validation layer on.
pub fn device() -> Arc<Device> {
    fur::gpu::headless(true).expect("a Vulkan device with the validation layer (see README)")
}

/// Fails the test if the validation layer reported anything.
pub fn assert_clean(device: &Arc<Device>) {
    let messages = device.instance().validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation message(s):\n{}",
        messages.len(),
        messages.join("\n")
    );
}
