//! Binary USD (`.usdc`, a "crate" file) through the `openusd` crate's writer, with one
//! correction Pixar's library needs.
//!
//! The children lists of a layer (`primChildren`, `propertyChildren`, …) are vectors of
//! tokens (`TfTokenVector`), a type of their own in a crate file. Version 0.6 of
//! `openusd` writes them as arrays of tokens (`token[]`), which its own reader accepts
//! and Pixar's refuses ("Invalid children found in primChildren field"); the versions
//! that write vectors need a newer Rust than fur builds with. The payload of the two is
//! the same (a count, then token or string indices), so only each such field's value
//! representation differs: [`write_usdc`] writes the layer, then rewrites the `FIELDS`
//! section with those representations corrected, appended after the rest with a new
//! table of contents that points to it (the old section stays, unread).

use std::io::Cursor;

use openusd::sdf::AbstractData;

/// The fields Pixar's library reads as token vectors (`SdfChildrenKeys` and the
/// orders and sublayers of `SdfFieldKeys`), as a crate file names them (the property
/// children are `properties` there).
const VECTOR_FIELDS: [&str; 9] = [
    "expressionChildren",
    "mapperArgChildren",
    "primChildren",
    "properties",
    "variantChildren",
    "variantSetChildren",
    "primOrder",
    "propertyOrder",
    "subLayers",
];

/// The crate file's value types this correction touches (`openusd::usdc`'s `Type`): an
/// array of strings or tokens, and the vectors the same payload becomes.
const TYPE_STRING: u64 = 10;
const TYPE_TOKEN: u64 = 11;
const TYPE_TOKEN_VECTOR: u64 = 41;
const TYPE_STRING_VECTOR: u64 = 50;
const ARRAY_BIT: u64 = 1 << 63;
const TYPE_MASK: u64 = 0xff << 48;

/// `data` as a binary USD file Pixar's library opens.
pub fn write_usdc(data: &dyn AbstractData) -> Result<Vec<u8>, String> {
    let mut out = Cursor::new(Vec::new());
    openusd::usdc::CrateWriter::write(data, &mut out).map_err(|e| format!("{e:#}"))?;
    let mut file = out.into_inner();
    correct_vector_fields(&mut file).map_err(|m| format!("writing the crate file: {m}"))?;
    Ok(file)
}

/// The USD text `text` as a binary USD file Pixar's library opens (the same layer,
/// parsed by `openusd` and written by [`write_usdc`]).
pub fn usdc_from_text(text: &str) -> Result<Vec<u8>, String> {
    let data = openusd::usda::parse(text).map_err(|e| format!("USD text: {e:#}"))?;
    write_usdc(&data)
}

/// A little-endian reader over a byte slice that fails instead of panicking.
struct Bytes<'a> {
    data: &'a [u8],
    at: usize,
}

impl<'a> Bytes<'a> {
    fn at(data: &'a [u8], at: u64) -> Result<Self, String> {
        let at = usize::try_from(at).map_err(|_| "an offset past the file".to_string())?;
        Ok(Self { data, at })
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.data.len());
        let end = end.ok_or_else(|| format!("{n} bytes past the end at {}", self.at))?;
        let s = &self.data[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn u64(&mut self) -> Result<u64, String> {
        let b = self.take(8)?;
        Ok(u64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
    }

    /// A block the writer compressed: its size, a zero chunk count, one LZ4 block, of
    /// at most `at_most` bytes (and never more than LZ4 can expand it to).
    fn lz4(&mut self, at_most: usize) -> Result<Vec<u8>, String> {
        let size = self.u64()?;
        let block = self.take(usize::try_from(size).map_err(|_| "a huge block")?)?;
        let at_most = at_most.min(255 * block.len() + 64);
        match block.split_first() {
            Some((0, lz4)) => lz4_flex::block::decompress(lz4, at_most).map_err(|e| e.to_string()),
            _ => Err("a compressed block of more than one chunk".into()),
        }
    }
}

/// A section of the table of contents: its name (NUL-padded), start and size.
type Section = ([u8; 16], u64, u64);

/// The table of contents' offset and its sections.
fn sections(file: &[u8]) -> Result<(u64, Vec<Section>), String> {
    let mut boot = Bytes::at(file, 0)?;
    if boot.take(8)? != b"PXR-USDC" {
        return Err("not a crate file".into());
    }
    boot.take(8)?;
    let toc = boot.u64()?;
    let mut r = Bytes::at(file, toc)?;
    let count = r.u64()?;
    if count > 64 {
        return Err(format!("{count} sections"));
    }
    let mut out = Vec::new();
    for _ in 0..count {
        let name: [u8; 16] = r.take(16)?.try_into().map_err(|_| "a section name")?;
        out.push((name, r.u64()?, r.u64()?));
    }
    Ok((toc, out))
}

fn named<'s>(
    s: &'s [([u8; 16], u64, u64)],
    name: &str,
) -> Result<&'s ([u8; 16], u64, u64), String> {
    s.iter()
        .find(|(n, _, _)| n.split(|&b| b == 0).next() == Some(name.as_bytes()))
        .ok_or_else(|| format!("no {name} section"))
}

