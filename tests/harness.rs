//! Tests of the checks every GPU test and the binary lean on: the test device hears the
//! validation layer, a validation error fails `common::assert_clean`, and a leaked
//! buffer fails `fur_gpu::gpu::shut_down`, what `fur render` and `fur bench` run at exit
//! (their errors end the process with a failure, which `tests/cli/`'s
//! `nothing_is_left_alive_at_exit` asserts against).

mod common;

use ash::vk;
use gpu_allocator::MemoryLocation;

/// A buffer the layer must object to: no usage at all (VUID-VkBufferCreateInfo-None-09499
/// / usage-requiredbitmask), which lavapipe itself creates without complaint.
fn create_invalid_buffer(device: &fur_gpu::gpu::Device) -> vk::Buffer {
    let info = vk::BufferCreateInfo::default()
        .size(256)
        .usage(vk::BufferUsageFlags::empty())
        .sharing_mode(vk::SharingMode::EXCLUSIVE);
    unsafe { device.raw().create_buffer(&info, None) }.expect("lavapipe creates the buffer")
}

#[test]
fn a_validation_error_fails_the_gpu_tests_check() {
    let device = common::device();
    assert!(device.instance().validation_enabled());
    assert!(device.instance().has_debug_messenger());
    common::assert_clean(&device);
    let buffer = create_invalid_buffer(&device);
    unsafe { device.raw().destroy_buffer(buffer, None) };
    let messages = device.instance().validation_messages();
    assert!(
        messages.iter().any(|m| m.contains("VkBufferCreateInfo")),
        "the layer's complaint was not heard: {messages:?}"
    );
    let check = std::panic::catch_unwind(|| common::assert_clean(&device));
    let message = check.expect_err("assert_clean passed a run with a validation error");
    let text = message
        .downcast_ref::<String>()
        .cloned()
        .unwrap_or_default();
    assert!(text.contains("validation message"), "{text}");
}

#[test]
fn a_leaked_buffer_fails_the_exit_check() {
    // A buffer never dropped keeps the device alive: `shut_down` names the leak.
    let device = common::device();
    let buffer = fur_gpu::gpu::Buffer::new(
        &device,
        "leaked on purpose",
        1024,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    std::mem::forget(buffer);
    let error = fur_gpu::gpu::shut_down(device).expect_err("a leaked buffer passed shut_down");
    assert!(matches!(error, fur::Error::Leak(_)), "{error}");
    assert!(error.to_string().contains("leak"), "{error}");

    // A Vulkan buffer created and never destroyed (nothing in Rust holds it): the
    // layer's object tracker reports it when the device is destroyed, and `shut_down`
    // fails with its message.
    let device = common::device();
    let info = vk::BufferCreateInfo::default()
        .size(1024)
        .usage(vk::BufferUsageFlags::STORAGE_BUFFER)
        .sharing_mode(vk::SharingMode::EXCLUSIVE);
    let raw = unsafe { device.raw().create_buffer(&info, None) }.unwrap();
    assert_ne!(raw, vk::Buffer::null());
    common::assert_clean(&device);
    let error = fur_gpu::gpu::shut_down(device).expect_err("a leaked VkBuffer passed shut_down");
    let text = error.to_string();
    assert!(
        matches!(error, fur::Error::Validation { .. }) && text.contains("VkBuffer"),
        "{text}"
    );

    // And the same run without the leak passes.
    let device = common::device();
    let buffer = fur_gpu::gpu::Buffer::new(
        &device,
        "released",
        1024,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    drop(buffer);
    fur_gpu::gpu::shut_down(device).unwrap();
}
