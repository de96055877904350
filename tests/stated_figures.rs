//! The limits, targets and defaults the documents state are the code's. Each phrase
//! below is built from the constant it states and must stand in its document word for
//! word, so changing either the constant or the document fails here (seen failing with
//! the model limit changed to 3 GiB, and with the README's Rust version one behind).
//!
//! Figures measured by a run are bound elsewhere: the README's against the generated
//! tables (`docs.rs`), the ratios it derives from them below, and every figure inside a
//! `<!-- BEGIN … -->` region is a benchmark figure, written by the run the region names.

#[path = "common/mod.rs"]
mod common;

#[path = "stated_figures/phrases.rs"]
mod phrases;
#[path = "stated_figures/simulation.rs"]
mod simulation;

use common::{flat, read_doc as read};
use fur_core::files::size_text;
use phrases::{count_text, stated};

#[test]
fn the_limits_targets_and_defaults_the_documents_state_are_the_codes() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for (doc, phrases) in stated() {
        let text = flat(&read(doc));
        for phrase in phrases {
            checked += 1;
            if !text.contains(&phrase) {
                missing.push(format!("{doc}: \"{phrase}\""));
            }
        }
    }
    assert!(checked >= 20, "only {checked} phrases checked");
    assert!(
        missing.is_empty(),
        "the documents do not state what the code does:\n{}",
        missing.join("\n")
    );
}

#[test]
fn counts_are_written_with_commas() {
    assert_eq!(count_text(8_000_000), "8,000,000");
    assert_eq!(count_text(999), "999");
    assert_eq!(count_text(1000), "1,000");
    assert_eq!(size_text(2 << 30), "2 GiB");
}

/// The documents whose prose [`every_figure_in_the_documents_prose_is_bound_or_marked`]
/// reads. The README's "What to expect" and the measured documents (docs/benchmark.md,
/// ground-truth.md, gpu.md) quote the runs and are bound by `docs.rs`.
const PROSE: [&str; 16] = [
    "README.md",
    "docs/lighting.md",
    "docs/compute-raster.md",
    "docs/testing.md",
    "docs/testing-simulation.md",
    "docs/testing-rendering.md",
    "docs/testing-truth.md",
    "docs/testing-inputs.md",
    "docs/testing-drivers.md",
    "docs/mutation-runs.md",
    "docs/design.md",
    "docs/simulation.md",
    "docs/pipeline.md",
    "docs/grooms.md",
    "docs/robustness.md",
    "docs/scene-files.md",
];

