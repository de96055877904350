//! One USD layer from a file's bytes: text (after the nesting guard), binary, or the
//! first layer of a zip package (stored, as USD's packages are, and bounded by the
//! package's own size), handed to `openusd`'s decoders.

use std::io::{Cursor, Read as _};

use openusd::sdf::AbstractData;

use super::super::GroomFormat;

/// The deepest bracket nesting of USD text handed to the parser (which recurses).
pub const MAX_TEXT_NESTING: usize = 1024;

/// Decodes the layer in `bytes`; `format` from the file's extension (`.usd` may hold
/// text or binary: the bytes decide).
pub fn open_layer(bytes: &[u8], format: GroomFormat) -> Result<Box<dyn AbstractData>, String> {
    match format {
        GroomFormat::Usda => text(bytes),
        GroomFormat::Usdz => {
            let (name, layer) = first_layer(bytes)?;
            let is_text = name.ends_with(".usda")
                || (!name.ends_with(".usdc") && !layer.starts_with(b"PXR-USDC"));
            if is_text {
                text(&layer).map_err(|m| format!("its layer `{name}`: {m}"))
            } else {
                binary(layer).map_err(|m| format!("its layer `{name}`: {m}"))
            }
        }
        _ if bytes.starts_with(b"#usda") => text(bytes),
        _ if bytes.starts_with(b"PXR-USDC") => binary(bytes.to_vec()),
        _ => Err("neither USD text (`#usda`) nor binary USD (`PXR-USDC`)".into()),
    }
}

fn text(bytes: &[u8]) -> Result<Box<dyn AbstractData>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "USD text that is not UTF-8")?;
    check_nesting(text)?;
    let data = openusd::usda::parse(text).map_err(|e| format!("USD text: {e:#}"))?;
    Ok(Box::new(data))
}

fn binary(bytes: Vec<u8>) -> Result<Box<dyn AbstractData>, String> {
    openusd::usdc::CrateData::open(Cursor::new(bytes), true)
        .map(|d| Box::new(d) as Box<dyn AbstractData>)
        .map_err(|e| format!("binary USD: {e:#}"))
}

/// The name and bytes of a package's first USD layer (its root layer, by USD's
/// rule). USD packages store their files uncompressed, so an entry is read only if it
/// is stored and lies within the package: what it unpacks to is bounded by the
/// package's own size.
fn first_layer(package: &[u8]) -> Result<(String, Vec<u8>), String> {
    let mut archive = zip::ZipArchive::new(Cursor::new(package))
        .map_err(|e| format!("USD package (zip): {e}"))?;
    let name = archive
        .file_names()
        .find(|n| n.ends_with(".usda") || n.ends_with(".usdc") || n.ends_with(".usd"))
        .map(str::to_string)
        .ok_or("a USD package with no USD layer (.usda, .usdc or .usd) in it")?;
    let entry = archive
        .by_name(&name)
        .map_err(|e| format!("USD package: its layer `{name}`: {e}"))?;
    if entry.compression() != zip::CompressionMethod::Stored {
        return Err(format!(
            "its layer `{name}` is compressed ({}); USD packages store their files \
             uncompressed, and a compressed one is not unpacked",
            entry.compression()
        ));
    }
    let limit = package.len() as u64;
    if entry.size() > limit {
        return Err(format!(
            "its layer `{name}` says it is {} bytes, more than the package's {limit}",
            entry.size()
        ));
    }
    let mut layer = Vec::with_capacity(entry.size() as usize);
    entry
        .take(limit + 1)
        .read_to_end(&mut layer)
        .map_err(|e| format!("USD package: its layer `{name}`: {e}"))?;
    if layer.len() as u64 > limit {
        return Err(format!(
            "its layer `{name}` unpacks to more than the package's {limit} bytes"
        ));
    }
    Ok((name, layer))
}

/// Refuses USD text whose brackets nest deeper than [`MAX_TEXT_NESTING`] (a parser
/// that recurses would run out of stack). Brackets are counted as the format reads
/// them: not inside `#` comments, strings (`"…"`, `'…'`, `"""…"""`, `'''…'''`, with
/// backslash escapes) or asset paths (`@…@`, `@@@…@@@`).
pub fn check_nesting(text: &str) -> Result<(), String> {
    let b = text.as_bytes();
    let (mut i, mut depth, mut deepest) = (0, 0usize, 0usize);
    while i < b.len() {
        i = match b[i] {
            b'#' => line_end(b, i),
            b'"' | b'\'' => past_string(b, i),
            b'@' => past_asset(b, i),
            b'{' | b'(' | b'[' => {
                depth += 1;
                deepest = deepest.max(depth);
                i + 1
            }
            b'}' | b')' | b']' => {
                depth = depth.saturating_sub(1);
                i + 1
            }
            _ => i + 1,
        };
    }
    if deepest > MAX_TEXT_NESTING {
        return Err(format!(
            "USD text nested {deepest} deep (over {MAX_TEXT_NESTING})"
        ));
    }
    Ok(())
}

/// Where the line holding byte `i` ends (its newline, or the text's end).
fn line_end(b: &[u8], i: usize) -> usize {
    b[i..]
        .iter()
        .position(|&c| c == b'\n')
        .map_or(b.len(), |n| i + n)
}

/// Past the string opening at `i`: a triple-quoted one may span lines, a single-quoted
/// one ends at its line's end if unclosed (the parser reports it); `\` escapes.
fn past_string(b: &[u8], i: usize) -> usize {
    let q = b[i];
    let triple = b[i..].starts_with(&[q, q, q]);
    let mut at = i + if triple { 3 } else { 1 };
    while at < b.len() {
        match b[at] {
            b'\\' => at += 2,
            b'\n' if !triple => return at,
            c if c == q && (!triple || b[at..].starts_with(&[q, q, q])) => {
                return at + if triple { 3 } else { 1 }
            }
            _ => at += 1,
        }
    }
    b.len()
}

/// Past the asset path opening at `i`: `@@@…@@@` (where `\@@@` is escaped) or `@…@`
/// on one line.
fn past_asset(b: &[u8], i: usize) -> usize {
    if b[i..].starts_with(b"@@@") {
        let mut at = i + 3;
        while at < b.len() {
            if b[at] == b'\\' {
                at += 2;
            } else if b[at..].starts_with(b"@@@") {
                return at + 3;
            } else {
                at += 1;
            }
        }
        return b.len();
    }
    match b[i + 1..].iter().position(|&c| c == b'@' || c == b'\n') {
        Some(n) if b[i + 1 + n] == b'@' => i + n + 2,
        Some(n) => i + 1 + n,
        None => b.len(),
    }
}
