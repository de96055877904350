//! The truth section's groom scene: a groom file drawn as it is (`--groom-mode draw`),
//! each guide one hair, against the path tracer like the grown scenes.

use std::path::Path;

use fur_core::scene::{GroomMode, ModelSpec, Strands};
use fur_core::scene_file::Scene;
use fur_gpu::error::Result;

/// The scene's name in the tables.
pub(super) const NAME: &str = "groom-drawn";

/// How much the groom's guides curl: enough that the drawing is of the file's own
/// curves, not of a comb the scene could have grown.
const CURL: f32 = 0.6;

/// The blob's master hairs, curled, written as a groom file at `path`, and the blob's
/// scene drawing that file as it is.
pub(super) fn scene(path: &Path) -> Result<Scene> {
    let mut grown = Scene::defaults(ModelSpec::Blob);
    grown.options.curl = CURL;
    let (mesh, _, _) = grown.model.prepare_body(None)?;
    let (groom, settings) = grown.options.resolve(&mesh)?;
    let (strands, _) = Strands::grow_reported(&mesh, &groom)?;
    let guides = strands.to_guides(Some(settings.style.hair_width));
    fur_core::groom_file::write_groom(path, &guides, "fur bench")?;
    let mut scene = Scene::defaults(ModelSpec::Blob);
    scene.options.groom_file = Some(path.to_string_lossy().into_owned());
    scene.options.groom_mode = GroomMode::Draw;
    Ok(scene)
}