/// Figures the documents state that are neither the code's constants nor measurements:
/// per document, the phrase that holds them (which must stand there word for word) and
/// what they are.
const NOT_MEASURED: [(&str, &str, &str); 40] = [
    (
        "docs/design.md",
        "(Crane, Weischedel and Wardetzky, 2013;",
        "a year",
    ),
    (
        "docs/design.md",
        "the indices sum to 2 as Poincaré–Hopf requires",
        "the theorem's sum on a closed body",
    ),
    ("docs/design.md", "(`--flow-from 0,1,0.5`)", "an example"),
    (
        "docs/compute-raster.md",
        "have turned 65,535 times in all",
        "Mesa's gallivm loop limit (LP_MAX_TGSI_LOOP_ITERATIONS)",
    ),
    ("docs/simulation.md", "(Han & Harada §4.2)", "a section of the paper"),
    ("docs/simulation.md", "at 60 frames per second", "the frame rate the seed's wind assumes"),
    (
        "docs/design.md",
        "rows hold ⌊16384/V⌋ strands, so 15 M strands fit where the seed's one-row-per-strand layout stopped at 16,384",
        "lavapipe's largest image side, a device limit, and what it holds",
    ),
    ("docs/design.md", "(64 on lavapipe)", "lavapipe's largest tessellation level"),
    ("docs/simulation.md", "32-bit floats", "the number format"),
    ("docs/simulation.md", "one 16-byte load", "an rgba32f texel's size"),
    ("docs/simulation.md", "two joint indices in 16 bits each", "the packing's format"),
    ("docs/simulation.md", "**glTF 2.0**", "the format's version"),
    ("docs/lighting.md", "Kajiya–Kay (1989)", "a year"),
    ("docs/lighting.md", "Chiang et al. 2016's", "a year"),
    ("docs/lighting.md", "(Marschner et al. 2003)", "a year"),
    ("docs/lighting.md", "Karis 2016's closed forms", "a year"),
    ("docs/lighting.md", "(Zinke et al. 2008)", "a year"),
    (
        "docs/lighting.md",
        "(azimuths more than 90° from the way back)",
        "the forward half's definition",
    ),
    (
        "docs/design.md",
        "the original drew its 58,240 tessellated points 189,600 times",
        "the original demo's own counts",
    ),
    ("docs/pipeline.md", "the default blob at 480×270", "the pictures' size"),
    ("docs/pipeline.md", "⌊16384/V⌋ strands a row", "lavapipe's largest image side"),
    ("docs/pipeline.md", "the 30th frame of the scripted shake", "an example's frame"),
    ("docs/pipeline.md", "magnified 100 times", "an example's magnification"),
    (
        "docs/pipeline.md",
        "red the device's largest, 64 on lavapipe",
        "lavapipe's largest tessellation level",
    ),
    ("docs/grooms.md", "a 10K-strand head of hair", "an example"),
    ("docs/grooms.md", "need Rust 1.96", "a version"),
    ("docs/grooms.md", "tested with (1.95)", "the toolchain's version"),
    ("docs/robustness.md", "(130 after Ctrl-C)", "the shell's status for an interrupt"),
    ("docs/robustness.md", "exit status 130", "the shell's status for an interrupt"),
    ("docs/scene-files.md", "the 2018 demo's sphere", "the original demo's year"),
    ("docs/testing-drivers.md", "KhronosGroup/Vulkan-Loader#2018", "an issue's number"),
    ("README.md", "frames 28, 32, 36)", "the pictures' frames"),
    ("README.md", "**Checked on 2026-11-25**", "a date"),
    ("README.md", "| 1.3.239 | 2023.2, 12.0 |", "versions"),
    ("README.md", "| 1.4.309 | 2025.2, 15.1 |", "versions"),
    ("README.md", "the original 2018 demo", "the original demo's year"),
    (
        "README.md",
        "glslang has: 12 on Debian 12, 15 on Debian 13",
        "versions",
    ),
    ("docs/testing-truth.md", "Chiang et al. 2016,", "a year"),
    (
        "docs/testing-drivers.md",
        "\"deprecated in SPIR-V 1.6\": glslang 12 and 15 emit it",
        "versions",
    ),
    (
        "docs/testing-drivers.md",
        "SPIR-V 1.5 (Vulkan 1.2), where it is not deprecated, so that drivers without 1.3",
        "versions",
    ),
];

/// Names whose following number is their version (Debian 12, Mesa 22.3.6, glTF 2.0),
/// and in "Debian 12 and 13" the number after `and` or `or` too.
const VERSIONED: [&str; 9] = [
    "Debian", "Mesa", "LLVM", "glTF", "SPIR-V", "Vulkan", "glslang", "Rust", "Python",
];

/// `text` without the versions of [`VERSIONED`] names.
fn without_versions(text: &str) -> String {
    let words: Vec<&str> = text.split(' ').collect();
    let mut out = Vec::new();
    let mut i = 0;
    let starts_with_digit = |w: &str| w.starts_with(|c: char| c.is_ascii_digit());
    while i < words.len() {
        out.push(words[i]);
        let name = words[i].trim_start_matches(['(', '*', '[']);
        if VERSIONED.contains(&name) && words.get(i + 1).is_some_and(|w| starts_with_digit(w)) {
            i += 2;
            while words.get(i).is_some_and(|w| *w == "and" || *w == "or")
                && words.get(i + 1).is_some_and(|w| starts_with_digit(w))
            {
                i += 2;
            }
        } else {
            i += 1;
        }
    }
    out.join(" ")
}

