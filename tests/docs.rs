//! The documents agree with themselves: every figure the README's "What to expect"
//! section quotes appears in docs/benchmark.md (which `fur bench --write-docs` writes),
//! every link between the documents leads to a file, and the README stays a front page.

#[path = "common/mod.rs"]
mod common;

use common::{flat, numbers, read_doc as read, without_code_and_links};
#[path = "docs/truth_ratios.rs"]
mod truth_ratios;
use std::path::Path;
use truth_ratios::{truth_ratios, TruthRatios};

/// The README's section that starts at `heading` up to the next `## ` heading.
fn section<'a>(text: &'a str, heading: &str) -> &'a str {
    let start = text
        .find(heading)
        .unwrap_or_else(|| panic!("no `{heading}` section"));
    let rest = &text[start + heading.len()..];
    &rest[..rest.find("\n## ").unwrap_or(rest.len())]
}

#[test]
fn the_figures_the_readme_quotes_come_from_the_benchmark_document() {
    let readme = read("README.md");
    // One run's tables in each document: the benchmark's sections, and the truth.
    let benchmark = format!(
        "{}\n{}",
        generated(&read("docs/benchmark.md")),
        generated(&read("docs/ground-truth.md"))
    );
    let expect = section(&readme, "## What to expect");
    // The GPU's table quotes docs/gpu.md (the next test); the rest quotes lavapipe's run.
    let expect: String = expect
        .split("\n\n")
        .filter(|t| !is_gpu_table(t))
        .collect::<Vec<_>>()
        .join("\n\n");
    let expect = expect.as_str();
    let quoted: Vec<String> = expect
        .lines()
        .filter(|l| l.starts_with('|') && !l.starts_with("| ---"))
        .skip(1) // the header row
        // The first cell names what is measured ("the original 2018 demo's scene").
        .flat_map(|l| numbers(&l.split('|').skip(2).collect::<Vec<_>>().join("|")))
        .filter(|n| n.len() > 1 || n.contains('.'))
        .collect();
    assert!(
        quoted.len() >= 4,
        "the README quotes no figures: {quoted:?}"
    );
    // Whole numbers of the generated tables, not substrings of the document: 45.3
    // must not be found inside 145.3, nor in prose outside the run.
    let generated = benchmark.as_str();
    let held: std::collections::HashSet<String> = numbers(generated).into_iter().collect();
    let missing: Vec<&String> = quoted.iter().filter(|n| !held.contains(*n)).collect();
    assert!(
        missing.is_empty(),
        "figures in the README's \"What to expect\" that the run's tables (docs/benchmark.md, docs/ground-truth.md) do not hold: {missing:?}"
    );
    // The tables the README copies row by row (the quality ladder, the ways of colliding
    // with a walking body, the drawings against the truth): each figure of a row is the
    // exact cell under the same column of one row of the run's tables, so a figure cannot
    // be taken from the wrong row or column, nor be a part of a cell.
    let run_tables = tables(generated);
    let mut copied = 0;
    for (header, rows) in tables(expect).into_iter().filter(|(h, _)| {
        matches!(
            h.first().map(String::as_str),
            Some("rung" | "way" | "drawing")
        )
    }) {
        for row in rows {
            let figures: Vec<(&str, &str)> = header
                .iter()
                .zip(&row)
                .filter(|(_, cell)| cell.starts_with(|c: char| c.is_ascii_digit()))
                .map(|(h, c)| (h.as_str(), c.as_str()))
                .collect();
            assert!(!figures.is_empty(), "README row {row:?} holds no figures");
            let found = run_tables.iter().any(|(run_header, run_rows)| {
                let column = |name: &str| run_header.iter().position(|h| h == name);
                figures.iter().all(|(name, _)| column(name).is_some())
                    && run_rows.iter().any(|run_row| {
                        figures.iter().all(|(name, cell)| {
                            column(name)
                                .and_then(|i| run_row.get(i))
                                .map(String::as_str)
                                == Some(*cell)
                        })
                    })
            });
            assert!(
                found,
                "README row {row:?}: its figures {figures:?} are not the cells of one row of the run's tables"
            );
            copied += 1;
        }
    }
    assert!(copied >= 10, "only {copied} README rows checked row by row");
}

/// The cells of a table row, trimmed, without the empty ends.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    inner.split('|').map(|c| c.trim().to_string()).collect()
}

