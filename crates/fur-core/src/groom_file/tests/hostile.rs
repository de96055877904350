//! Files from strangers: each way a careless or hostile groom file once took the
//! process down (an allocation of terabytes, a stack overflow, a panic, memory without
//! bound, quadratic time, a count silently cut), and a sweep of every byte flip and
//! truncation of each format. Memory is observed (this thread's allocations, or the
//! decoding process's address space), not inferred.

use std::io::{Cursor, Write as _};

use glam::Vec3;

use super::super::*;
use super::binary::tfx_by_hand;
use crate::test_alloc::measure;

/// One curve of 37 points starting at (1.5, -2.25, 3.125): its points array is easy
/// to find in a binary file (a count of 37, then that first coordinate).
fn marked() -> Guides {
    Guides {
        counts: vec![37],
        points: (0..37)
            .map(|i| Vec3::new(1.5 + i as f32, -2.25, 3.125))
            .collect(),
        ..Guides::default()
    }
}

fn usdc(g: &Guides) -> Vec<u8> {
    usdc_from_text(&write_usda(g, "hostile test").unwrap()).unwrap()
}

/// `file` with the points array's count (a u64 before the first coordinate) set to
/// `count`.
fn with_points_count(file: &[u8], count: u64) -> Vec<u8> {
    let mut needle = 37u64.to_le_bytes().to_vec();
    needle.extend_from_slice(&1.5f32.to_le_bytes());
    let at = file
        .windows(needle.len())
        .position(|w| w == needle)
        .expect("the points array is in the file");
    let mut out = file.to_vec();
    out[at..at + 8].copy_from_slice(&count.to_le_bytes());
    out
}

/// An error of one line (the caller puts the file's name before it).
fn one_line(result: Result<Guides, String>) -> String {
    let error = result.expect_err("the file was read");
    assert_eq!(error.lines().count(), 1, "{error}");
    error
}

/// In-process, `openusd` allocates 2⁴⁰ × 12 bytes for a count of 2⁴⁰ and the
/// allocation failure aborts; a count of 2⁶² overflows and panics. Decoded apart, each
/// is one line.
#[test]
fn counts_that_claim_terabytes_are_an_error_not_an_abort() {
    let file = usdc(&marked());
    assert_eq!(
        parse_usd(&file, GroomFormat::Usdc).unwrap().points.len(),
        37
    );
    let error = one_line(parse_usd(
        &with_points_count(&file, 1 << 40),
        GroomFormat::Usdc,
    ));
    assert!(error.contains("asked for 12288 GiB"), "{error}");
    let error = one_line(parse_usd(
        &with_points_count(&file, 1 << 62),
        GroomFormat::Usdc,
    ));
    assert!(error.contains("the decoder failed on it"), "{error}");
}

/// A stray quote in a comment once hid 100,000 brackets from the nesting guard, and
/// the parser's recursion overflowed the stack; a package's text layer was not guarded
/// at all.
#[test]
fn deep_brackets_after_a_quote_in_a_comment_are_refused_in_a_file_and_a_package() {
    let text = format!("#usda 1.0\n# it's \"odd\n{}\n", "[".repeat(100_000));
    let error = one_line(parse_usd(text.as_bytes(), GroomFormat::Usda));
    assert!(error.contains("nested 100000 deep"), "{error}");
    let package = zip_of("deep.usda", text.as_bytes(), zip::CompressionMethod::Stored);
    let error = one_line(parse_usd(&package, GroomFormat::Usdz));
    assert!(
        error.contains("`deep.usda`") && error.contains("nested 100000 deep"),
        "{error}"
    );
}

/// Strings, asset paths and comments are read the way USD's grammar reads them: the
/// brackets inside them are not nesting, a quote inside a comment opens no string,
/// and the real nesting around them still counts.
#[test]
fn the_nesting_guard_reads_strings_assets_and_comments_as_usd_does() {
    let deep = "(".repeat(1100);
    for inside in [
        format!("\"a \\\" {deep}\""),
        format!("'it\\'s {deep}'"),
        format!("\"\"\"two\nlines \" {deep}\"\"\""),
        format!("'''{deep}\n'''"),
        format!("@{deep}@"),
        format!("@@@ \\@@@ {deep}@@@"),
        format!("0 # {deep}\n"),
    ] {
        let text = format!("#usda 1.0\n(\n    doc = {inside}\n)\n");
        check_nesting(&text).unwrap_or_else(|e| panic!("{inside}: {e}"));
        let nested = format!("#usda 1.0\n{}{text}", "[".repeat(MAX_TEXT_NESTING));
        let error = check_nesting(&nested).unwrap_err();
        assert!(error.contains("nested 1025 deep"), "{inside}: {error}");
    }
    // A quote in a comment opens no string: the brackets after it count.
    let text = format!("#usda 1.0\n# \"\n{deep}\n# \"\n");
    assert!(check_nesting(&text)
        .unwrap_err()
        .contains("nested 1100 deep"));
    // The parser agrees with the guard on what the strings hold.
    let curves = "def BasisCurves \"C\" (\n    doc = \"\"\"((( \" )))\"\"\"\n)\n{\n    \
         uniform token type = \"linear\"\n    int[] curveVertexCounts = [2]\n    \
         point3f[] points = [(0, 0, 0), (0, 1, 0)] # ((( \"\n}\n";
    let g = decode_usd(format!("#usda 1.0\n{curves}").as_bytes(), GroomFormat::Usda).unwrap();
    assert_eq!(g.counts, vec![2]);
}

