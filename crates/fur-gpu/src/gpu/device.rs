//! Physical-device selection and the logical device with its queue, allocator and
//! command pool.

use std::ffi::CStr;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::{ext, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::instance::Instance;
use super::physical::select_physical_device;
use crate::error::{Error, Result, VkContext};

/// How long a single submission may run before it counts as hung.
const SUBMIT_TIMEOUT_S: u64 = 600;

/// What the chosen physical device offers that the renderer cares about.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub name: String,
    /// The driver's name and information, e.g. `llvmpipe: Mesa 22.3.6 (LLVM 15.0.6)`.
    pub driver: String,
    pub device_type: vk::PhysicalDeviceType,
    pub limits: vk::PhysicalDeviceLimits,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period: f32,
    pub timestamps: bool,
    pub pipeline_statistics: bool,
    /// Stores and atomics in vertex, tessellation and geometry shaders (the fur pass
    /// counts what it draws with them).
    pub vertex_pipeline_stores: bool,
    /// The invocations a subgroup runs together (a GPU's warp, a CPU driver's SIMD
    /// vector: 8 on lavapipe with 256-bit vectors); 1 where the device does not say.
    pub subgroup_size: u32,
}

impl DeviceInfo {
    /// Whether the device is a CPU driver (lavapipe): it runs shaders a vector of
    /// invocations at a time and bins its draws, so its timestamps between passes
    /// misattribute.
    pub fn is_cpu(&self) -> bool {
        self.device_type == vk::PhysicalDeviceType::CPU
    }

    /// Whether strands drawn in compute are the quality ladder's cheaper rungs here: a
    /// GPU whose geometry stage can write them out. On a CPU driver (`fur bench --only
    /// raster`, `--only ladder`) the compute frame errs less and costs less than the
    /// fixed-function 4× MSAA ribbons on the blob, but more than the fixed ladder's
    /// cheaper rungs (4× lines and below).
    pub fn prefers_compute_strands(&self) -> bool {
        !self.is_cpu() && self.vertex_pipeline_stores
    }

    /// The quality ladder of this device for a scene drawn by `scene`: on a device that
    /// prefers compute strands, their LOD rungs (below 4× lines where the scene asks
    /// for the fixed-function rasteriser), else the fixed-function one.
    pub fn ladder(&self, scene: fur_core::render::Raster) -> fur_core::render::budget::Ladder {
        use fur_core::render::budget::Ladder;
        use fur_core::render::Raster;
        match (self.prefers_compute_strands(), scene) {
            (false, _) => Ladder::FIXED,
            (true, Raster::Hardware) => Ladder::COMPUTE,
            (true, Raster::Compute) => Ladder::IN_COMPUTE,
        }
    }
}

/// The logical device. Shared through `Arc` by every resource created from it.
pub struct Device {
    pub instance: Arc<Instance>,
    pub physical: vk::PhysicalDevice,
    pub raw: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub info: DeviceInfo,
    debug_utils: Option<ext::debug_utils::Device>,
    allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    command_pool: Mutex<vk::CommandPool>,
}

/// Optional requirement: a surface the chosen queue family must be able to present to.
pub struct PresentTarget<'a> {
    pub surface_fn: &'a ash::khr::surface::Instance,
    pub surface: vk::SurfaceKHR,
}

