//! The glTF file and what it refers to: the `.glb` container, the JSON document, the
//! buffers (the `.glb`'s BIN chunk, `.bin` files beside the model, `data:` URIs, read
//! once and only when used) and the base colour image.

use std::cell::OnceCell;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use gltf::json;

use super::super::TextureSpec;
use super::document;
use super::uri::{is_data_uri, resolve, short, Uri};

/// An opened glTF document with its buffers.
pub(super) struct Source<'a> {
    pub root: json::Root,
    /// The model file, named in messages and in embedded images' names.
    pub model: &'a Path,
    /// Its folder: URIs are relative to it.
    folder: &'a Path,
    /// The whole file (a `.glb`'s BIN chunk is a range of it).
    file: Vec<u8>,
    bin: Option<Range<usize>>,
    /// Per buffer with a URI, its bytes (or why they cannot be had), read on first use.
    loaded: Vec<OnceCell<Result<Vec<u8>, String>>>,
}

impl<'a> Source<'a> {
    /// Parses the document in `file` (see [`document::parse`]).
    pub fn open(
        file: Vec<u8>,
        model: &'a Path,
        warnings: &mut Vec<String>,
    ) -> Result<Self, String> {
        let (root, bin) = document::parse(&file, &model.display().to_string(), warnings)?;
        let loaded = root.buffers.iter().map(|_| OnceCell::new()).collect();
        Ok(Self {
            root,
            model,
            folder: model.parent().unwrap_or(Path::new("")),
            file,
            bin,
            loaded,
        })
    }

    /// Buffer `index`'s bytes (its `byteLength` of them), read on first use.
    pub fn buffer(&self, index: usize) -> Result<&[u8], String> {
        let buffer = self.root.buffers.get(index).ok_or_else(|| {
            format!(
                "buffer {index} does not exist (the file has {} buffers)",
                self.root.buffers.len()
            )
        })?;
        let name = self.buffer_name(index);
        let bytes: &[u8] = match &buffer.uri {
            None => match (&self.bin, index) {
                (Some(range), 0) => self.file.get(range.clone()).unwrap_or_default(),
                (Some(_), _) => {
                    return Err(format!(
                        "{name} has no uri: only buffer 0 can be the .glb's BIN chunk"
                    ))
                }
                (None, _) => {
                    return Err(format!(
                        "{name} has no uri, and the file is not a .glb with a BIN chunk"
                    ))
                }
            },
            Some(uri) => {
                let cell = self.loaded.get(index).ok_or("buffer cache out of step")?;
                let result = cell.get_or_init(|| match resolve(self.folder, uri)? {
                    Uri::Data(bytes) => Ok(bytes),
                    Uri::File(path) => {
                        crate::files::read_bounded(&path, crate::files::MAX_MODEL_BYTES, "model")
                    }
                });
                result
                    .as_deref()
                    .map_err(|e| format!("{name} cannot be read: {e}"))?
            }
        };
        let declared = buffer.byte_length.0;
        if (bytes.len() as u64) < declared {
            return Err(format!(
                "{name} has {} bytes, but its byteLength says {declared}",
                bytes.len()
            ));
        }
        Ok(bytes.get(..declared as usize).unwrap_or(bytes))
    }

    /// `buffer 0 (scene.bin)`, `buffer 0 (the .glb's BIN chunk)`, `buffer 1 (a data: URI)`.
    pub fn buffer_name(&self, index: usize) -> String {
        match self.root.buffers.get(index).map(|b| b.uri.as_deref()) {
            Some(Some(uri)) if is_data_uri(uri) => format!("buffer {index} (a data: URI)"),
            Some(Some(uri)) => format!("buffer {index} ({})", short(uri)),
            Some(None) if self.bin.is_some() && index == 0 => {
                format!("buffer {index} (the .glb's BIN chunk)")
            }
            _ => format!("buffer {index}"),
        }
    }

    /// The bytes of buffer view `index`, bounds-checked against its buffer.
    pub fn view(&self, index: usize) -> Result<&[u8], String> {
        let view = self.root.buffer_views.get(index).ok_or_else(|| {
            format!(
                "buffer view {index} does not exist (the file has {} buffer views)",
                self.root.buffer_views.len()
            )
        })?;
        let buffer = view.buffer.value();
        let declared = self
            .root
            .buffers
            .get(buffer)
            .map(|b| b.byte_length.0)
            .ok_or_else(|| {
                format!(
                    "buffer view {index} refers to buffer {buffer}, which does not exist (the \
                     file has {})",
                    self.root.buffers.len()
                )
            })?;
        let start = view.byte_offset.map_or(0, |o| o.0);
        let end = start.saturating_add(view.byte_length.0);
        if end > declared {
            return Err(format!(
                "buffer view {index} reaches byte {end} of the {declared}-byte {}",
                self.buffer_name(buffer)
            ));
        }
        let bytes = self.buffer(buffer)?;
        bytes
            .get(start as usize..end as usize)
            .ok_or_else(|| format!("buffer view {index} lies outside its buffer"))
    }

    /// The texture for glTF texture `index`: an image file beside the model, or an image
    /// held in a buffer view or a `data:` URI. A missing or unusable image is a warning.
    pub fn texture(&self, index: usize, warnings: &mut Vec<String>) -> Option<TextureSpec> {
        let mut warn = |message: String| {
            warnings.push(format!(
                "model {}: {message}; it loads without a texture",
                self.model.display()
            ));
            None
        };
        let Some(texture) = self.root.textures.get(index) else {
            return warn(format!("texture {index} does not exist"));
        };
        let image_index = texture.source.value();
        let Some(image) = self.root.images.get(image_index) else {
            return warn(format!(
                "texture {index} names image {image_index}, which does not exist"
            ));
        };
        let name = format!(
            "{}#image{image_index}",
            self.model.file_name().map_or_else(
                || self.model.display().to_string(),
                |n| n.to_string_lossy().into_owned()
            )
        );
        if let Some(view) = image.buffer_view {
            return match self.view(view.value()) {
                Ok(bytes) => Some(TextureSpec::Embedded {
                    name,
                    bytes: Arc::from(bytes),
                }),
                Err(e) => warn(format!("image {image_index} cannot be read ({e})")),
            };
        }
        let Some(uri) = image.uri.as_deref() else {
            return warn(format!(
                "image {image_index} has neither a uri nor a bufferView"
            ));
        };
        match resolve(self.folder, uri) {
            Ok(Uri::Data(bytes)) => Some(TextureSpec::Embedded {
                name,
                bytes: Arc::from(bytes),
            }),
            Ok(Uri::File(path)) => {
                if let Err(e) = crate::files::read_bounded_check(&path) {
                    return warn(format!("its image {} cannot be read ({e})", path.display()));
                }
                Some(TextureSpec::File(path))
            }
            Err(e) => warn(format!("image {image_index} cannot be read ({e})")),
        }
    }
}