/// Where a passage stands: a paragraph, an item of a list or a table (which belong to
/// the paragraph before them), or nested in an item (an indented item or paragraph).
#[derive(Clone, Copy, PartialEq)]
enum Place {
    Paragraph,
    Item,
    Nested,
}

/// The passages of `text`, each flattened, with where each stands: paragraphs, list
/// items, tables and headings.
fn passages(text: &str) -> Vec<(String, Place)> {
    let mut out: Vec<(String, Place)> = Vec::new();
    let mut current = String::new();
    let mut place = Place::Paragraph;
    let mut in_list = false;
    let mut blank = false;
    for line in text.lines() {
        let t = line.trim_start();
        let indented = t.len() < line.len();
        let row = t.starts_with('|');
        let item = t.starts_with("- ")
            || t.starts_with("* ")
            || t.split_once(". ")
                .is_some_and(|(n, _)| !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()));
        let table_goes_on = row && current.starts_with('|');
        // An indented paragraph after a blank line inside a list belongs to its item.
        let nested_paragraph = blank && indented && in_list && !item;
        if t.is_empty() || t.starts_with('#') || item || (row && !table_goes_on) || nested_paragraph
        {
            out.push((flat(&std::mem::take(&mut current)), place));
            place = match (item || row || nested_paragraph, indented) {
                (true, true) => Place::Nested,
                (true, false) => Place::Item,
                (false, _) => Place::Paragraph,
            };
        }
        if !t.is_empty() {
            in_list = place != Place::Paragraph;
        }
        blank = t.is_empty();
        current.push_str(t);
        current.push(' ');
        if t.starts_with('#') {
            out.push((flat(&std::mem::take(&mut current)), Place::Paragraph));
            in_list = false;
        }
    }
    out.push((flat(&current), place));
    out.into_iter().filter(|(p, _)| !p.is_empty()).collect()
}

/// Every function name in the test sources (the integration tests and the crates'
/// sources, whose unit tests live beside the code).
fn test_names() -> std::collections::HashSet<String> {
    fn walk(dir: &std::path::Path, names: &mut std::collections::HashSet<String>) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, names);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                for rest in text.split("fn ").skip(1) {
                    let name: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    names.insert(name);
                }
            }
        }
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut names = Default::default();
    for dir in ["tests", "crates", "src"] {
        walk(&root.join(dir), &mut names);
    }
    names
}

/// The tests a passage names (code spans of three or more words joined by `_` that are
/// functions of the test sources): in the testing pages, a passage that names its test
/// quotes that test's bound and what it measured.
fn named_tests(passage: &str, names: &std::collections::HashSet<String>) -> usize {
    passage
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|span| span.matches('_').count() >= 2 && names.contains(*span))
        .count()
}

/// How many marks a passage has naming what measures its figures: `measured by \`fur
/// bench --only SECTION\`` or `measured by \`FILE\``, a test file that prints them.
/// Errors name a mark that leads nowhere.
fn marks(passage: &str) -> Result<usize, String> {
    let sections: Vec<&str> = fur::bench::Section::ALL.iter().map(|s| s.name()).collect();
    let mut count = 0;
    for (at, mark) in passage.match_indices("measured by `") {
        let named = passage[at + mark.len()..]
            .split('`')
            .next()
            .unwrap_or_default();
        if let Some(section) = named.strip_prefix("fur bench --only ") {
            if !sections.contains(&section) {
                return Err(format!("no bench section `{section}`"));
            }
            count += 1;
        } else if named == "cargo mutants" {
            count += 1;
        } else if named.ends_with(".rs") {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(named);
            if !(named.contains("tests/") && path.is_file()) {
                return Err(format!("no test file `{named}`"));
            }
            count += 1;
        }
    }
    Ok(count)
}

