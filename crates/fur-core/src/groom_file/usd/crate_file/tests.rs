use openusd::sdf::{self, SpecType, Value};

use super::*;
use crate::groom_file::{parse_usd, GroomFormat, Guides};

fn guides() -> Guides {
    Guides {
        counts: vec![2, 3],
        points: (0..5).map(|i| glam::Vec3::splat(i as f32)).collect(),
        widths: None,
        colors: None,
        notes: Vec::new(),
    }
}

/// Every field of a crate file: its name, value type and whether it is an array.
fn field_types(file: &[u8]) -> Vec<(String, u64, bool)> {
    let (_, table) = sections(file).unwrap();
    let (_, start, _) = *named(&table, "TOKENS").unwrap();
    let mut r = Bytes::at(file, start).unwrap();
    let count = r.u64().unwrap() as usize;
    let size = r.u64().unwrap() as usize;
    let text = r.lz4(size).unwrap();
    let tokens: Vec<String> = text
        .split(|&b| b == 0)
        .take(count)
        .map(|t| String::from_utf8_lossy(t).into_owned())
        .collect();
    let (_, start, _) = *named(&table, "FIELDS").unwrap();
    let mut r = Bytes::at(file, start).unwrap();
    let n = r.u64().unwrap() as usize;
    let names = decode_ints(&r.lz4(4 + n + 4 * n).unwrap(), n).unwrap();
    let reps = r.lz4(8 * n).unwrap();
    names
        .iter()
        .zip(reps.chunks_exact(8))
        .map(|(&t, b)| {
            let rep = u64::from_le_bytes(b.try_into().unwrap());
            (
                tokens[t as usize].clone(),
                (rep & TYPE_MASK) >> 48,
                rep & ARRAY_BIT != 0,
            )
        })
        .collect()
}

// The children lists become vectors (of tokens; a sublayer list of strings), and an
// attribute's `token[]` value stays an array; the layer reads back through openusd's
// reader with its curves.
#[test]
fn children_fields_become_vectors_and_arrays_stay_arrays() {
    let mut data = super::super::write::groom_layer(&guides(), "test").unwrap();
    data.spec_mut(&sdf::Path::abs_root())
        .unwrap()
        .add("subLayers", Value::StringVec(vec!["under.usda".into()]));
    let order = sdf::path("/Groom.xformOpOrder").unwrap();
    let attr = data.create_spec(order, SpecType::Attribute);
    attr.add("typeName", Value::Token("token[]".into()));
    attr.add("default", Value::TokenVec(vec!["xformOp:translate".into()]));
    let file = write_usdc(&data).unwrap();
    let types = field_types(&file);
    let of = |name: &str| -> Vec<(u64, bool)> {
        types
            .iter()
            .filter(|t| t.0 == name)
            .map(|t| (t.1, t.2))
            .collect()
    };
    assert_eq!(of("primChildren"), vec![(TYPE_TOKEN_VECTOR, false)]);
    assert_eq!(of("properties"), vec![(TYPE_TOKEN_VECTOR, false)]);
    assert_eq!(of("subLayers"), vec![(TYPE_STRING_VECTOR, false)]);
    assert!(of("default").contains(&(TYPE_TOKEN, true)), "{types:?}");
}

// The corrected file is whole: every section inside it, the new FIELDS section
// ending where the new table of contents begins; text becomes the same binary layer.
#[test]
fn the_corrected_file_is_whole_and_reads_back() {
    let text = super::super::write::write_usda(&guides(), "test").unwrap();
    let file = usdc_from_text(&text).unwrap();
    let (toc, table) = sections(&file).unwrap();
    for (name, start, size) in &table {
        assert!(start + size <= toc, "{:?} runs past the table", name);
    }
    let (_, start, size) = *named(&table, "FIELDS").unwrap();
    assert_eq!(start + size, toc);
    let back = parse_usd(&file, GroomFormat::Usdc).unwrap();
    assert_eq!(back.counts, guides().counts);
    assert_eq!(back.points, guides().points);
    assert!(usdc_from_text("#usda 1.0\ndef Xform \"A\" {").is_err());
}

// A table of contents of more than 64 sections is refused, 64 are read; a block of no
// bytes is an error, and the most compressible block (a MiB of zeros) still decodes.
#[test]
fn malformed_files_are_errors() {
    let file_of = |count: u64| -> Vec<u8> {
        let mut f = b"PXR-USDC".to_vec();
        f.extend([0u8; 8]);
        f.extend(24u64.to_le_bytes());
        f.extend(count.to_le_bytes());
        f.extend(vec![0u8; 32 * count as usize]);
        f
    };
    assert_eq!(sections(&file_of(64)).unwrap().1.len(), 64);
    assert!(sections(&file_of(65)).is_err());
    assert!(sections(b"PXR-USDX").is_err());
    let empty = 0u64.to_le_bytes();
    assert!(Bytes::at(&empty, 0).unwrap().lz4(100).is_err());
    let zeros = vec![0u8; 1 << 20];
    let mut block = vec![0u8];
    block.extend(lz4_flex::block::compress(&zeros));
    let mut framed = (block.len() as u64).to_le_bytes().to_vec();
    framed.extend(&block);
    assert_eq!(Bytes::at(&framed, 0).unwrap().lz4(1 << 20).unwrap(), zeros);
}

#[test]
fn the_integer_coding_reads_each_width() {
    // Common delta 1; codes: common, 8-bit, 16-bit, 32-bit.
    let mut data = 1i32.to_le_bytes().to_vec();
    data.push(0b11_10_01_00);
    data.push(5i8 as u8);
    data.extend((-300i16).to_le_bytes());
    data.extend(70_000i32.to_le_bytes());
    assert_eq!(decode_ints(&data, 4).unwrap(), vec![1, 6, -294, 69_706]);
    assert!(decode_ints(&data[..6], 4).is_err());
}
