//! The settings' definitions (`crates/fur-core/src/scene_file/keys/`, and beside the
//! fields they set): every setting's flag and its scene-file key set the same field its
//! definition reads, to a value that differs from the default; saved scenes hold every
//! setting; flags and keys are unique; the docs' table is the one the definitions
//! make; a setting a shader reads lives in three code files.

use std::path::{Path, PathBuf};

use clap::{Args, FromArgMatches};
use fur::setting_args::SettingArgs;
use fur_core::scene::ModelSpec;
use fur_core::scene_file::{docs, Flag, Kind, Scene, SceneFile, Setting, Value, GROUPS};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("settings");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn every_setting() -> impl Iterator<Item = (&'static str, &'static Setting)> {
    GROUPS
        .iter()
        .flat_map(|g| g.settings.iter().map(move |s| (g.section, s)))
}

/// A valid value of `setting` other than its default in `scene`.
fn other_value(setting: &Setting, scene: &Scene) -> Value {
    let default = setting.get(scene);
    let value = match (setting.kind, &default) {
        (
            Kind::Number {
                min, max, min_open, ..
            },
            _,
        ) => {
            let current = match default {
                Value::Number(v) => v,
                _ => f64::NAN,
            };
            let lo = if min_open {
                min + (max.min(1e3) - min) / 4.0
            } else {
                min
            };
            let hi = max.min(lo.abs().max(1.0) * 1e3);
            let mid = ((lo + hi) / 2.0 * 64.0).round() / 64.0;
            Value::Number(if mid != current { mid } else { lo })
        }
        (Kind::Integer { min, max, .. }, Value::Integer(v)) => {
            Value::Integer(if *v != max { max } else { min })
        }
        (Kind::OneOf(allowed), v) => {
            Value::Integer(*allowed.iter().find(|&&n| Value::Integer(n) != *v).unwrap())
        }
        (Kind::Bool, Value::Bool(b)) => Value::Bool(!b),
        (Kind::Bool, Value::Unset) => Value::Bool(false),
        (Kind::Choice(names), v) => Value::Text(
            names
                .iter()
                .find(|&&n| Value::Text(n.into()) != *v)
                .unwrap()
                .to_string(),
        ),
        (Kind::Vector { .. } | Kind::Colour { .. }, Value::Vector(v)) => {
            Value::Vector(*v + glam::Vec3::new(0.25, 0.5, 0.125))
        }
        (Kind::Vector { .. }, Value::Unset) => Value::Vector(glam::Vec3::new(1.0, 2.0, 3.0)),
        // Absolute: a relative groom path in a scene file is read relative to the file
        // (tests/grooms.rs checks that).
        (Kind::Text, _) => Value::Text("/walk".into()),
        // A point, written as a scene file would write it back.
        (Kind::Place, _) => Value::Text("0.5,1,-2".into()),
        (kind, v) => panic!("{setting:?}: no other value for {kind:?} from {v:?}"),
    };
    setting
        .check(&value)
        .unwrap_or_else(|e| panic!("{setting:?}: {value:?}: {e}"));
    value
}

/// `value` as a command-line argument and as a TOML value.
fn spelled(value: &Value) -> (String, String) {
    match value {
        Value::Number(v) => (format!("{v}"), format!("{v:?}")),
        Value::Integer(v) => (v.to_string(), v.to_string()),
        Value::Bool(b) => (b.to_string(), b.to_string()),
        Value::Vector(v) => (
            format!("{},{},{}", v.x, v.y, v.z),
            format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z),
        ),
        Value::Text(t) => (t.clone(), format!("{t:?}")),
        Value::Unset => unreachable!(),
    }
}

fn command_line(args: &[String]) -> SettingArgs {
    let command = SettingArgs::augment_args(clap::Command::new("fur"));
    let matches = command
        .try_get_matches_from(std::iter::once("fur".to_string()).chain(args.iter().cloned()))
        .unwrap_or_else(|e| panic!("{args:?}: {e}"));
    SettingArgs::from_arg_matches(&matches).unwrap()
}

