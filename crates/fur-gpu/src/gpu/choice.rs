//! Which physical device to use: the default (discrete over integrated over virtual over
//! CPU drivers) or the one `--device INDEX|NAME` names, and the device list shown by
//! `fur devices` and by every refused choice. Pure logic over plain data; the Vulkan
//! side is in `physical.rs`.

use std::fmt;

use ash::vk;

/// What kind of device a physical device is (`VkPhysicalDeviceType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeviceKind {
    Discrete,
    Integrated,
    Virtual,
    Cpu,
    Other,
}

impl DeviceKind {
    pub fn from_vk(kind: vk::PhysicalDeviceType) -> Self {
        match kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => Self::Discrete,
            vk::PhysicalDeviceType::INTEGRATED_GPU => Self::Integrated,
            vk::PhysicalDeviceType::VIRTUAL_GPU => Self::Virtual,
            vk::PhysicalDeviceType::CPU => Self::Cpu,
            _ => Self::Other,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Discrete => "discrete",
            Self::Integrated => "integrated",
            Self::Virtual => "virtual",
            Self::Cpu => "cpu",
            Self::Other => "other",
        }
    }

    /// Higher is preferred by default; ties go to the lower index.
    fn rank(self) -> u32 {
        match self {
            Self::Discrete => 4,
            Self::Integrated => 3,
            Self::Virtual => 2,
            Self::Cpu | Self::Other => 1,
        }
    }
}

impl fmt::Display for DeviceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A device as the choice sees it: its name, kind, and why fur cannot use it (`None`:
/// usable).
#[derive(Clone, Copy, Debug)]
pub struct Candidate<'a> {
    pub name: &'a str,
    pub kind: DeviceKind,
    pub problem: Option<&'a str>,
}

