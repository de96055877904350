//! The physical devices: what each offers, whether fur can run on it (and why not),
//! and the one a run uses (`choice.rs` decides which).

use std::sync::Arc;

use ash::vk;

use super::choice::{DeviceEntry, DeviceKind, DeviceList};
use super::device::{DeviceInfo, PresentTarget};
use super::instance::{Instance, InstanceDesc};
use crate::error::{Error, Result, VkContext};

/// A physical device as probed: its listing, and what device creation needs.
struct Probe {
    entry: DeviceEntry,
    physical: vk::PhysicalDevice,
    /// The queue family and the device's properties, when it is usable.
    usable: Option<(u32, DeviceInfo)>,
}

/// Every physical device, in `vkEnumeratePhysicalDevices`' order, with the default
/// marked. Opens its own instance (no validation): `fur devices`.
pub fn list_devices() -> Result<DeviceList> {
    let instance = Arc::new(Instance::new(&InstanceDesc::default())?);
    let probes = probe_all(&instance, None)?;
    Ok(DeviceList::new(
        probes.into_iter().map(|p| p.entry).collect(),
    ))
}

/// The device `choice` names (`--device INDEX|NAME`), or the best usable one: the
/// physical device, its graphics+compute queue family and its properties. A bad choice
/// is an error naming the problem, with the device list.
pub(super) fn select_physical_device(
    instance: &Instance,
    present: Option<&PresentTarget<'_>>,
    choice: Option<&str>,
) -> Result<(vk::PhysicalDevice, u32, DeviceInfo)> {
    let mut probes = probe_all(instance, present)?;
    if probes.is_empty() {
        return Err(Error::NoSuitableDevice(
            "  the Vulkan loader reports no devices (is a driver such as mesa-vulkan-drivers installed?)"
                .into(),
        ));
    }
    let list = DeviceList::new(probes.iter().map(|p| p.entry.clone()).collect());
    let index = match list.choose(choice) {
        Ok(index) => index,
        Err(_) if choice.is_none() => {
            let rejections: Vec<String> = probes
                .iter()
                .filter_map(|p| Some(format!("  {}: {}", p.entry.name, p.entry.problem.as_ref()?)))
                .collect();
            return Err(Error::NoSuitableDevice(rejections.join("\n")));
        }
        Err(problem) => return Err(Error::DeviceChoice(format!("{problem}\n{list}"))),
    };
    let probe = probes.swap_remove(index);
    let (family, info) = probe.usable.expect("the choice is a usable device");
    Ok((probe.physical, family, info))
}

