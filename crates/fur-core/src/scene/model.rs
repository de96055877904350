//! Which model to grow fur on: a built-in one, an OBJ file or a glTF file (`.gltf`,
//! `.glb`), skinned and animated or not.

use std::path::PathBuf;

use super::{Mesh, Rig, TextureSpec};
use crate::error::Result;

/// A model named on the command line: `blob`, `sphere`, `dense-sphere`, `critter`, or the path of an
/// OBJ or glTF file (write `./sphere` for a file of that name).
#[derive(Clone, Debug, PartialEq, Default)]
pub enum ModelSpec {
    /// The default model, see [`Mesh::blob`].
    #[default]
    Blob,
    /// The original fur demo's scene model: a UV sphere of radius 2 with 40 latitude
    /// and 80 longitude bands, poles on ±z ([`Mesh::uv_sphere`]).
    Sphere,
    /// The original's sphere 2.5× finer each way (100 × 200 bands, 19,901 vertices): the
    /// performance goal's body (`assets/scenes/goal.toml`), 20K master hairs.
    DenseSphere,
    /// The built-in animated creature ([`super::critter`]): skinned, with a walk and an
    /// idle clip.
    Critter,
    File(PathBuf),
}

impl ModelSpec {
    pub const BUILT_IN: [&'static str; 4] = ["blob", "sphere", "dense-sphere", "critter"];

    /// The model's mesh in its rest pose (a skinned model's rig is left out).
    pub fn load(&self) -> Result<Mesh> {
        Ok(self.load_body()?.0)
    }

    /// The model's mesh in its rest pose, its rig when it is skinned or animated, and
    /// what loading it warned about.
    pub fn load_body(&self) -> Result<(Mesh, Option<Rig>, Vec<String>)> {
        match self {
            Self::Blob => Ok((Mesh::blob(), None, Vec::new())),
            Self::Sphere => Ok((Mesh::uv_sphere(2.0, 40, 80), None, Vec::new())),
            Self::DenseSphere => Ok((Mesh::uv_sphere(2.0, 100, 200), None, Vec::new())),
            Self::Critter => {
                let (mesh, rig) = super::critter();
                Ok((mesh, Some(rig), Vec::new()))
            }
            Self::File(path) if is_gltf(path) => {
                let body = super::load_gltf(path)?;
                Ok((body.mesh, body.rig, body.warnings))
            }
            Self::File(path) => Ok((Mesh::load_obj(path)?, None, Vec::new())),
        }
    }

    /// Loads the model ready to grow fur on: scaled into [`Mesh::SCALE_RANGE`] and
    /// turned right side out when needed, with a warning naming the model for each;
    /// `texture`, if given, replaces the model's own (its material's).
    pub fn prepare(&self, texture: Option<&TextureSpec>) -> Result<(Mesh, Vec<String>)> {
        let (mesh, _, warnings) = self.prepare_body(texture)?;
        Ok((mesh, warnings))
    }

    /// [`ModelSpec::prepare`] keeping the rig of a skinned or animated model (rescaled
    /// and turned with the mesh).
    pub fn prepare_body(
        &self,
        texture: Option<&TextureSpec>,
    ) -> Result<(Mesh, Option<Rig>, Vec<String>)> {
        let (mut mesh, mut rig, mut warnings) = self.load_body()?;
        if let Some(t) = texture {
            mesh.texture = Some(t.clone());
        } else if let Some(TextureSpec::File(path)) = &mesh.texture {
            // Exporters leave dangling texture paths: the model's own texture is optional.
            if let Err(problem) = crate::files::read_bounded_check(path) {
                warnings.push(format!(
                    "model {} names the texture {}, which cannot be read ({problem}); it is \
                     drawn without a texture",
                    self.name(),
                    path.display()
                ));
                mesh.texture = None;
            }
        }
        let (_, radius) = mesh.bounds();
        if let Some(factor) = mesh.normalize_scale() {
            if let Some(rig) = &mut rig {
                rig.scale *= factor;
            }
            warnings.push(format!(
                "model {} has a bounding radius of {radius:e} units; it is drawn scaled by \
                 {factor:e} to a radius of 1",
                self.name()
            ));
        }
        if mesh.orient_outwards() {
            if let Some(rig) = &mut rig {
                rig.bind_normals.iter_mut().for_each(|n| *n = -*n);
            }
            warnings.push(format!(
                "model {}: most normals point into the model (inside out); they were flipped so \
                 the fur grows outwards",
                self.name()
            ));
        }
        Ok((mesh, rig, warnings))
    }

    pub fn name(&self) -> String {
        match self {
            Self::Blob => "blob".into(),
            Self::Sphere => "sphere".into(),
            Self::DenseSphere => "dense-sphere".into(),
            Self::Critter => "critter".into(),
            Self::File(path) => path.display().to_string(),
        }
    }
}

impl std::str::FromStr for ModelSpec {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Ok(match s {
            "blob" => Self::Blob,
            "sphere" => Self::Sphere,
            "dense-sphere" => Self::DenseSphere,
            "critter" => Self::Critter,
            "" => return Err(
                "expected blob, sphere, dense-sphere, critter or the path of an OBJ or glTF file"
                    .into(),
            ),
            path => Self::File(PathBuf::from(path)),
        })
    }
}

/// Whether `path` names a glTF file (`.gltf` or `.glb`, any case).
fn is_gltf(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}