/// The tables of `text`: each as its header's cells and its rows' cells.
fn tables(text: &str) -> Vec<(Vec<String>, Vec<Vec<String>>)> {
    let mut out: Vec<(Vec<String>, Vec<Vec<String>>)> = Vec::new();
    let mut in_table = false;
    for line in text.lines() {
        if !line.starts_with('|') {
            in_table = false;
        } else if !in_table {
            out.push((cells(line), Vec::new()));
            in_table = true;
        } else if !line.starts_with("| ---") {
            if let Some((_, rows)) = out.last_mut() {
                rows.push(cells(line));
            }
        }
    }
    out
}

/// Whether `table` (a paragraph of the README) is its table of figures from a GPU run.
fn is_gpu_table(table: &str) -> bool {
    table.lines().next().unwrap_or("").starts_with("| on the ")
}

/// The lines of `text` that are table rows, as the numbers each holds.
fn table_rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .filter(|l| l.starts_with('|'))
        .map(numbers)
        .collect()
}

#[test]
fn the_gpu_figures_the_readme_quotes_come_from_the_gpu_run() {
    let readme = read("README.md");
    let gpu = read("docs/gpu.md");
    let rows = table_rows(region(&gpu, "fur gpu-bench"));
    assert!(rows.len() > 20, "docs/gpu.md's region holds no tables");
    let expect = section(&readme, "## What to expect");
    let mut checked = 0;
    for table in expect.split("\n\n").filter(|t| is_gpu_table(t)) {
        for line in table.lines().skip(2) {
            // Each README row's figures (past the cell naming it) stand in one row of
            // the run's tables, so none is taken from the wrong scene.
            let cells = line.split('|').skip(2).collect::<Vec<_>>().join("|");
            let figures: Vec<String> = numbers(&cells)
                .into_iter()
                .filter(|n| n.len() > 1 || n.contains('.'))
                .collect();
            assert!(
                figures.len() >= 2,
                "README GPU row {line:?} quotes no figures"
            );
            assert!(
                rows.iter().any(|row| figures.iter().all(|f| row.contains(f))),
                "README GPU row {line:?}: its figures {figures:?} are not one row of docs/gpu.md's run"
            );
            checked += 1;
        }
    }
    assert!(checked >= 3, "only {checked} README GPU rows checked");
}

/// Whether git would leave `path` out of a commit (false where git or the
/// repository is absent, as in a packaged source tree).
fn git_ignores(path: &Path) -> bool {
    std::process::Command::new("git")
        .arg("check-ignore")
        .arg("--quiet")
        .arg(path)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .status()
        .map(|status| status.success())
        .unwrap_or(false)
}

/// The part of docs/benchmark.md that `fur bench --write-docs` writes.
fn generated(benchmark: &str) -> &str {
    region(benchmark, "fur bench")
}

/// The part of a document between its `<!-- BEGIN {name} -->` and `<!-- END {name} -->`
/// lines: what a tool wrote there.
fn region<'a>(doc: &'a str, name: &str) -> &'a str {
    let begin = doc
        .find(&format!("<!-- BEGIN {name} -->"))
        .unwrap_or_else(|| panic!("no `<!-- BEGIN {name} -->` marker"));
    let end = doc
        .find(&format!("<!-- END {name} -->"))
        .unwrap_or_else(|| panic!("no `<!-- END {name} -->` marker"));
    &doc[begin..end]
}

/// Every document: the README and each page of docs/, by path from the root (read
/// from the folder, so a new page is checked without a list to keep).
fn documents() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    let mut pages: Vec<String> = std::fs::read_dir(&dir)
        .expect("docs/ lists")
        .map(|entry| entry.expect("a docs/ entry").file_name())
        .filter_map(|name| name.to_str().map(str::to_string))
        .filter(|name| name.ends_with(".md"))
        .map(|name| format!("docs/{name}"))
        .collect();
    pages.sort();
    assert!(pages.len() > 10, "only {} pages in docs/", pages.len());
    std::iter::once("README.md".to_string())
        .chain(pages)
        .collect()
}

#[test]
fn links_between_the_documents_lead_to_files() {
    for doc in documents() {
        let doc = doc.as_str();
        let text = read(doc);
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(doc)
            .parent()
            .unwrap()
            .to_path_buf();
        let mut rest = text.as_str();
        while let Some(i) = rest.find("](") {
            rest = &rest[i + 2..];
            let end = rest.find(')').unwrap_or(rest.len());
            let target = &rest[..end];
            rest = &rest[end..];
            let file = target.split('#').next().unwrap_or("");
            if file.is_empty() || file.contains("://") {
                continue;
            }
            assert!(
                dir.join(file).exists(),
                "{doc} links to {target}, which is not there"
            );
            assert!(
                !git_ignores(&dir.join(file)),
                "{doc} links to {target}, which git ignores: a fresh clone will not have it"
            );
        }
    }
}