fn zip_of(name: &str, bytes: &[u8], method: zip::CompressionMethod) -> Vec<u8> {
    let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(method)
        .compression_level((method != zip::CompressionMethod::Stored).then_some(1))
        .large_file(bytes.len() as u64 >= u32::MAX as u64);
    out.start_file(name, options).unwrap();
    out.write_all(bytes).unwrap();
    out.finish().unwrap().into_inner()
}

/// A package of 256 MiB of zeros deflated to a few hundred KiB was unpacked whole. USD
/// packages store their files: a compressed one is refused before it is unpacked, and
/// a stored one is bounded by the package.
#[test]
fn a_package_is_never_unpacked_past_its_own_size() {
    let zeros = vec![0u8; 256 << 20];
    let bomb = zip_of("layer.usda", &zeros, zip::CompressionMethod::Deflated);
    drop(zeros);
    assert!(bomb.len() < 4 << 20, "{} bytes", bomb.len());
    let error = one_line(parse_usd(&bomb, GroomFormat::Usdz));
    assert!(error.contains("is compressed"), "{error}");
    // The same refusal in this process: nothing near the entry's size is allocated.
    let (result, usage) = measure(|| decode_usd(&bomb, GroomFormat::Usdz));
    assert!(result.is_err());
    assert!(usage.peak < bomb.len() + (1 << 20), "{usage:?}");
    // A stored package reads, through its text and its binary layer alike.
    let g = marked();
    let text = write_usda(&g, "t").unwrap();
    for (name, layer) in [("a.usda", text.into_bytes()), ("a.usdc", usdc(&g))] {
        let package = zip_of(name, &layer, zip::CompressionMethod::Stored);
        assert_eq!(
            parse_usd(&package, GroomFormat::Usdz).unwrap().points,
            g.points
        );
    }
}

/// A cyHair header of 700 M hairs with no segments array made a count for every hair
/// before it looked at the points (2.7 GB).
#[test]
fn a_cyhair_header_cannot_make_the_reader_allocate_what_the_file_does_not_hold() {
    let mut b = b"HAIR".to_vec();
    for v in [700_000_000u32, 2, 2, 1] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.resize(128 + 24, 0);
    let (result, usage) = measure(|| parse_cyhair(&b));
    let error = result.unwrap_err();
    assert!(error.contains("700000000 hairs"), "{error}");
    assert!(usage.peak < 64 << 10, "{usage:?}");
}

/// Per-vertex colours were split into channels again for every curve: quadratic in
/// the curves. What reading allocates in all grows as the file does.
#[test]
fn reading_usd_allocates_in_proportion_to_the_file() {
    let file = |curves: usize| {
        let g = Guides {
            counts: vec![10; curves],
            points: (0..curves * 10)
                .map(|i| Vec3::new(i as f32, 1.0, 2.0))
                .collect(),
            widths: Some(vec![0.01; curves * 10]),
            colors: Some(vec![Vec3::new(0.5, 0.25, 0.125); curves * 10]),
            notes: Vec::new(),
        };
        write_usda(&g, "t").unwrap()
    };
    let (small, large) = (file(500), file(4000));
    let (_, a) = measure(|| decode_usd(small.as_bytes(), GroomFormat::Usda).unwrap());
    let (_, b) = measure(|| decode_usd(large.as_bytes(), GroomFormat::Usda).unwrap());
    let ratio = b.total as f64 / a.total as f64;
    // 8× the curves: 8× the work when linear, 64× when quadratic.
    assert!(
        ratio < 12.0,
        "8× the curves allocated {ratio:.1}× ({a:?}, {b:?})"
    );
    assert!(
        b.total < 40 * large.len(),
        "{b:?} for {} bytes",
        large.len()
    );
}

