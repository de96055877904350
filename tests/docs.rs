//! The documents agree with themselves: every figure the README's "What to expect"
//! section quotes appears in docs/benchmark.md (which `fur bench --write-docs` writes),
//! every link between the documents leads to a file, and the README stays a front page.

use std::path::Path;

fn read(path: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The numbers in `text` (digits with an optional decimal part), as written.
fn numbers(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for c in text.chars().chain(std::iter::once(' ')) {
        if c.is_ascii_digit()
            || (c == '.' && !current.is_empty())
            || (c == ',' && !current.is_empty())
        {
            current.push(c);
        } else if !current.is_empty() {
            let n = current.trim_end_matches(['.', ',']).to_string();
            out.push(n);
            current.clear();
        }
    }
    out
}

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
    // with a walking body): each row's figures all stand in one row of the run's tables,
    // so a figure cannot be taken from the wrong row.
    let rows = table_rows(generated);
    let mut copied = 0;
    for table in expect.split("\n\n").filter(|t| {
        let header = t.lines().next().unwrap_or("");
        header.starts_with("| rung |")
            || header.starts_with("| way |")
            || header.starts_with("| drawing |")
    }) {
        for line in table.lines().skip(2) {
            let figures: Vec<String> = numbers(line)
                .into_iter()
                .filter(|n| n.len() > 1 || n.contains('.'))
                .collect();
            let found = rows
                .iter()
                .any(|row| figures.iter().all(|f| row.contains(f)));
            assert!(
                found,
                "README row {line:?}: its figures {figures:?} are not one row of the run's tables"
            );
            copied += 1;
        }
    }
    assert!(copied >= 10, "only {copied} README rows checked row by row");
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

#[test]
fn links_between_the_documents_lead_to_files() {
    for doc in [
        "README.md",
        "docs/design.md",
        "docs/pipeline.md",
        "docs/benchmark.md",
        "docs/robustness.md",
        "docs/testing.md",
        "docs/scene-files.md",
        "docs/grooms.md",
    ] {
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
    for doc in [
        "README.md",
        "docs/design.md",
        "docs/pipeline.md",
        "docs/benchmark.md",
        "docs/ground-truth.md",
        "docs/robustness.md",
        "docs/testing.md",
        "docs/scene-files.md",
        "docs/grooms.md",
    ] {
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