#[test]
fn the_readme_is_a_front_page() {
    let readme = read("README.md");
    let lines = readme.lines().count();
    assert!(
        lines <= 250,
        "README.md is {lines} lines; the depth belongs in docs/"
    );
    // The two commands the README promises: set-up and run, and the tests.
    assert!(readme.contains("cargo run --release"), "no run command");
    assert!(readme.contains("cargo test --locked"), "no test command");
}

#[test]
fn numbers_are_read_as_written() {
    assert_eq!(
        numbers("| 271.1 ms | 5.2× | 1,400 |"),
        ["271.1", "5.2", "1,400"]
    );
}

/// Every source path the documents name (`src/…`, `tests/…`, `shaders/…`, `crates/…`,
/// `tools/…`, in backticks or as a link) is a file or folder of the tree: a file moved
/// or renamed without its docs fails here.
#[test]
fn the_files_the_documents_name_exist() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut missing = Vec::new();
    for doc in documents() {
        let doc = doc.as_str();
        let text = read(doc);
        for prefix in ["src/", "tests/", "shaders/", "crates/", "tools/"] {
            for (i, _) in text.match_indices(prefix) {
                let before = text[..i].chars().next_back();
                if !matches!(before, Some('`') | Some('/') | Some('(')) {
                    continue;
                }
                if before == Some('/') && !text[..i].ends_with("../") {
                    continue;
                }
                let path: String = text[i..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || "_./-".contains(*c))
                    .collect();
                // A pattern (`shaders/mesh.*`) names no one file.
                if text[i + path.len()..].starts_with('*') {
                    continue;
                }
                let path = path.trim_end_matches(['.', '/']);
                if !root.join(path).exists() {
                    missing.push(format!("{doc}: {path}"));
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "named but not there:\n{}",
        missing.join("\n")
    );
}

/// The README's sentences on the two lighting models hold the ratios worked out from the
/// run ([`truth_ratios`]), and the verdict it draws from them (within half or not).
#[test]
fn the_ratios_the_readme_draws_from_the_truth_are_the_runs() {
    let TruthRatios {
        scenes: ratios,
        colours,
        fastest,
        slowest,
        ..
    } = truth_ratios();
    let readme = flat(&read("README.md"));
    let near = format!(
        "It is at {:.2} of Kajiya–Kay's distance on the blob, {:.2} on the sphere, {:.2} on \
         the walking critter, {:.2} on a groom drawn as it is, {:.2} on white fur, {:.2} on \
         blond fur, {:.2} on black fur and {:.2} on tabby fur, at \
         {fastest:.1}–{slowest:.1}× its frame time here",
        ratios[0], ratios[1], ratios[2], ratios[3], colours[0], colours[1], colours[2], colours[3]
    );
    // The verdict the README draws: within half everywhere, or "short of half".
    let all_within = ratios.iter().chain(&colours).all(|r| *r <= 0.5);
    let verdict = if all_within {
        "within half of Kajiya–Kay's distance on every scene and fur".to_string()
    } else {
        "short of half".to_string()
    };
    for sentence in [&near, &verdict] {
        assert!(
            readme.contains(sentence.as_str()),
            "the README does not say, from the run: \"{sentence}\""
        );
    }
    if all_within {
        assert!(
            !readme.contains("short of half"),
            "the README says a fur is short of half, but the run has every one within it"
        );
    }
}

/// Every figure in the prose of the README's "What to expect" (outside its tables, code
/// and links) is a figure of a generated run: a whole number of the regions written by
/// `fur bench --write-docs` (docs/benchmark.md, docs/ground-truth.md) or
/// `tools/gpu-bench.sh --write-docs` (docs/gpu.md), or one of the ratios worked out in
/// [`truth_ratios`].
#[test]
fn the_readme_prose_figures_come_from_the_runs() {
    let readme = read("README.md");
    let expect = section(&readme, "## What to expect");
    let held: std::collections::HashSet<String> = [
        generated(&read("docs/benchmark.md")),
        generated(&read("docs/ground-truth.md")),
        region(&read("docs/gpu.md"), "fur gpu-bench"),
    ]
    .iter()
    .flat_map(|text| numbers(text))
    .collect();
    // The ratios the README derives from the truth tables (checked in their sentence).
    let derived = truth_ratios().derived();
    let mut missing = Vec::new();
    for line in expect.lines().filter(|l| !l.starts_with('|')) {
        for n in numbers(&without_code_and_links(line)) {
            if (n.len() > 1 || n.contains('.')) && !held.contains(&n) && !derived.contains(&n) {
                missing.push(n);
            }
        }
    }
    assert!(
        missing.is_empty(),
        "figures in the README's \"What to expect\" prose that no generated run holds: {missing:?}"
    );
}

/// Figures the measured documents state outside their generated regions that no run
/// measures, each with what it is: versions, years, the image sizes and the camera a
/// section is defined by, and the calibration's test sizes.
const NOT_MEASURED: [(&str, &str, &str); 14] = [
    ("docs/gpu.md", "500", "the goal: 500K drawn hairs"),
    ("docs/benchmark.md", "22.3", "Mesa's version"),
    ("docs/benchmark.md", "2018", "the original demo's year"),
    (
        "docs/benchmark.md",
        "45",
        "the sphere scene's field of view, in degrees",
    ),
    ("docs/benchmark.md", "1920", "the goal's resolution"),
    ("docs/benchmark.md", "1080", "the goal's resolution"),
    ("docs/benchmark.md", "320", "the truth section's resolution"),
    ("docs/benchmark.md", "180", "the truth section's resolution"),
    ("docs/ground-truth.md", "2016", "Chiang et al.'s year"),
    ("docs/ground-truth.md", "3.9", "Mitsuba's version"),
    ("docs/ground-truth.md", "32", "32-bit floats"),
    (
        "docs/ground-truth.md",
        "96",
        "the calibration test's width (tests/truth/)",
    ),
    (
        "docs/ground-truth.md",
        "54",
        "the calibration test's height (tests/truth/)",
    ),
    (
        "docs/ground-truth.md",
        "0.03",
        "the calibration strands' width (tests/truth/)",
    ),
];

/// The prose of the measured documents (docs/benchmark.md, docs/ground-truth.md,
/// docs/gpu.md) around their generated regions quotes only figures of a run: every
/// figure there is a whole number of one of the three regions (commas aside), a ratio
/// or difference worked out from the truth tables ([`TruthRatios::derived`]), the fibre's defaults (bound to the code by
/// tests/stated_figures.rs), or one of [`NOT_MEASURED`].
#[test]
fn the_measured_documents_prose_quotes_their_runs() {
    let docs = [
        ("docs/benchmark.md", "fur bench"),
        ("docs/ground-truth.md", "fur bench"),
        ("docs/gpu.md", "fur gpu-bench"),
    ];
    let plain = |n: &str| n.replace(',', "");
    let mut held: std::collections::HashSet<String> = docs
        .iter()
        .flat_map(|(doc, name)| numbers(region(&read(doc), name)))
        .map(|n| plain(&n))
        .collect();
    // The ratios and the distances between the two models, per scene and fur colour.
    held.extend(truth_ratios().derived());
    let fibre = fur_core::render::Fibre::default();
    held.extend(
        [
            fibre.longitudinal_roughness,
            fibre.azimuthal_roughness,
            fibre.ior,
        ]
        .map(|x| x.to_string()),
    );
    // The goal's body's vertices (`dense-sphere`: its masters), bound to the code by
    // tests/stated_figures.rs.
    let dense: fur_core::scene::ModelSpec = "dense-sphere".parse().unwrap();
    held.insert(dense.load().unwrap().positions.len().to_string());
    let mut unheld = Vec::new();
    for (doc, name) in docs {
        let text = read(doc);
        // The region the run writes must be there; around it, the prose without its
        // fenced blocks, then without code spans (which may run over a line end) and
        // link targets.
        assert!(
            !region(&text, name).is_empty(),
            "{doc} has no `{name}` region"
        );
        for line in without_code_and_links(&common::prose(&text)).lines() {
            for n in numbers(line) {
                let figure = n.len() > 1 || n.contains('.');
                let excepted = NOT_MEASURED.iter().any(|(d, f, _)| *d == doc && *f == n);
                if figure && !held.contains(&plain(&n)) && !excepted {
                    unheld.push(format!("{doc}: {n} in {line:?}"));
                }
            }
        }
    }
    assert!(
        unheld.is_empty(),
        "figures in the measured documents' prose that no run holds:\n{}",
        unheld.join("\n")
    );
}
