//! URIs in a glTF file: `data:` URIs decoded, relative paths percent-decoded and
//! resolved against the model's folder; URLs and absolute paths refused.

use std::path::{Path, PathBuf};

use base64::Engine as _;

/// What a URI in the file stands for.
pub(super) enum Uri {
    /// The bytes of a `data:` URI.
    Data(Vec<u8>),
    /// A file beside the model.
    File(PathBuf),
}

/// What a URI names: `data:` bytes, or a file in the model's `folder`. URLs and
/// absolute paths are refused.
pub(super) fn resolve(folder: &Path, uri: &str) -> Result<Uri, String> {
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
    Ok(Uri::File(folder.join(decoded)))
}

pub(super) fn is_data_uri(uri: &str) -> bool {
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
pub(super) fn short(uri: &str) -> String {
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
}