/// USD's rule: a primvar has exactly the values its interpolation asks for. 40 widths
/// for 30 points were read as 30, the rest dropped without a word.
#[test]
fn a_primvar_of_the_wrong_length_is_refused_naming_it() {
    let read = |widths: &str, colours: &str| {
        let text = format!(
            "#usda 1.0\ndef BasisCurves \"C\"\n{{\n    uniform token type = \"linear\"\n    \
             int[] curveVertexCounts = [3, 2]\n    \
             point3f[] points = [(0, 0, 0), (0, 1, 0), (0, 2, 0), (1, 0, 0), (1, 1, 0)]\n    \
             {widths}\n    {colours}\n}}\n"
        );
        decode_usd(text.as_bytes(), GroomFormat::Usda)
    };
    let widths = |n: usize, interpolation: &str| {
        let v = vec!["0.1"; n].join(", ");
        format!("float[] widths = [{v}] (interpolation = \"{interpolation}\")")
    };
    let colours = |n: usize, interpolation: &str| {
        let v = vec!["(1, 0, 0)"; n].join(", ");
        format!("color3f[] primvars:displayColor = [{v}] (interpolation = \"{interpolation}\")")
    };
    for (interpolation, right) in [
        ("vertex", 5),
        ("uniform", 2),
        ("constant", 1),
        ("varying", 5),
    ] {
        assert!(
            read(&widths(right, interpolation), "").is_ok(),
            "{interpolation}"
        );
        assert!(
            read("", &colours(right, interpolation)).is_ok(),
            "{interpolation}"
        );
        for wrong in [right - 1, right + 1, right + 8] {
            let error = read(&widths(wrong, interpolation), "").unwrap_err();
            let values = if wrong == 1 { "value" } else { "values" };
            let expected = format!(
                "/C: `widths` ({interpolation}) has {wrong} {values}; 2 curves of 5 control \
                 points need exactly {right}"
            );
            assert_eq!(error, expected);
            let error = read("", &colours(wrong, interpolation)).unwrap_err();
            assert!(
                error.starts_with(&format!(
                    "/C: `primvars:displayColor` ({interpolation}) has {wrong} "
                )),
                "{error}"
            );
        }
    }
}

/// Each variant of `file` (every byte inverted, every byte's high bit flipped, every
/// truncation), read by `read`, which must return, never panic.
fn sweep(file: &[u8], mut read: impl FnMut(&[u8]) -> Result<Guides, String>) -> (usize, usize) {
    let (mut loaded, mut refused) = (0, 0);
    let mut tally = |r: Result<Guides, String>| match r {
        Ok(_) => loaded += 1,
        Err(e) => {
            assert_eq!(e.lines().count(), 1, "{e}");
            refused += 1;
        }
    };
    for at in 0..file.len() {
        for flip in [0xff, 0x80] {
            let mut v = file.to_vec();
            v[at] ^= flip;
            tally(read(&v));
        }
    }
    for len in 0..file.len() {
        tally(read(&file[..len]));
    }
    (loaded, refused)
}

/// Every single-byte flip and every truncation of a small valid file of each format
/// loads or is refused in one line: fur's own readers in this process, within 16× the
/// file plus 64 KiB of allocation (observed), USD in its decoding process, within its
/// stated limit (observed: the process's peak address space).
#[test]
fn every_flip_and_truncation_of_each_format_loads_or_is_refused() {
    if crate::isolate::rerun_without_backtraces(
        "groom_file::tests::hostile::every_flip_and_truncation_of_each_format_loads_or_is_refused",
    ) {
        return;
    }
    let g = super::sample_guides();
    let hair = write_cyhair(&g, "sweep").unwrap();
    for (name, file, read) in [
        (
            "cyHair",
            hair,
            parse_cyhair as fn(&[u8]) -> Result<Guides, String>,
        ),
        ("TressFX", tfx_by_hand(true), parse_tfx),
    ] {
        let (loaded, refused) = sweep(&file, |v| {
            let (r, usage) = measure(|| read(v));
            assert!(usage.peak <= 16 * v.len() + (64 << 10), "{name}: {usage:?}");
            r
        });
        assert!(
            loaded > 0 && refused > 0,
            "{name}: {loaded} loaded, {refused} refused"
        );
    }
    let text = write_usda(&g, "sweep").unwrap().into_bytes();
    let binary = usdc(&g);
    for (name, file, format) in [
        ("USD text", text, GroomFormat::Usda),
        ("binary USD", binary, GroomFormat::Usdc),
    ] {
        let (loaded, refused) = sweep(&file, |v| {
            let limit = usd_limits(v.len()).memory;
            parse_usd_measured(v, format).map(|(g, peak)| {
                assert!(peak <= limit, "{name}: peak {peak} over {limit}");
                g
            })
        });
        assert!(
            loaded > 0 && refused > 0,
            "{name}: {loaded} loaded, {refused} refused"
        );
    }
}