/// Every setting, on the blob's and the sphere's defaults: set by its flag, by its
/// scene-file key and by its definition's setter, the three scenes are the same, differ
/// from the defaults, and read back the value; a saved scene loads back unchanged.
#[test]
fn every_flag_and_key_sets_the_field_its_definition_reads() {
    let mut count = 0;
    for model in [ModelSpec::Blob, ModelSpec::Sphere] {
        let defaults = Scene::defaults(model);
        for (section, setting) in every_setting() {
            let value = other_value(setting, &defaults);
            let mut expected = defaults.clone();
            setting.set(&mut expected, value.clone());
            assert_ne!(
                expected, defaults,
                "{section}.{}: setting {value:?} changed nothing",
                setting.key
            );
            let read = setting.get(&expected);
            match (&read, &value) {
                (Value::Number(a), Value::Number(b)) => {
                    assert!(
                        (a - b).abs() <= 1e-6 * b.abs().max(1.0),
                        "{section}.{}: {a} ≠ {b}",
                        setting.key
                    )
                }
                _ => assert_eq!(read, value, "{section}.{}", setting.key),
            }

            // No other setting reads the field this one sets (two definitions of one
            // field, or one pointing at another's field, fail here).
            for (other_section, other) in every_setting() {
                if !std::ptr::eq(other, setting) {
                    assert_eq!(
                        other.get(&expected),
                        other.get(&defaults),
                        "setting {section}.{} moved {other_section}.{}",
                        setting.key,
                        other.key
                    );
                }
            }

            let (cli, toml) = spelled(&value);
            let args = match setting.flag {
                Flag::Long(name) => vec![format!("--{name}"), cli],
                Flag::Switch(name, on) => {
                    assert_eq!(value, Value::Bool(on), "--{name}");
                    vec![format!("--{name}")]
                }
            };
            let mut by_flag = defaults.clone();
            command_line(&args).apply(&mut by_flag).unwrap();
            assert_eq!(by_flag, expected, "{args:?}");

            let path = scratch("one.toml");
            let text = format!("[{section}]\n{} = {toml}\n", setting.key);
            std::fs::write(&path, &text).unwrap();
            let (file, text) = SceneFile::load(&path).unwrap();
            let mut by_key = defaults.clone();
            file.apply(&mut by_key, &path, &text).unwrap();
            assert_eq!(by_key, expected, "{text}");

            let saved = scratch("saved.toml");
            expected.save(&saved).unwrap();
            assert_eq!(
                Scene::load(Some(&saved), None).unwrap(),
                expected,
                "{section}.{}",
                setting.key
            );
            count += 1;
        }
    }
    assert!(count >= 2 * 70, "only {count} settings");
}

/// A flag out of range is refused naming the flag and the setting, before any work.
#[test]
fn a_flag_out_of_range_names_itself_and_its_setting() {
    let cases = [
        ("--segments", "64", "hair"),
        ("--fov", "171", "field of view"),
        ("--kd", "-1", "Kd"),
        ("--wind-cone", "91", "wind cone"),
        ("--tip-color", "1,2", "tip colour"),
        ("--samples", "3", "samples per pixel"),
    ];
    for (flag, value, label) in cases {
        let mut scene = Scene::defaults(ModelSpec::Blob);
        let error = command_line(&[flag.into(), value.into()])
            .apply(&mut scene)
            .expect_err(flag)
            .to_string();
        assert!(
            error.contains(flag)
                && error.contains(if label == "hair" { "segments" } else { label }),
            "{error}"
        );
        assert_eq!(
            scene,
            Scene::defaults(ModelSpec::Blob),
            "{flag} changed the scene"
        );
    }
}

#[test]
fn flags_and_keys_are_unique_and_every_choice_parses() {
    let mut flags: Vec<&str> = every_setting().map(|(_, s)| s.flag.name()).collect();
    let mut keys: Vec<String> = every_setting()
        .map(|(g, s)| format!("{g}.{}", s.key))
        .collect();
    let n = flags.len();
    flags.sort_unstable();
    flags.dedup();
    keys.sort_unstable();
    keys.dedup();
    assert_eq!((flags.len(), keys.len()), (n, n));
    for (section, setting) in every_setting() {
        assert!(
            !setting.help.is_empty() && !setting.label.is_empty(),
            "{section}.{}",
            setting.key
        );
        if let Kind::Choice(names) = setting.kind {
            for name in names {
                let mut scene = Scene::defaults(ModelSpec::Blob);
                setting.set(&mut scene, Value::Text(name.to_string()));
                assert_eq!(
                    setting.get(&scene),
                    Value::Text(name.to_string()),
                    "{section}.{}",
                    setting.key
                );
            }
        }
    }
}

/// docs/scene-files.md holds the tables `fur settings` makes from the definitions.
#[test]
fn the_scene_file_docs_hold_the_generated_tables() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-files.md"))
            .unwrap();
    let (before, after) = fur_core::files::region(&doc, docs::BEGIN, docs::END).expect("markers");
    let _ = before;
    let table = &doc[doc.len() - after.len() - (doc.len() - before.len() - after.len())
        ..doc.len() - after.len()];
    assert_eq!(
        table.trim(),
        docs::markdown().trim(),
        "docs/scene-files.md is stale: run `fur settings --write-docs docs/scene-files.md`"
    );
}