/// Pixar's integer coding of `count` 32-bit integers: a common delta, two bits of
/// code per integer (common, 8, 16 or 32 bits), then the other deltas.
fn decode_ints(data: &[u8], count: usize) -> Result<Vec<i64>, String> {
    if count == 0 {
        return Ok(Vec::new());
    }
    let mut r = Bytes { data, at: 0 };
    let common = i64::from(i32::from_le_bytes(r.take(4)?.try_into().unwrap_or([0; 4])));
    let codes = r.take((count * 2).div_ceil(8))?;
    let (mut prev, mut out) = (0i64, Vec::with_capacity(count));
    for i in 0..count {
        let delta = match (codes[i / 4] >> (2 * (i % 4))) & 3 {
            0 => common,
            1 => i64::from(r.take(1)?[0] as i8),
            2 => i64::from(i16::from_le_bytes(r.take(2)?.try_into().unwrap_or([0; 2]))),
            _ => i64::from(i32::from_le_bytes(r.take(4)?.try_into().unwrap_or([0; 4]))),
        };
        prev = prev.wrapping_add(delta);
        out.push(prev);
    }
    Ok(out)
}

/// Rewrites `file`'s vector fields' value representations from `token[]` to a token
/// vector (see the module documentation).
fn correct_vector_fields(file: &mut Vec<u8>) -> Result<(), String> {
    let (_, table) = sections(file)?;
    // The tokens: a count, the text's size, the text (NUL after each).
    let (_, start, _) = *named(&table, "TOKENS")?;
    let mut r = Bytes::at(file, start)?;
    let count = r.u64()?;
    let size = usize::try_from(r.u64()?).map_err(|_| "a huge token table")?;
    let text = r.lz4(size)?;
    let tokens: Vec<&[u8]> = text.split(|&b| b == 0).take(count as usize).collect();
    let vector: Vec<i64> = (0..tokens.len() as i64)
        .filter(|&t| {
            VECTOR_FIELDS
                .iter()
                .any(|f| f.as_bytes() == tokens[t as usize])
        })
        .collect();
    // The fields: a count, their names' token indices (integer-coded), their values.
    let (_, start, _) = *named(&table, "FIELDS")?;
    let mut r = Bytes::at(file, start)?;
    let fields = usize::try_from(r.u64()?).map_err(|_| "a huge field table")?;
    if fields > file.len() {
        return Err(format!("{fields} fields in a file of {} bytes", file.len()));
    }
    let names_at = r.at;
    let names = decode_ints(&r.lz4(4 + fields.div_ceil(4) + 4 * fields)?, fields)?;
    let names_block = file[names_at..r.at].to_vec();
    let reps_bytes = r.lz4(8 * fields)?;
    let mut reps: Vec<u64> = reps_bytes
        .chunks_exact(8)
        .map(|b| u64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
        .collect();
    if reps.len() != fields {
        return Err("the field values do not match their count".into());
    }
    for (rep, name) in reps.iter_mut().zip(&names) {
        let vector_type = match (*rep & TYPE_MASK) >> 48 {
            TYPE_TOKEN => TYPE_TOKEN_VECTOR,
            TYPE_STRING => TYPE_STRING_VECTOR,
            _ => continue,
        };
        if *rep & ARRAY_BIT != 0 && vector.contains(name) {
            *rep = (*rep & !(TYPE_MASK | ARRAY_BIT)) | (vector_type << 48);
        }
    }
    // The new FIELDS section, then the table of contents pointing to it.
    let fields_at = file.len() as u64;
    file.extend_from_slice(&(fields as u64).to_le_bytes());
    file.extend_from_slice(&names_block);
    let raw: Vec<u8> = reps.iter().flat_map(|r| r.to_le_bytes()).collect();
    let mut packed = vec![0u8];
    packed.extend(lz4_flex::block::compress(&raw));
    file.extend_from_slice(&(packed.len() as u64).to_le_bytes());
    file.extend_from_slice(&packed);
    let fields_size = file.len() as u64 - fields_at;
    let toc_at = file.len() as u64;
    file.extend_from_slice(&(table.len() as u64).to_le_bytes());
    for (name, start, size) in &table {
        let is_fields = name.split(|&b| b == 0).next() == Some(b"FIELDS".as_slice());
        let (start, size) = if is_fields {
            (fields_at, fields_size)
        } else {
            (*start, *size)
        };
        file.extend_from_slice(name);
        file.extend_from_slice(&start.to_le_bytes());
        file.extend_from_slice(&size.to_le_bytes());
    }
    file[16..24].copy_from_slice(&toc_at.to_le_bytes());
    Ok(())
}

#[cfg(test)]
mod tests;
