//! The glTF file and what it refers to: the `.glb` container, the JSON document, the
//! buffers (the `.glb`'s BIN chunk, `.bin` files beside the model, `data:` URIs, read
//! once and only when used) and the base colour image.

use std::cell::OnceCell;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use base64::Engine as _;
use gltf::json;

use super::super::TextureSpec;

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

/// What a URI in the file stands for.
enum Uri {
    /// The bytes of a `data:` URI.
    Data(Vec<u8>),
    /// A file beside the model.
    File(PathBuf),
}

impl<'a> Source<'a> {
    /// Splits a `.glb` (or takes `.gltf` JSON text), parses the document and refuses
    /// files that require extensions; extensions used but not required, and cameras,
    /// are warnings.
    pub fn open(
        file: Vec<u8>,
        model: &'a Path,
        warnings: &mut Vec<String>,
    ) -> Result<Self, String> {
        let (json_range, bin) = if file.starts_with(b"glTF") {
            split_glb(&file)?
        } else {
            let start = if file.starts_with(b"\xEF\xBB\xBF") {
                3
            } else {
                0
            };
            let first = file
                .get(start..)
                .and_then(|rest| rest.iter().find(|b| !b.is_ascii_whitespace()).copied());
            if first != Some(b'{') {
                return Err(
                    "not a glTF file: a .glb starts with `glTF` and a .gltf is JSON \
                            text starting with `{`"
                        .into(),
                );
            }
            (start..file.len(), None)
        };
        let text = file.get(json_range).unwrap_or_default();
        let root: json::Root =
            json::deserialize::from_slice(text).map_err(|e| match declared_version(text) {
                Some(v) if !v.starts_with("2.") => {
                    format!("it is a glTF {v} file; only glTF 2.0 is supported")
                }
                _ => format!("not a valid glTF 2.0 document ({e})"),
            })?;
        if !root.asset.version.starts_with("2.") {
            return Err(format!(
                "it is a glTF {} file; only glTF 2.0 is supported",
                root.asset.version
            ));
        }
        if !root.extensions_required.is_empty() {
            return Err(format!(
                "it requires the glTF extension(s) {}, which fur does not support; export \
                 the model without them (no Draco or meshopt compression, no quantisation)",
                root.extensions_required.join(", ")
            ));
        }
        if !root.extensions_used.is_empty() {
            warnings.push(format!(
                "{} uses the glTF extension(s) {}, which fur ignores",
                model.display(),
                root.extensions_used.join(", ")
            ));
        }
        if !root.cameras.is_empty() {
            warnings.push(format!(
                "{} has {} camera(s); they are ignored (fur places its own camera)",
                model.display(),
                root.cameras.len()
            ));
        }
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
                "buffer {index} does not exist (the file has {})",
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
                let result = cell.get_or_init(|| match self.resolve(uri)? {
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
                "buffer view {index} does not exist (the file has {})",
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

    /// What a URI names: `data:` bytes, or a file in the model's folder. URLs and
    /// absolute paths are refused.
    fn resolve(&self, uri: &str) -> Result<Uri, String> {
        if is_data_uri(uri) {
            return decode_data_uri(uri).map(Uri::Data);
        }
        if let Some(scheme) = scheme(uri) {
            return Err(match scheme.to_ascii_lowercase().as_str() {
                "http" | "https" => format!(
                    "{} is a URL, and http(s) URLs are not fetched; download it beside the model",
                    short(uri)
                ),
                other => format!(
                    "{} is a `{other}:` URI; only paths relative to the model and data: URIs \
                     are read",
                    short(uri)
                ),
            });
        }
        let decoded = percent_decode(uri);
        let decoded = String::from_utf8(decoded)
            .map_err(|_| format!("{} is not UTF-8 once percent-decoded", short(uri)))?
            .replace('\\', "/");
        let drive = decoded.as_bytes().get(1) == Some(&b':');
        if decoded.starts_with('/') || drive {
            return Err(format!(
                "{} is an absolute path; a glTF file may only refer to files relative to it",
                short(&decoded)
            ));
        }
        if decoded.is_empty() {
            return Err("the URI is empty".into());
        }
        Ok(Uri::File(self.folder.join(decoded)))
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
        match self.resolve(uri) {
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

/// A `.glb`'s JSON chunk and BIN chunk (if any) as ranges of the file; chunks of other
/// types are skipped, as the format says.
fn split_glb(file: &[u8]) -> Result<(Range<usize>, Option<Range<usize>>), String> {
    let word = |at: usize| -> Option<u32> {
        let bytes: [u8; 4] = file.get(at..at.checked_add(4)?)?.try_into().ok()?;
        Some(u32::from_le_bytes(bytes))
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(format!(
            "truncated .glb: the file has {} bytes, less than the 12-byte header",
            file.len()
        ));
    };
    if version != 2 {
        return Err(format!(
            "it is a version {version} .glb; only glTF 2.0 (version 2) is supported"
        ));
    }
    let length = length as usize;
    if length > file.len() {
        return Err(format!(
            "truncated .glb: the header says {length} bytes, the file has {}",
            file.len()
        ));
    }
    if length < 20 {
        return Err(format!(
            "the .glb header says the file has {length} bytes, too few for the header and a \
             JSON chunk"
        ));
    }
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    while at < length {
        let (Some(chunk_length), Some(kind)) = (word(at), file.get(at + 4..at + 8)) else {
            return Err(format!(
                "truncated .glb: the chunk header at byte {at} is cut off at byte {length}"
            ));
        };
        let start = at + 8;
        let end = start.saturating_add(chunk_length as usize);
        if end > length {
            return Err(format!(
                "truncated .glb: the chunk at byte {at} says {chunk_length} bytes, only {} \
                 remain",
                length - start.min(length)
            ));
        }
        match (kind, json.is_some()) {
            (b"JSON", false) => json = Some(start..end),
            (_, false) => {
                return Err(format!(
                    "the first chunk of a .glb must be JSON, it is `{}`",
                    String::from_utf8_lossy(kind).trim_end_matches('\0')
                ))
            }
            (b"BIN\0", true) if bin.is_none() => bin = Some(start..end),
            _ => {}
        }
        at = end.saturating_add(3) & !3;
    }
    let json = json.ok_or("the .glb has no JSON chunk")?;
    Ok((json, bin))
}

/// The `asset.version` a document declares, when it can be read at all.
fn declared_version(text: &[u8]) -> Option<String> {
    let value: json::Value = json::deserialize::from_slice(text).ok()?;
    Some(value.get("asset")?.get("version")?.as_str()?.to_string())
}

fn is_data_uri(uri: &str) -> bool {
    uri.get(..5)
        .is_some_and(|s| s.eq_ignore_ascii_case("data:"))
}

/// The bytes of a `data:` URI: base64 (`;base64,`) or percent-encoded text.
fn decode_data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let (header, payload) = uri
        .split_once(',')
        .ok_or("a data: URI without a comma before its data")?;
    if header.to_ascii_lowercase().ends_with(";base64") {
        let engine = base64::engine::GeneralPurpose::new(
            &base64::alphabet::STANDARD,
            base64::engine::GeneralPurposeConfig::new()
                .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent)
                .with_decode_allow_trailing_bits(true),
        );
        let payload: String = payload
            .chars()
            .filter(|c| !c.is_ascii_whitespace())
            .collect();
        engine
            .decode(payload.as_bytes())
            .map_err(|e| format!("its data: URI is not valid base64 ({e})"))
    } else {
        Ok(percent_decode(payload))
    }
}

/// A URI's scheme (`http` in `http://...`), if it has one; a one-letter "scheme" is a
/// Windows drive, not a scheme.
fn scheme(uri: &str) -> Option<&str> {
    let (scheme, _) = uri.split_once(':')?;
    let mut chars = scheme.chars();
    let valid = chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
        && scheme.len() > 1;
    valid.then_some(scheme)
}

/// `%XX` escapes decoded; malformed ones kept as they are.
fn percent_decode(text: &str) -> Vec<u8> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while let Some(&b) = bytes.get(i) {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (b, hex) {
            (b'%', Some(value)) => {
                out.push(value);
                i += 3;
            }
            _ => {
                out.push(b);
                i += 1;
            }
        }
    }
    out
}

/// A URI for messages: at most 80 characters.
fn short(uri: &str) -> String {
    if uri.chars().count() <= 80 {
        uri.to_string()
    } else {
        format!("{}…", uri.chars().take(80).collect::<String>())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_decode_and_urls_are_named() {
        assert_eq!(percent_decode("my%20fur.bin"), b"my fur.bin");
        assert_eq!(percent_decode("100%zz%4"), b"100%zz%4");
        assert_eq!(scheme("https://example.com/a.bin"), Some("https"));
        assert_eq!(scheme("C:/a.bin"), None);
        assert_eq!(scheme("a.bin"), None);
        assert_eq!(
            decode_data_uri("data:application/octet-stream;base64,AAEC").unwrap(),
            [0, 1, 2]
        );
        assert_eq!(decode_data_uri("data:,a%20b").unwrap(), b"a b");
        assert!(decode_data_uri("data:;base64,@@@").is_err());
    }

    #[test]
    fn glb_chunks_are_found_and_short_headers_refused() {
        let mut glb = b"glTF\x02\0\0\0\0\0\0\0".to_vec();
        glb.extend_from_slice(&4u32.to_le_bytes());
        glb.extend_from_slice(b"JSON{}  ");
        glb.extend_from_slice(&4u32.to_le_bytes());
        glb.extend_from_slice(b"XYZW1234");
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(b"BIN\0ab\0\0");
        let length = glb.len() as u32;
        glb[8..12].copy_from_slice(&length.to_le_bytes());
        let (json, bin) = split_glb(&glb).unwrap();
        assert_eq!(&glb[json], b"{}  ");
        assert_eq!(&glb[bin.unwrap()], b"ab");
        for length in [0u32, 5, 11, 19] {
            glb[8..12].copy_from_slice(&length.to_le_bytes());
            let message = split_glb(&glb).unwrap_err();
            assert!(message.contains("too few"), "length {length}: {message}");
        }
        let message = split_glb(&glb[..7]).unwrap_err();
        assert!(message.contains("12-byte header"), "{message}");
    }
}