/// Every figure in the prose of the documents is bound or marked: it stands in a phrase
/// built from the constant it states ([`stated`]), or its passage names what measures
/// it (`measured by \`fur bench --only SECTION\``, `measured by \`cargo mutants\``, or
/// a test file that prints it; in the testing pages, the test the passage names), as
/// does the paragraph a list or table follows, or it is one of [`NOT_MEASURED`]
/// (years, versions, an example's settings). Seen failing with a figure added to a
/// passage without a mark, with a default written wrong (`--friction` 0.2), and with a
/// mark naming a section the benchmark does not have.
#[test]
fn every_figure_in_the_documents_prose_is_bound_or_marked() {
    let stated = stated();
    let names = test_names();
    let mut unbound = Vec::new();
    for doc in PROSE {
        let bound: Vec<&String> = stated
            .iter()
            .filter(|(d, _)| *d == doc)
            .flat_map(|(_, p)| p)
            .collect();
        // Whether the paragraph a list or table follows is marked, and the item a
        // nested passage belongs to.
        let (mut intro, mut parent) = (false, false);
        let mut text = read(doc);
        if doc == "README.md" {
            // Its "What to expect" section quotes the runs: docs.rs binds it.
            let start = text
                .find("\n## What to expect")
                .expect("the README's results");
            let end = text[start + 1..]
                .find("\n## ")
                .map_or(text.len(), |e| start + 1 + e);
            text.replace_range(start..end, "");
        }
        for (passage, place) in passages(&common::prose(&text)) {
            let tests = if doc.starts_with("docs/testing") || doc == "docs/mutation-runs.md" {
                named_tests(&passage, &names)
            } else {
                0
            };
            let marked = marks(&passage).map(|m| m + tests);
            let own = marked.as_ref().is_ok_and(|&m| m > 0);
            let inherited = match place {
                Place::Paragraph => {
                    intro = own;
                    false
                }
                Place::Item => {
                    parent = own || intro;
                    intro
                }
                Place::Nested => parent || intro,
            };
            match marked {
                Err(why) => unbound.push(format!("{doc}: {why} in {passage:?}")),
                Ok(0) if !inherited => {
                    let mut text = passage.clone();
                    for phrase in &bound {
                        text = text.replace(phrase.as_str(), " ");
                    }
                    for (_, phrase, _) in NOT_MEASURED.iter().filter(|(d, _, _)| *d == doc) {
                        text = text.replace(phrase, " ");
                    }
                    let text = without_versions(&text);
                    for n in common::numbers(&common::without_code_and_links(&text)) {
                        // Versions (1.4.309) are names, not figures.
                        let version = n.matches('.').count() >= 2;
                        if (n.len() > 1 || n.contains('.')) && !version {
                            unbound.push(format!("{doc}: {n} in {passage:?}"));
                        }
                    }
                }
                Ok(_) => {}
            }
        }
    }
    for (doc, phrase, what) in NOT_MEASURED {
        if !flat(&read(doc)).contains(phrase) {
            unbound.push(format!("{doc} no longer says {phrase:?} ({what})"));
        }
    }
    assert!(
        unbound.is_empty(),
        "{} figures neither stated by the code nor marked as measured:\n{}",
        unbound.len(),
        unbound.join("\n")
    );
}

/// Every test a document names exists: a code span of four or more lower-case words
/// joined by `_` is a function of the sources (seen failing on a test renamed by a
/// search-and-replace, `impossible_budgets_and_frame_rates_are_assert_fails_cleanly`,
/// that docs/testing.md still cited by its old name).
#[test]
fn the_tests_the_documents_name_exist() {
    let names = test_names();
    let mut missing = Vec::new();
    for doc in PROSE
        .iter()
        .chain(&["docs/benchmark.md", "docs/ground-truth.md"])
    {
        let text = read(doc);
        for span in text.split('`').skip(1).step_by(2) {
            let snake = !span.is_empty()
                && span
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
            if snake && span.matches('_').count() >= 3 && !names.contains(span) {
                missing.push(format!("{doc}: `{span}`"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "tests the documents name but the sources do not have:\n{}",
        missing.join("\n")
    );
}