/// The index of the device to use: the best usable one by kind when `choice` is `None`,
/// else the device `choice` names: a number is an index into `candidates`, anything
/// else a case-insensitive part of exactly one usable device's name. The error says
/// what is wrong with the choice (the caller adds the device list).
pub fn choose(candidates: &[Candidate<'_>], choice: Option<&str>) -> Result<usize, String> {
    let usable = |i: &usize| candidates[*i].problem.is_none();
    let Some(choice) = choice else {
        return (0..candidates.len())
            .filter(usable)
            .min_by_key(|&i| (std::cmp::Reverse(candidates[i].kind.rank()), i))
            .ok_or_else(|| "no device has everything fur needs".to_string());
    };
    let wanted = choice.trim();
    if wanted.is_empty() {
        return Err("the device choice is empty: give a device's index or part of its name".into());
    }
    let describe = |i: usize| format!("{i} ({})", candidates[i].name);
    if wanted.bytes().all(|b| b.is_ascii_digit()) {
        let index = wanted.parse::<usize>().unwrap_or(usize::MAX);
        return match candidates.get(index) {
            None if candidates.is_empty() => {
                Err(format!("there is no device {wanted}: there are no devices"))
            }
            None if candidates.len() == 1 => {
                Err(format!("there is no device {wanted}: the only device is 0"))
            }
            None => Err(format!(
                "there is no device {wanted}: the devices are numbered 0 to {}",
                candidates.len() - 1
            )),
            Some(Candidate {
                problem: Some(problem),
                ..
            }) => Err(format!(
                "device {} cannot run fur: it {problem}",
                describe(index)
            )),
            Some(_) => Ok(index),
        };
    }
    let needle = wanted.to_lowercase();
    let matches: Vec<usize> = (0..candidates.len())
        .filter(|&i| candidates[i].name.to_lowercase().contains(&needle))
        .collect();
    let usable_matches: Vec<usize> = matches.iter().copied().filter(|i| usable(i)).collect();
    match (usable_matches.as_slice(), matches.as_slice()) {
        ([one], _) => Ok(*one),
        ([], []) => Err(format!("no device's name contains `{wanted}`")),
        ([], unusable) => Err(format!(
            "`{wanted}` names only devices fur cannot run on: {}",
            unusable
                .iter()
                .map(|&i| format!(
                    "{}, which {}",
                    describe(i),
                    candidates[i].problem.unwrap_or("is unusable")
                ))
                .collect::<Vec<_>>()
                .join("; ")
        )),
        (several, _) => Err(format!(
            "`{wanted}` matches {} devices: {}; choose one by its index",
            several.len(),
            several
                .iter()
                .map(|&i| describe(i))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// One physical device, as `fur devices` lists it.
#[derive(Clone, Debug)]
pub struct DeviceEntry {
    /// Its place in `vkEnumeratePhysicalDevices`' order.
    pub index: usize,
    pub name: String,
    pub kind: DeviceKind,
    /// The Vulkan version it supports, `major.minor.patch`.
    pub api_version: String,
    /// The driver's name and information (`VkPhysicalDeviceDriverProperties`).
    pub driver: String,
    /// Why fur cannot use it; `None`: usable.
    pub problem: Option<String>,
}

impl DeviceEntry {
    pub fn candidate(&self) -> Candidate<'_> {
        Candidate {
            name: &self.name,
            kind: self.kind,
            problem: self.problem.as_deref(),
        }
    }
}

/// Every physical device, the one fur uses by default and the one a choice names.
#[derive(Clone, Debug)]
pub struct DeviceList {
    pub devices: Vec<DeviceEntry>,
    /// The index of the default device; `None` when no device is usable.
    pub default: Option<usize>,
    /// The index of the device a choice named ([`DeviceList::with_choice`]).
    pub chosen: Option<usize>,
}

impl DeviceList {
    pub fn new(devices: Vec<DeviceEntry>) -> Self {
        let default = choose(&candidates(&devices), None).ok();
        Self {
            devices,
            default,
            chosen: None,
        }
    }

    /// The index of the device `choice` names (see [`choose`]), or the default.
    pub fn choose(&self, choice: Option<&str>) -> Result<usize, String> {
        choose(&candidates(&self.devices), choice)
    }

    /// The list with the device `choice` names marked instead of the default; the
    /// error is the problem with the choice followed by the list.
    pub fn with_choice(mut self, choice: Option<&str>) -> Result<Self, String> {
        if choice.is_some() {
            match self.choose(choice) {
                Ok(index) => self.chosen = Some(index),
                Err(problem) => return Err(format!("{problem}\n{self}")),
            }
        }
        Ok(self)
    }

    /// The device a run uses: the chosen one, else the default.
    fn marked(&self) -> Option<usize> {
        self.chosen.or(self.default)
    }
}

fn candidates(devices: &[DeviceEntry]) -> Vec<Candidate<'_>> {
    devices.iter().map(DeviceEntry::candidate).collect()
}

impl fmt::Display for DeviceList {
    /// A table: marker, index, type, Vulkan version, name, driver, usability.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let header = ["index", "type", "Vulkan", "name", "driver", "fur"];
        let rows: Vec<[String; 6]> = self
            .devices
            .iter()
            .map(|d| {
                let mut usable = match &d.problem {
                    Some(problem) => format!("not usable: {problem}"),
                    None => "usable".into(),
                };
                if self.default == Some(d.index) {
                    usable.push_str(", the default");
                }
                if self.chosen == Some(d.index) {
                    usable.push_str(", chosen");
                }
                [
                    d.index.to_string(),
                    d.kind.to_string(),
                    d.api_version.clone(),
                    d.name.clone(),
                    d.driver.clone(),
                    usable,
                ]
            })
            .collect();
        let mut widths = header.map(|h| h.chars().count());
        for row in &rows {
            for (w, cell) in widths.iter_mut().zip(row) {
                *w = (*w).max(cell.chars().count());
            }
        }
        writeln!(
            f,
            "Vulkan devices (* = the one fur uses{}):",
            if self.chosen.is_some() {
                ", as chosen"
            } else {
                " by default"
            }
        )?;
        let line = |f: &mut fmt::Formatter<'_>, mark: &str, cells: &[&str]| {
            let padded: Vec<String> = cells
                .iter()
                .zip(widths)
                .map(|(c, w)| format!("{c:<w$}"))
                .collect();
            writeln!(f, "{mark} {}", padded.join("  ").trim_end())
        };
        line(f, " ", &header)?;
        for (device, row) in self.devices.iter().zip(&rows) {
            let mark = if self.marked() == Some(device.index) {
                "*"
            } else {
                " "
            };
            line(f, mark, &row.each_ref().map(String::as_str))?;
        }
        if self.devices.is_empty() {
            writeln!(
                f,
                "  (none: the Vulkan loader reports no devices; is a driver such as \
                 mesa-vulkan-drivers installed?)"
            )?;
        }
        write!(
            f,
            "By default fur takes the first usable device of the best kind (discrete,\n\
             integrated, virtual, cpu); --device INDEX|NAME or FUR_DEVICE chooses another."
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use DeviceKind::*;

    fn devices(
        list: &[(&'static str, DeviceKind, Option<&'static str>)],
    ) -> Vec<Candidate<'static>> {
        list.iter()
            .map(|&(name, kind, problem)| Candidate {
                name,
                kind,
                problem,
            })
            .collect()
    }

    #[test]
    fn by_default_discrete_beats_integrated_beats_cpu() {
        let all = devices(&[
            ("llvmpipe (LLVM 15.0.6, 256 bits)", Cpu, None),
            ("Intel(R) UHD Graphics 770", Integrated, None),
            ("NVIDIA GeForce RTX 4070", Discrete, None),
        ]);
        assert_eq!(choose(&all, None), Ok(2));
        assert_eq!(choose(&all[..2], None), Ok(1));
        assert_eq!(choose(&all[..1], None), Ok(0));
        // An unusable discrete GPU is passed over; ties go to the first.
        let mixed = devices(&[
            ("Old GPU", Discrete, Some("lacks geometryShader")),
            ("llvmpipe", Cpu, None),
            ("Virtual GPU", Virtual, None),
            ("Second virtual GPU", Virtual, None),
        ]);
        assert_eq!(choose(&mixed, None), Ok(2));
        let none = devices(&[("Old GPU", Discrete, Some("lacks geometryShader"))]);
        assert!(choose(&none, None).is_err());
        assert!(choose(&[], None).is_err());
    }

    #[test]
    fn a_device_is_chosen_by_index_or_by_any_case_part_of_its_name() {
        let all = devices(&[
            ("llvmpipe (LLVM 15.0.6, 256 bits)", Cpu, None),
            ("NVIDIA GeForce RTX 4070", Discrete, None),
        ]);
        assert_eq!(choose(&all, Some("0")), Ok(0));
        assert_eq!(choose(&all, Some("1")), Ok(1));
        assert_eq!(choose(&all, Some("LLVMpipe")), Ok(0));
        assert_eq!(choose(&all, Some("rtx")), Ok(1));
        // A name that matches a usable and an unusable device means the usable one.
        let two = devices(&[
            ("AMD Radeon (old)", Discrete, Some("lacks Vulkan 1.3")),
            ("AMD Radeon RX 7900", Discrete, None),
        ]);
        assert_eq!(choose(&two, Some("radeon")), Ok(1));
    }

    #[test]
    fn bad_choices_are_refused_saying_why() {
        let all = devices(&[
            ("NVIDIA GeForce RTX 4070", Discrete, None),
            ("NVIDIA GeForce GTX 1080", Discrete, None),
            (
                "Old GPU",
                Integrated,
                Some("lacks tessellationShader, geometryShader"),
            ),
        ]);
        let err = choose(&all, Some("7")).unwrap_err();
        assert!(
            err.contains("no device 7") && err.contains("0 to 2"),
            "{err}"
        );
        let err = choose(&all, Some("nosuchgpu")).unwrap_err();
        assert!(err.contains("nosuchgpu"), "{err}");
        for empty in ["", "  "] {
            let err = choose(&all, Some(empty)).unwrap_err();
            assert!(err.contains("empty"), "{err}");
        }
        let err = choose(&all, Some("geforce")).unwrap_err();
        assert!(
            err.contains("2 devices")
                && err.contains("0 (NVIDIA GeForce RTX 4070)")
                && err.contains("1 (NVIDIA GeForce GTX 1080)"),
            "{err}"
        );
        for choice in ["2", "old"] {
            let err = choose(&all, Some(choice)).unwrap_err();
            assert!(
                err.contains("Old GPU") && err.contains("lacks tessellationShader, geometryShader"),
                "{choice}: {err}"
            );
        }
        assert!(choose(&all, Some("99999999999999999999999")).is_err());
    }

    #[test]
    fn the_list_marks_the_default_and_says_why_a_device_is_unusable() {
        let entry = |index, name: &str, kind, problem: Option<&str>| DeviceEntry {
            index,
            name: name.into(),
            kind,
            api_version: "1.3.255".into(),
            driver: "some driver".into(),
            problem: problem.map(Into::into),
        };
        let list = DeviceList::new(vec![
            entry(0, "llvmpipe", Cpu, None),
            entry(1, "Old GPU", Discrete, Some("lacks geometryShader")),
            entry(2, "RTX", Discrete, None),
        ]);
        assert_eq!(list.default, Some(2));
        let text = list.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[1].contains("index") && lines[1].contains("type"),
            "{text}"
        );
        assert!(
            lines[2].starts_with("  0") && lines[2].contains("cpu"),
            "{text}"
        );
        assert!(
            lines[3].contains("not usable: lacks geometryShader"),
            "{text}"
        );
        assert!(
            lines[4].starts_with("* 2") && lines[4].contains("the default"),
            "{text}"
        );
        let chosen = list.clone().with_choice(Some("LLVM")).unwrap().to_string();
        let lines: Vec<&str> = chosen.lines().collect();
        assert!(lines[0].contains("as chosen"), "{chosen}");
        assert!(
            lines[2].starts_with("* 0") && lines[2].ends_with("usable, chosen"),
            "{chosen}"
        );
        assert!(
            lines[4].starts_with("  2") && lines[4].contains("the default"),
            "{chosen}"
        );
        let refused = list.with_choice(Some("old")).unwrap_err();
        assert!(refused.contains("lacks geometryShader") && refused.contains("Vulkan devices"));
    }
}
