//! The Vulkan instance, the optional Khronos validation layer and the debug messenger
//! that collects its messages.

use std::ffi::{c_char, c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::{ext, vk};

use crate::error::{Result, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Validation messages (warnings and errors) reported while the instance lived.
#[derive(Debug, Default)]
pub struct ValidationLog {
    messages: Mutex<Vec<String>>,
    /// How many messages an error has already reported.
    reported: std::sync::atomic::AtomicUsize,
}

impl ValidationLog {
    /// Every warning and error recorded so far.
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    fn push(&self, message: String) {
        if let Ok(mut messages) = self.messages.lock() {
            messages.push(message);
        }
    }
}

/// How to create the instance.
#[derive(Clone, Debug, Default)]
pub struct InstanceDesc {
    /// Enable `VK_LAYER_KHRONOS_validation` with synchronization validation.
    pub validation: bool,
    /// Extra instance extensions (a window surface's, for example).
    pub extensions: Vec<&'static CStr>,
}

/// Owns the `VkInstance` and its debug messenger.
pub struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    pub debug_utils: Option<ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
    /// Kept alive for the messenger's user-data pointer.
    log: Arc<ValidationLog>,
    validation: bool,
}

impl Instance {
    pub fn new(desc: &InstanceDesc) -> Result<Self> {
        // SAFETY: loading the system's Vulkan loader; symbols are resolved by ash.
        let entry = unsafe { ash::Entry::load().map_err(|e| crate::Error::Loader(e.to_string()))? };
        // The loader may load and unload drivers and layers while it answers these
        // (see `loader_lock`).
        let loader = super::loader_lock();
        // SAFETY: `entry` holds the loaded Vulkan loader, and these global queries take
        // no handles; the loader lock is held.
        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .vk("vkEnumerateInstanceLayerProperties");
        // SAFETY: as above: a global query on the loaded loader, under the loader lock.
        let available = unsafe { entry.enumerate_instance_extension_properties(None) }
            .vk("vkEnumerateInstanceExtensionProperties");
        drop(loader);
        let (layers, available) = (layers?, available?);
        let has_layer = |name: &CStr| {
            layers
                .iter()
                .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == name))
        };
        if desc.validation && !has_layer(VALIDATION_LAYER) {
            return Err(crate::Error::ValidationLayerMissing);
        }
        let has_debug_utils = available.iter().any(|e| {
            e.extension_name_as_c_str()
                .is_ok_and(|n| n == ext::debug_utils::NAME)
        });

        let mut extensions: Vec<*const c_char> =
            desc.extensions.iter().map(|e| e.as_ptr()).collect();
        if has_debug_utils {
            extensions.push(ext::debug_utils::NAME.as_ptr());
        }
        let layer_names: Vec<*const c_char> = if desc.validation {
            vec![VALIDATION_LAYER.as_ptr()]
        } else {
            Vec::new()
        };

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"fur")
            .engine_name(c"fur")
            .api_version(vk::API_VERSION_1_3);
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
        let log = Arc::new(ValidationLog::default());
        let mut messenger_info = messenger_create_info(&log);
        let mut create_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layer_names)
            .enabled_extension_names(&extensions);
        if desc.validation {
            create_info = create_info.push_next(&mut validation_features);
        }
        if has_debug_utils {
            // Also reports problems during vkCreateInstance/vkDestroyInstance.
            create_info = create_info.push_next(&mut messenger_info);
        }
        let loader = super::loader_lock();
        // SAFETY: the create info and all it points at (application info, layer and
        // extension names, the pNext chain whose messenger info carries a pointer to
        // `log`, which the Instance keeps) live on this stack frame through the call;
        // the loader lock is held.
        let raw = unsafe { entry.create_instance(&create_info, None) }.vk("vkCreateInstance")?;
        drop(loader);

        let (debug_utils, messenger) = if has_debug_utils {
            let debug_utils = ext::debug_utils::Instance::new(&entry, &raw);
            let info = messenger_create_info(&log);
            // SAFETY: `raw` was just created with VK_EXT_debug_utils enabled
            // (`has_debug_utils`); the user data in `info` points at `log`, which the
            // Instance holds for as long as the messenger lives.
            match unsafe { debug_utils.create_debug_utils_messenger(&info, None) } {
                Ok(messenger) => (Some(debug_utils), messenger),
                Err(result) => {
                    // SAFETY: `raw` was just created and nothing else was created from
                    // it (the messenger failed); it is not used after this.
                    unsafe { raw.destroy_instance(None) };
                    return Err(crate::error::vulkan(
                        "vkCreateDebugUtilsMessengerEXT",
                        result,
                    ));
                }
            }
        } else {
            (None, vk::DebugUtilsMessengerEXT::null())
        };
        Ok(Self {
            entry,
            raw,
            debug_utils,
            messenger,
            log,
            validation: desc.validation,
        })
    }

    /// Whether the validation layer is on.
    pub fn validation_enabled(&self) -> bool {
        self.validation
    }

    /// Whether a debug messenger collects the layer's messages (`VK_EXT_debug_utils`
    /// was available). Without one, [`Instance::validation_messages`] stays empty
    /// whatever the layer finds: the GPU tests refuse to run then.
    pub fn has_debug_messenger(&self) -> bool {
        self.debug_utils.is_some()
    }

    /// Validation warnings and errors reported so far.
    pub fn validation_messages(&self) -> Vec<String> {
        self.log.messages()
    }

    /// An error if the validation layer reported anything so far.
    pub fn check_validation(&self) -> Result<()> {
        let messages = self.validation_messages();
        self.log
            .reported
            .store(messages.len(), std::sync::atomic::Ordering::SeqCst);
        match messages.first() {
            None => Ok(()),
            Some(first) => Err(crate::Error::Validation {
                count: messages.len(),
                first: first.clone(),
            }),
        }
    }

    pub fn raw(&self) -> &ash::Instance {
        &self.raw
    }

    pub fn entry(&self) -> &ash::Entry {
        &self.entry
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        let loader = super::loader_lock();
        // SAFETY: every device and surface holds an `Arc<Instance>`, so none is left;
        // the messenger was created from this instance and goes first; the loader lock
        // is held.
        unsafe {
            if let Some(debug_utils) = &self.debug_utils {
                debug_utils.destroy_debug_utils_messenger(self.messenger, None);
            }
            self.raw.destroy_instance(None);
        }
        drop(loader);
        // What the layer said while the device was torn down (objects left alive, for
        // one) comes after every check: say it here rather than lose it.
        let reported = self.log.reported.load(std::sync::atomic::Ordering::SeqCst);
        for message in self.log.messages().iter().skip(reported) {
            eprintln!("validation at teardown: {message}");
        }
    }
}

