//! The glTF document: a `.glb`'s chunks or `.gltf` JSON text, parsed into
//! [`json::Root`], its version checked and files that require extensions refused.

use std::ops::Range;

use gltf::json;

/// The document in `file` and, for a `.glb`, the range of its BIN chunk. Extensions
/// used but not required, and cameras, are warnings naming `model`.
pub(super) fn parse(
    file: &[u8],
    model: &str,
    warnings: &mut Vec<String>,
) -> Result<(json::Root, Option<Range<usize>>), String> {
    let (json_range, bin) = if file.starts_with(b"glTF") {
        split_glb(file)?
    } else {
        let first = file
            .iter()
            .skip(BOM.len() * usize::from(file.starts_with(BOM)))
            .find(|b| !b.is_ascii_whitespace());
        if first != Some(&b'{') {
            return Err(
                "not a glTF file: a .glb starts with `glTF` and a .gltf is JSON text \
                        starting with `{`"
                    .into(),
            );
        }
        (0..file.len(), None)
    };
    let text = file.get(json_range).unwrap_or_default();
    let text = text.strip_prefix(BOM).unwrap_or(text);
    let root = deserialize(text, warnings)?;
    if !root.asset.version.starts_with("2.") {
        return Err(format!(
            "it is a glTF {} file; only glTF 2.0 is supported",
            root.asset.version
        ));
    }
    if !root.extensions_required.is_empty() {
        return Err(format!(
            "it requires the glTF extension(s) {}, which fur does not support; export the \
             model without them (no Draco or meshopt compression, no quantisation)",
            root.extensions_required.join(", ")
        ));
    }
    if !root.extensions_used.is_empty() {
        warnings.push(format!(
            "{model} uses the glTF extension(s) {}, which fur ignores",
            root.extensions_used.join(", ")
        ));
    }
    if !root.cameras.is_empty() {
        warnings.push(format!(
            "{model} has {} camera(s); they are ignored (fur places its own camera)",
            root.cameras.len()
        ));
    }
    Ok((root, bin))
}

const BOM: &[u8] = b"\xEF\xBB\xBF";

/// The document; when it does not deserialise as it is, it is read once more with what
/// valid files hold but the `gltf` crate refuses taken out (`extras` that are not
/// objects, animation channels with no target node, as `KHR_animation_pointer` writes
/// them), each a warning.
fn deserialize(text: &[u8], warnings: &mut Vec<String>) -> Result<json::Root, String> {
    let first = match json::deserialize::from_slice::<json::Root>(text) {
        Ok(root) => return Ok(root),
        Err(e) => e,
    };
    let refused = || format!("not a valid glTF 2.0 document ({first})");
    let Ok(mut value) = json::deserialize::from_slice::<json::Value>(text) else {
        return Err(refused());
    };
    let version = value
        .get("asset")
        .and_then(|a| a.get("version"))
        .and_then(|v| v.as_str());
    if let Some(v) = version.filter(|v| !v.starts_with("2.")) {
        return Err(format!("it is a glTF {v} file; only glTF 2.0 is supported"));
    }
    let mut fixes = Vec::new();
    drop_scalar_extras(&mut value);
    let animations = value.get_mut("animations").and_then(|a| a.as_array_mut());
    for (a, animation) in animations.into_iter().flatten().enumerate() {
        let Some(channels) = animation.get_mut("channels").and_then(|c| c.as_array_mut()) else {
            continue;
        };
        let before = channels.len();
        channels.retain(|c| c.get("target").is_some_and(|t| t.get("node").is_some()));
        if channels.len() < before {
            fixes.push(format!(
                "animation {a}: {} channel(s) with no target node (animation pointers) are \
                 ignored",
                before - channels.len()
            ));
        }
    }
    let root = json::deserialize::from_value::<json::Root>(value).map_err(|_| refused())?;
    warnings.extend(fixes);
    Ok(root)
}

/// Removes every `extras` that is not an object (glTF allows any value there).
fn drop_scalar_extras(value: &mut json::Value) {
    match value {
        json::Value::Object(map) => {
            if map.get("extras").is_some_and(|e| !e.is_object()) {
                map.remove("extras");
            }
            map.values_mut().for_each(drop_scalar_extras);
        }
        json::Value::Array(items) => items.iter_mut().for_each(drop_scalar_extras),
        _ => {}
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

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn valid_oddities_are_read_with_warnings() {
        let text = br#"{"asset":{"version":"2.0","extras":42},"animations":[{"channels":[
            {"sampler":0,"target":{"path":"pointer"}}],"samplers":[]}]}"#;
        let mut warnings = Vec::new();
        let (root, bin) = parse(text, "m.gltf", &mut warnings).unwrap();
        assert!(bin.is_none());
        assert!(root.animations[0].channels.is_empty());
        assert!(warnings[0].contains("no target node"), "{warnings:?}");
        let message = parse(br#"{"asset":{"version":"1.0"}}"#, "m", &mut warnings).unwrap_err();
        assert!(message.contains("glTF 1.0"), "{message}");
    }
}