/// The hairs `fur render ARGS` reports drawing (a small, validated frame).
fn hairs_drawn(args: &[&str]) -> u64 {
    let out = scratch("cull.png");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(["render", "--validate", "--width", "96", "--height", "54"])
        .args(["--density-scale", "0.2", "--out", out.to_str().unwrap()])
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let before = stdout.split(" hairs drawn in ").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap()
}

/// `[render] cull_margin` (the setting added to show what adding one takes): a larger
/// margin keeps the hairs of triangles facing further away. At 0 every back-facing
/// triangle is culled; at 1 only the screen's bounds cull, so more hairs are drawn; with
/// culling off no fewer again.
#[test]
fn the_cull_margin_keeps_hairs_past_the_silhouette() {
    let none = hairs_drawn(&["--cull-margin", "0"]);
    let default = hairs_drawn(&[]);
    let all = hairs_drawn(&["--cull-margin", "1"]);
    let uncull = hairs_drawn(&["--cull", "off"]);
    assert!(
        none < default && default < all,
        "{none} < {default} < {all}"
    );
    assert!(all <= uncull, "margin 1 {all} vs culling off {uncull}");
}

/// The code files under `dir` (Rust and GLSL) whose text holds `word`, relative to the
/// repository's root, sorted.
fn code_files_naming(dir: &Path, word: &str, found: &mut Vec<String>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let code = ["rs", "glsl", "vert", "tesc", "tese", "geom", "frag", "comp"];
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            code_files_naming(&path, word, found);
        } else if code
            .iter()
            .any(|e| path.extension().is_some_and(|x| x == *e))
            && std::fs::read_to_string(&path).is_ok_and(|t| t.contains(word))
        {
            let relative = path.strip_prefix(root).unwrap();
            found.push(relative.to_string_lossy().replace('\\', "/"));
        }
    }
    found.sort();
}

/// `[render] cull_margin`, a setting a shader reads, lives in three code files: its
/// declaration (the style's field, default and range, its scene key, flag and help,
/// and its member of the drawing block with the line writing it, all in
/// `render/style.rs`), its use (`fur.tesc`) and its test (this file). The block's GLSL
/// and the docs' tables are made from the declaration. A setting spread over more
/// files again (a block typed twice, a key declared apart from its field) fails here.
#[test]
fn a_setting_a_shader_reads_lives_in_three_code_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    for dir in ["crates", "src", "shaders", "tests"] {
        code_files_naming(&root.join(dir), "cull_margin", &mut found);
    }
    assert_eq!(
        found,
        [
            "crates/fur-core/src/render/style.rs",
            "shaders/fur.tesc",
            "tests/settings.rs"
        ]
    );
}

/// The default lighting model is the Marschner model, as `fur settings` prints it and on
/// every built-in model but the original's sphere, which keeps the original's Kajiya–Kay;
/// Kajiya–Kay (the seed's) is one flag away. Seen failing with Kajiya–Kay left the
/// default.
#[test]
fn the_default_lighting_model_is_marschner_in_fur_settings() {
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_fur"))
        .arg("settings")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    let row = stdout
        .lines()
        .find(|l| l.starts_with("| `lighting_model` |"))
        .unwrap_or_else(|| panic!("no lighting_model row in:\n{stdout}"));
    // | key | flag | values | default | help |
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    assert_eq!(cells[4], "marschner; sphere: kajiya-kay", "{row}");
    for model in [
        ModelSpec::Blob,
        ModelSpec::Critter,
        "dense-sphere".parse().unwrap(),
    ] {
        let scene = Scene::defaults(model.clone());
        assert_eq!(
            scene.options.lighting.model,
            fur_core::render::LightingModel::Marschner,
            "{model:?}"
        );
    }
    assert_eq!(
        Scene::defaults(ModelSpec::Sphere).options.lighting.model,
        fur_core::render::LightingModel::KajiyaKay
    );
    let flagged: SettingArgs = command_line(&["--lighting-model".into(), "kajiya-kay".into()]);
    let mut scene = Scene::defaults(ModelSpec::Blob);
    flagged.apply(&mut scene).unwrap();
    assert_eq!(
        scene.options.lighting.model,
        fur_core::render::LightingModel::KajiyaKay
    );
}