fn messenger_create_info(
    log: &Arc<ValidationLog>,
) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(debug_callback))
        .user_data(Arc::as_ptr(log) as *mut c_void)
}

/// Records validation messages. Never panics and always returns `VK_FALSE`.
///
/// # Safety
///
/// Only for the validation layer to call, as `messenger_create_info` registers it:
/// `data` is null or a valid callback-data struct for the call's duration, and
/// `user_data` is null or the `ValidationLog` that the `Instance` owning the messenger
/// keeps alive.
unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    let _ = std::panic::catch_unwind(|| {
        if data.is_null() {
            return;
        }
        // SAFETY: the layer passes a valid callback-data struct for the call's duration.
        let data = unsafe { &*data };
        let message = if data.p_message.is_null() {
            String::from("(no message)")
        } else {
            // SAFETY: non-null (checked above); the layer passes a NUL-terminated
            // message that stays valid for the callback's duration.
            unsafe { CStr::from_ptr(data.p_message) }
                .to_string_lossy()
                .into_owned()
        };
        // The loader itself reports harmless GENERAL warnings (e.g. about manifest files);
        // only validation and performance reports count against a run.
        let counts = kind.intersects(
            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        ) || severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR);
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            log::error!("[vulkan {kind:?}] {message}");
        } else {
            log::warn!("[vulkan {kind:?}] {message}");
        }
        if counts && !user_data.is_null() {
            // SAFETY: user_data points at the ValidationLog kept alive by the Instance.
            let log = unsafe { &*(user_data as *const ValidationLog) };
            log.push(format!("{severity:?} {kind:?}: {message}"));
        }
    });
    vk::FALSE
}
