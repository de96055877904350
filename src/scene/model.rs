//! Which model to grow fur on: a built-in one or an OBJ file.

use std::path::PathBuf;

use super::{Mesh, TextureSpec};
use crate::error::Result;

/// A model named on the command line: `blob`, `sphere`, or a path to an OBJ file
/// (write `./sphere` for a file of that name).
#[derive(Clone, Debug, PartialEq, Default)]
pub enum ModelSpec {
    /// The default model, see [`Mesh::blob`].
    #[default]
    Blob,
    /// The original fur demo's scene model: a UV sphere of radius 2 with 40 latitude
    /// and 80 longitude bands, poles on ±z ([`Mesh::uv_sphere`]).
    Sphere,
    File(PathBuf),
}

impl ModelSpec {
    pub const BUILT_IN: [&'static str; 2] = ["blob", "sphere"];

    pub fn load(&self) -> Result<Mesh> {
        match self {
            Self::Blob => Ok(Mesh::blob()),
            Self::Sphere => Ok(Mesh::uv_sphere(2.0, 40, 80)),
            Self::File(path) => Mesh::load_obj(path),
        }
    }

    /// Loads the model ready to grow fur on: scaled into [`Mesh::SCALE_RANGE`] and
    /// turned right side out when needed, with a warning naming the model for each;
    /// `texture`, if given, replaces the model's own (its material's).
    pub fn prepare(&self, texture: Option<&TextureSpec>) -> Result<(Mesh, Vec<String>)> {
        let mut mesh = self.load()?;
        let mut warnings = Vec::new();
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
            warnings.push(format!(
                "model {} has a bounding radius of {radius:e} units; it is drawn scaled by \
                 {factor:e} to a radius of 1",
                self.name()
            ));
        }
        if mesh.orient_outwards() {
            warnings.push(format!(
                "model {}: most normals point into the model (inside out); they were flipped so \
                 the fur grows outwards",
                self.name()
            ));
        }
        Ok((mesh, warnings))
    }

    pub fn name(&self) -> String {
        match self {
            Self::Blob => "blob".into(),
            Self::Sphere => "sphere".into(),
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
            "" => return Err("expected blob, sphere or the path of an OBJ file".into()),
            path => Self::File(PathBuf::from(path)),
        })
    }
}