impl Device {
    /// Creates the device `choice` names (an index or part of a name, as `--device`
    /// takes; `None`: the best device that supports everything the fur pipeline
    /// needs). `extensions` are extra device extensions (the swapchain's).
    pub fn new(
        instance: Arc<Instance>,
        present: Option<PresentTarget<'_>>,
        extensions: &[&'static CStr],
        choice: Option<&str>,
    ) -> Result<Arc<Self>> {
        let (physical, queue_family, info) =
            select_physical_device(&instance, present.as_ref(), choice)?;
        log::info!(
            "using {} ({:?}; driver {})",
            info.name,
            info.device_type,
            info.driver
        );

        let priorities = [1.0];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let features = vk::PhysicalDeviceFeatures::default()
            .tessellation_shader(true)
            .geometry_shader(true)
            .pipeline_statistics_query(info.pipeline_statistics)
            .vertex_pipeline_stores_and_atomics(info.vertex_pipeline_stores);
        let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true);
        let mut features12 = vk::PhysicalDeviceVulkan12Features::default().host_query_reset(true);
        let extension_names: Vec<_> = extensions.iter().map(|e| e.as_ptr()).collect();
        let create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .enabled_features(&features)
            .enabled_extension_names(&extension_names)
            .push_next(&mut features13)
            .push_next(&mut features12);
        // Held until the device and its debug-utils functions are loaded (see
        // `loader_lock`).
        let _loader = super::loader_lock();
        // SAFETY: `physical` was enumerated from this instance and offers
        // `queue_family`; the create info, its feature chain and the extension names
        // live on this stack frame through the call, and the loader lock is held.
        let raw = unsafe { instance.raw.create_device(physical, &create_info, None) }
            .vk("vkCreateDevice")?;
        // SAFETY: the device was just created with one queue of `queue_family`
        // (queue_infos above).
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.raw.clone(),
            device: raw.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(source) => {
                // SAFETY: the allocator failed, so nothing was created from the device
                // yet and it is not used after this.
                unsafe { raw.destroy_device(None) };
                return Err(Error::Allocation {
                    name: "allocator".into(),
                    bytes: 0,
                    source: Box::new(source),
                });
            }
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: the device is alive and `queue_family` is the family its queue came
        // from.
        let command_pool = match unsafe { raw.create_command_pool(&pool_info, None) } {
            Ok(pool) => pool,
            Err(result) => {
                drop(allocator);
                // SAFETY: the allocator, the only object created from the device, was
                // dropped above; the device is not used after this.
                unsafe { raw.destroy_device(None) };
                return Err(crate::error::vulkan("vkCreateCommandPool", result));
            }
        };
        let debug_utils = instance
            .debug_utils
            .as_ref()
            .map(|_| ext::debug_utils::Device::new(&instance.raw, &raw));
        Ok(Arc::new(Self {
            instance,
            physical,
            raw,
            queue,
            queue_family,
            info,
            debug_utils,
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            command_pool: Mutex::new(command_pool),
        }))
    }

    pub fn raw(&self) -> &ash::Device {
        &self.raw
    }

    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    pub fn instance(&self) -> &Arc<Instance> {
        &self.instance
    }

