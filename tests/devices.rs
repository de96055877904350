//! Device selection: `fur devices` lists every Vulkan device and marks the default;
//! `--device INDEX|NAME` (or `FUR_DEVICE`) chooses one, and a bad choice is refused with
//! the problem and the list, never a panic. The choosing logic itself is unit-tested
//! with made-up device lists in `src/gpu/choice.rs`.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fur(args: &[&str], env: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_fur"));
    command.args(args).env("RUST_BACKTRACE", "0");
    match env {
        Some(value) => command.env("FUR_DEVICE", value),
        None => command.env_remove("FUR_DEVICE"),
    };
    command.output().expect("the fur binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("devices")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A tiny validated render on the device `choice` names, into `out`.
fn render_on(choice: &str, out: &Path, env: Option<&str>) -> Output {
    let on = ["render", "--validate", "--device", choice];
    let args = [
        on.as_slice(),
        &common::SMALL,
        &["--out", out.to_str().unwrap()],
    ]
    .concat();
    fur(&args, env)
}

/// The devices as the library lists them (the same list `fur devices` prints).
fn devices() -> fur_gpu::gpu::DeviceList {
    let list = fur_gpu::gpu::list_devices().expect("the Vulkan devices can be listed");
    assert!(!list.devices.is_empty(), "no Vulkan device (see README)");
    list
}

/// A case-changed part of a name only the default device has: `LLVMpipe` on lavapipe.
fn name_choice(list: &fur_gpu::gpu::DeviceList) -> String {
    let default = &list.devices[list.default.expect("a usable device")];
    let lavapipe = list
        .devices
        .iter()
        .filter(|d| d.name.to_lowercase().contains("llvmpipe"))
        .count();
    if default.name.to_lowercase().contains("llvmpipe") && lavapipe == 1 {
        "LLVMpipe".into()
    } else {
        default.name.to_uppercase()
    }
}

#[test]
fn fur_devices_lists_every_device_and_marks_the_default() {
    let list = devices();
    let out = fur(&["devices"], None);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "fur devices failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<&str> = stdout
        .lines()
        .skip_while(|l| !l.contains("index"))
        .skip(1)
        .take(list.devices.len())
        .collect();
    assert_eq!(rows.len(), list.devices.len(), "{stdout}");
    for (row, device) in rows.iter().zip(&list.devices) {
        let mut cells = row[1..].split_whitespace();
        assert_eq!(
            cells.next(),
            Some(device.index.to_string().as_str()),
            "{row}"
        );
        assert_eq!(cells.next(), Some(device.kind.name()), "{row}");
        assert!(
            row.contains(&device.name) && row.contains(&device.driver),
            "{row}"
        );
        let marked = row.starts_with('*');
        assert_eq!(marked, list.default == Some(device.index), "{stdout}");
        if marked {
            assert!(row.contains("usable, the default"), "{row}");
        }
    }
    assert_eq!(
        rows.iter().filter(|r| r.starts_with('*')).count(),
        1,
        "{stdout}"
    );
}

#[test]
fn a_device_is_chosen_by_index_and_by_any_case_part_of_its_name() {
    let list = devices();
    let default = list.default.expect("a usable device");
    let dir = scratch("chosen");
    let choices = [default.to_string(), name_choice(&list)];
    for (i, choice) in choices.iter().enumerate() {
        let image = dir.join(format!("{i}.png"));
        let out = render_on(choice, &image, None);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.success(),
            "--device {choice:?} failed:\n{stderr}"
        );
        assert!(image.exists(), "--device {choice:?}: no image");
    }
    // The library takes the same choices, with the validation layer on.
    for choice in &choices {
        let device = fur_gpu::gpu::headless_on(true, Some(choice)).expect("the chosen device");
        assert_eq!(device.info().name, list.devices[default].name);
        assert!(!device.info().driver.is_empty());
        common::assert_clean(&device);
        fur_gpu::gpu::shut_down(device).unwrap();
    }
    // `--device` wins over FUR_DEVICE.
    let image = dir.join("over_env.png");
    let out = render_on(&default.to_string(), &image, Some("nosuchgpu"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_bad_choice_is_refused_with_the_problem_and_the_device_list() {
    let list = devices();
    let beyond = list.devices.len().max(7).to_string();
    let dir = scratch("refused");
    let image = dir.join("never.png");
    let cases = [
        (beyond.as_str(), None, format!("no device {beyond}")),
        ("nosuchgpu", None, "nosuchgpu".into()),
        ("", None, "empty".into()),
        ("  ", None, "empty".into()),
    ];
    let check = |what: &str, out: &Output, needle: &str| {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{what} succeeded");
        assert!(!stderr.contains("panicked"), "{what} panicked:\n{stderr}");
        assert!(
            stderr.contains(needle),
            "{what}: no `{needle}` in:\n{stderr}"
        );
        assert!(
            stderr.contains("Vulkan devices"),
            "{what}: no list:\n{stderr}"
        );
        for device in &list.devices {
            assert!(
                stderr.contains(&device.name),
                "{what}: {} unlisted",
                device.name
            );
        }
    };
    for (choice, env, needle) in &cases {
        let out = render_on(choice, &image, *env);
        check(&format!("--device {choice:?}"), &out, needle);
    }
    assert!(!image.exists(), "an image was written");
    // FUR_DEVICE chooses too, and the error says where the choice came from.
    let out = fur(
        &["render", "--out", image.to_str().unwrap()],
        Some("nosuchgpu"),
    );
    check("FUR_DEVICE=nosuchgpu", &out, "FUR_DEVICE");
    // The benchmark refuses the same way, before measuring anything.
    let bench_dir = dir.join("bench");
    let out = fur(
        &[
            "bench",
            "--quick",
            "--only",
            "frame",
            "--device",
            "nosuchgpu",
            "--out-dir",
            bench_dir.to_str().unwrap(),
        ],
        None,
    );
    check("bench --device nosuchgpu", &out, "nosuchgpu");
    assert!(!bench_dir.join("results.csv").exists());
}