fn probe_all(instance: &Instance, present: Option<&PresentTarget<'_>>) -> Result<Vec<Probe>> {
    // The loader unloads drivers that find no device while it enumerates (see
    // `loader_lock`).
    let loader = super::loader_lock();
    let devices =
        // SAFETY: the instance is alive (borrowed) and the loader lock is held.
        unsafe { instance.raw.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    drop(loader);
    Ok(devices
        .into_iter()
        .enumerate()
        .map(|(index, physical)| probe(instance, present, index, physical))
        .collect())
}

/// What fur needs of `physical`, and what it offers.
fn probe(
    instance: &Instance,
    present: Option<&PresentTarget<'_>>,
    index: usize,
    physical: vk::PhysicalDevice,
) -> Probe {
    let raw = &instance.raw;
    // SAFETY: `physical` was enumerated from this instance, which is alive (borrowed).
    let props = unsafe { raw.get_physical_device_properties(physical) };
    let name = props
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|_| "unnamed device".into());
    let version = props.api_version;
    let at_least =
        |minor| vk::api_version_major(version) > 1 || vk::api_version_minor(version) >= minor;
    let driver = if at_least(2) {
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
        // SAFETY: `physical` comes from this instance and reports Vulkan 1.2 or later,
        // so the driver-properties struct is a valid link of the chain; `props2` and
        // `driver` live through the call.
        unsafe { raw.get_physical_device_properties2(physical, &mut props2) };
        let text = |t: std::result::Result<&std::ffi::CStr, _>| {
            t.map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        let (name, info) = (
            text(driver.driver_name_as_c_str()),
            text(driver.driver_info_as_c_str()),
        );
        match (name.is_empty(), info.is_empty()) {
            (true, true) => "unknown".into(),
            (false, false) => format!("{name}: {info}"),
            _ => format!("{name}{info}"),
        }
    } else {
        "unknown (Vulkan 1.1 or older)".into()
    };
    let subgroup_size = if at_least(1) {
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut subgroup);
        // SAFETY: `physical` comes from this instance and reports Vulkan 1.1 or later,
        // so the subgroup-properties struct is a valid link of the chain; `props2` and
        // `subgroup` live through the call.
        unsafe { raw.get_physical_device_properties2(physical, &mut props2) };
        subgroup.subgroup_size.max(1)
    } else {
        1
    };
    // SAFETY: `physical` was enumerated from this instance.
    let features = unsafe { raw.get_physical_device_features(physical) };
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut f13)
        .push_next(&mut f12);
    let supports_13 = at_least(3);
    if supports_13 {
        // SAFETY: `physical` reports Vulkan 1.3, so the 1.2 and 1.3 feature structs are
        // valid links of the chain; the chain lives on this stack frame through the
        // call.
        unsafe { raw.get_physical_device_features2(physical, &mut features2) };
    }
    let mut missing = missing_features(supports_13, &features, &f12, &f13);
    // SAFETY: `physical` was enumerated from this instance.
    let families = unsafe { raw.get_physical_device_queue_family_properties(physical) };
    let family = families.iter().enumerate().find_map(|(i, f)| {
        let i = i as u32;
        let flags = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        // SAFETY: `i` indexes `physical`'s queue families; the surface and its loader
        // come from this instance, and the caller keeps the surface alive while devices
        // are probed.
        let presents = present.is_none_or(|p| unsafe {
            p.surface_fn
                .get_physical_device_surface_support(physical, i, p.surface)
                .unwrap_or(false)
        });
        (f.queue_flags.contains(flags) && presents).then_some((i, f.timestamp_valid_bits))
    });
    if family.is_none() {
        missing.push(if present.is_some() {
            "a graphics+compute queue that can present to the window".into()
        } else {
            "a graphics+compute queue".into()
        });
    }
    let entry = DeviceEntry {
        index,
        name: name.clone(),
        kind: DeviceKind::from_vk(props.device_type),
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(version),
            vk::api_version_minor(version),
            vk::api_version_patch(version)
        ),
        driver: driver.clone(),
        problem: (!missing.is_empty()).then(|| format!("lacks {}", missing.join(", "))),
    };
    let usable = family
        .filter(|_| missing.is_empty())
        .map(|(family, timestamp_bits)| {
            let info = DeviceInfo {
                name,
                driver,
                device_type: props.device_type,
                limits: props.limits,
                timestamp_period: props.limits.timestamp_period,
                timestamps: timestamp_bits > 0,
                pipeline_statistics: features.pipeline_statistics_query == vk::TRUE,
                vertex_pipeline_stores: features.vertex_pipeline_stores_and_atomics == vk::TRUE,
                subgroup_size,
            };
            (family, info)
        });
    Probe {
        entry,
        physical,
        usable,
    }
}

/// The features the renderer needs that a device lacks, by their Vulkan names.
fn missing_features(
    supports_13: bool,
    features: &vk::PhysicalDeviceFeatures,
    f12: &vk::PhysicalDeviceVulkan12Features,
    f13: &vk::PhysicalDeviceVulkan13Features,
) -> Vec<String> {
    let mut missing = Vec::new();
    if !supports_13 {
        missing.push("Vulkan 1.3".to_string());
    } else {
        for (name, supported) in [
            ("dynamicRendering", f13.dynamic_rendering),
            ("synchronization2", f13.synchronization2),
            ("hostQueryReset", f12.host_query_reset),
        ] {
            if supported == vk::FALSE {
                missing.push(name.to_string());
            }
        }
    }
    for (name, supported) in [
        ("tessellationShader", features.tessellation_shader),
        ("geometryShader", features.geometry_shader),
    ] {
        if supported == vk::FALSE {
            missing.push(name.to_string());
        }
    }
    missing
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_without_tessellation_or_geometry_shaders_is_named_as_lacking_them() {
        let f12 = vk::PhysicalDeviceVulkan12Features::default().host_query_reset(true);
        let f13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true);
        let full = vk::PhysicalDeviceFeatures::default()
            .tessellation_shader(true)
            .geometry_shader(true);
        assert!(missing_features(true, &full, &f12, &f13).is_empty());
        let none = vk::PhysicalDeviceFeatures::default();
        assert_eq!(
            missing_features(true, &none, &f12, &f13),
            ["tessellationShader", "geometryShader"]
        );
        let no_geometry = full.geometry_shader(false);
        assert_eq!(
            missing_features(true, &no_geometry, &f12, &f13),
            ["geometryShader"]
        );
        assert_eq!(missing_features(false, &full, &f12, &f13), ["Vulkan 1.3"]);
        let old13 = vk::PhysicalDeviceVulkan13Features::default();
        assert_eq!(
            missing_features(true, &full, &f12, &old13),
            ["dynamicRendering", "synchronization2"]
        );
    }
}
