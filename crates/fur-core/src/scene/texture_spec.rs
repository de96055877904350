//! Which colour texture a scene uses: a built-in one, an image file or an image held
//! inside a model file.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::Texture;
use crate::error::Result;

/// A texture by name: `tabby` (built in) or the path of a PNG, JPEG or TGA file.
#[derive(Clone, PartialEq)]
pub enum TextureSpec {
    /// Generated stripes for latitude/longitude UVs ([`Texture::tabby`], 512 × 256).
    Tabby,
    File(PathBuf),
    /// An image stored inside a model (a glTF buffer view or `data:` URI): its encoded
    /// bytes (PNG, JPEG, ...) and a name for messages, such as `model.glb#image0`.
    Embedded {
        name: String,
        bytes: Arc<[u8]>,
    },
}

/// Like a derived `Debug`, but an embedded image shows its size, not its bytes.
impl std::fmt::Debug for TextureSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Tabby => write!(f, "Tabby"),
            Self::File(path) => f.debug_tuple("File").field(path).finish(),
            Self::Embedded { name, bytes } => f
                .debug_struct("Embedded")
                .field("name", name)
                .field("bytes", &format_args!("{} bytes", bytes.len()))
                .finish(),
        }
    }
}

impl TextureSpec {
    pub fn name(&self) -> String {
        match self {
            Self::Tabby => "tabby".into(),
            Self::File(path) => path.display().to_string(),
            Self::Embedded { name, .. } => name.clone(),
        }
    }

    /// Loads or makes the texture; a file's errors name it.
    pub fn load(&self) -> Result<Texture> {
        match self {
            Self::Tabby => Ok(Texture::tabby(512, 256)),
            Self::File(path) => Texture::load(path),
            Self::Embedded { name, bytes } => Texture::decode(bytes, Path::new(name)),
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
