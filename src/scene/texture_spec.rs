//! Which colour texture a scene uses: a built-in one or an image file.

use std::path::PathBuf;

use super::Texture;
use crate::error::Result;

/// A texture by name: `tabby` (built in) or the path of a PNG, JPEG or TGA file.
#[derive(Clone, Debug, PartialEq)]
pub enum TextureSpec {
    /// Generated stripes for latitude/longitude UVs ([`Texture::tabby`], 512 × 256).
    Tabby,
    File(PathBuf),
}

impl TextureSpec {
    pub fn name(&self) -> String {
        match self {
            Self::Tabby => "tabby".into(),
            Self::File(path) => path.display().to_string(),
        }
    }

    /// Loads or makes the texture; a file's errors name it.
    pub fn load(&self) -> Result<Texture> {
        match self {
            Self::Tabby => Ok(Texture::tabby(512, 256)),
            Self::File(path) => Texture::load(path),
        }
    }
}

impl std::str::FromStr for TextureSpec {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "" => Err("expected `tabby` or the path of an image file, got nothing".into()),
            "tabby" => Ok(Self::Tabby),
            path => Ok(Self::File(PathBuf::from(path))),
        }
    }
}