    pub fn queue(&self) -> vk::Queue {
        self.queue
    }

    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }

    pub fn physical(&self) -> vk::PhysicalDevice {
        self.physical
    }

    /// The shared allocator, for libraries that allocate through it too (the UI
    /// renderer). Whoever holds a clone must be dropped before the device.
    pub fn shared_allocator(&self) -> Arc<Mutex<Allocator>> {
        Arc::clone(&self.allocator)
    }

    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A poisoned lock only means another thread panicked mid-allocation; the
        // allocator's state is still consistent enough to free memory on shutdown.
        self.allocator.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Gives a Vulkan object a name that validation messages and debuggers show.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(debug_utils) = &self.debug_utils else {
            return;
        };
        let Ok(name) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&name);
        let _loader = super::loader_lock();
        // Naming is best-effort diagnostics: a failure is not worth aborting for.
        // SAFETY: callers name objects they created from this device and still hold;
        // `name` is a NUL-terminated CString that outlives the call, and the loader
        // lock is held.
        let _ = unsafe { debug_utils.set_debug_utils_object_name(&info) };
    }

    /// Opens a named, labelled region in a command buffer (shown by debuggers).
    pub fn begin_label(&self, cmd: vk::CommandBuffer, name: &str) {
        if let (Some(debug_utils), Ok(name)) = (&self.debug_utils, std::ffi::CString::new(name)) {
            let label = vk::DebugUtilsLabelEXT::default().label_name(&name);
            let _loader = super::loader_lock();
            // SAFETY: callers pass a command buffer of this device in the recording
            // state; `label` and the CString it points at outlive the call; the loader
            // lock is held.
            unsafe { debug_utils.cmd_begin_debug_utils_label(cmd, &label) };
        }
    }

    pub fn end_label(&self, cmd: vk::CommandBuffer) {
        if let Some(debug_utils) = &self.debug_utils {
            let _loader = super::loader_lock();
            // SAFETY: `cmd` is recording and has a label open from `begin_label`
            // (callers pair the two); the loader lock is held.
            unsafe { debug_utils.cmd_end_debug_utils_label(cmd) };
        }
    }

    /// Records commands with `record`, submits them and waits for completion.
    pub fn submit_once<T>(&self, record: impl FnOnce(vk::CommandBuffer) -> Result<T>) -> Result<T> {
        let pool = self.command_pool.lock().unwrap_or_else(|e| e.into_inner());
        let alloc_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device, and its mutex (held until the buffer
        // is freed below) keeps any other thread from using the pool meanwhile.
        let cmd = unsafe { self.raw.allocate_command_buffers(&alloc_info) }
            .vk("vkAllocateCommandBuffers")?[0];
        let result = (|| {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            // SAFETY: `cmd` was just allocated, so it is in the initial state; the pool
            // lock is held.
            unsafe { self.raw.begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
            let value = record(cmd)?;
            // SAFETY: `cmd` is in the recording state: begun above, and `record` only
            // records into it.
            unsafe { self.raw.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
            // SAFETY: a plain create info on a live device; the fence is destroyed
            // below on every path.
            let fence = unsafe { self.raw.create_fence(&vk::FenceCreateInfo::default(), None) }
                .vk("vkCreateFence")?;
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            // SAFETY: `cmd` has ended recording (executable), the fence is new and
            // unsignalled, and the queue is this device's; `cmds` outlives the call.
            let submitted = unsafe { self.raw.queue_submit(self.queue, &[submit], fence) }
                .vk("vkQueueSubmit")
                .and_then(|_| self.wait_fence(fence));
            // SAFETY: the fence was never submitted (the submit failed) or the wait for
            // it returned; after a wait timeout the device counts as hung and the error
            // ends the run.
            unsafe { self.raw.destroy_fence(fence, None) };
            submitted.map(|_| value)
        })();
        // SAFETY: `cmd` came from `pool`, whose lock is still held, and is no longer
        // pending (as for the fence above); recording may have stopped half-way, which
        // freeing allows.
        unsafe { self.raw.free_command_buffers(*pool, &[cmd]) };
        result
    }

    /// Waits for a fence with the project's hang timeout.
    pub fn wait_fence(&self, fence: vk::Fence) -> Result<()> {
        // SAFETY: callers pass a fence created from this device that they still hold.
        match unsafe {
            self.raw
                .wait_for_fences(&[fence], true, SUBMIT_TIMEOUT_S * 1_000_000_000)
        } {
            Ok(()) => Ok(()),
            Err(vk::Result::TIMEOUT) => Err(Error::Timeout(SUBMIT_TIMEOUT_S)),
            Err(result) => Err(crate::error::vulkan("vkWaitForFences", result)),
        }
    }

    /// Waits until the device has finished all work.
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: the device is alive for as long as `self` is borrowed; the call takes
        // no other handle.
        unsafe { self.raw.device_wait_idle() }.vk("vkDeviceWaitIdle")
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: every object created from the device holds an `Arc` of it, so none is
        // left: the device is idle (waited here) and unused; the pool and the
        // allocator, its last two children, go before it, and the loader lock is held
        // around vkDestroyDevice.
        unsafe {
            // Nothing useful can be done about a lost device while tearing down.
            let _ = self.raw.device_wait_idle();
            let pool = *self
                .command_pool
                .get_mut()
                .unwrap_or_else(|e| e.into_inner());
            self.raw.destroy_command_pool(pool, None);
            // The allocator frees its memory blocks through the device: drop it first
            // (every other holder of the Arc is gone by now).
            ManuallyDrop::drop(&mut self.allocator);
            let _loader = super::loader_lock();
            self.raw.destroy_device(None);
        }
    }
}
