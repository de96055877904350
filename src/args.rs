//! Command-line options shared by `fur render`, `fur view` and `fur export-frame`: the
//! model and every setting of the scene (their flags come from the settings'
//! definitions); and the device (with `fur bench`).

use clap::Args;
use fur::setting_args::SettingArgs;
use fur_core::scene::{ModelSpec, TextureSpec};
use fur_core::scene_file::Scene;

/// The model and every setting of the scene. Options left out come from the scene
/// file, if one is given, else from the model's defaults (`--model sphere` is the
/// original fur demo's scene).
#[derive(Args, Clone)]
pub struct SceneArgs {
    /// Model: `blob` (built in, the default), `sphere` (the original demo's scene: a UV
    /// sphere of radius 2, 40 × 80 bands, hairs of 12 vertices), `critter` (a walking
    /// animal with a skeleton) or the path of an OBJ or glTF file.
    #[arg(long, allow_hyphen_values = true)]
    pub model: Option<ModelSpec>,
    /// Colour the fur and skin from a texture through the model's UVs: a PNG, JPEG or
    /// TGA file, or `tabby` (built in, made for lat-long UVs) [default: the OBJ
    /// material's map_Kd, if any].
    #[arg(long, allow_hyphen_values = true)]
    pub texture: Option<TextureSpec>,
    #[command(flatten)]
    pub settings: SettingArgs,
}

/// The scene a run draws: the model's defaults, then the scene file at `path` (if any),
/// then the command line's options.
pub fn scene(path: Option<&std::path::Path>, args: &SceneArgs) -> anyhow::Result<Scene> {
    let mut scene = Scene::load(path, args.model.clone())?;
    if args.texture.is_some() {
        scene.options.texture = args.texture.clone();
    }
    args.settings.apply(&mut scene)?;
    Ok(scene)
}

/// Which Vulkan device runs the work (`fur devices` lists them).
#[derive(Args, Clone, Default)]
pub struct DeviceArgs {
    /// The Vulkan device: its index in `fur devices`, or a case-insensitive part of its
    /// name that only one usable device has (e.g. `rtx`) [default: $FUR_DEVICE if set,
    /// else the first usable device of the best kind: discrete, integrated, virtual,
    /// cpu].
    #[arg(long, value_name = "INDEX|NAME", allow_hyphen_values = true)]
    pub device: Option<String>,
}

/// The environment variable that chooses the device when `--device` is not given.
pub const DEVICE_ENV: &str = "FUR_DEVICE";

impl DeviceArgs {
    /// The choice: `--device`, else `FUR_DEVICE` (empty counts as unset), else none.
    pub fn choice(&self) -> Option<String> {
        self.device.clone().or_else(|| {
            std::env::var(DEVICE_ENV)
                .ok()
                .filter(|v| !v.trim().is_empty())
        })
    }

    /// A headless device: the chosen one, with the validation layer if `validate`.
    pub fn headless(&self, validate: bool) -> anyhow::Result<std::sync::Arc<fur_gpu::gpu::Device>> {
        Ok(fur_gpu::gpu::headless_on(
            validate,
            self.choice().as_deref(),
        )?)
    }
}
