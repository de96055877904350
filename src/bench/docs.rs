//! A run's tables in a document: between the document's `<!-- BEGIN fur bench -->` and
//! `<!-- END fur bench -->` lines, headed by a line naming the sections the run
//! measured, so a later run can only replace them with the same sections (a document's
//! figures all come from one run: docs/benchmark.md holds every section, docs/pipeline.md
//! the stage views alone).

use std::path::Path;

use super::Section;
use fur_gpu::error::{CoreError, Error, Result};

/// The lines between which [`write_docs`] puts the tables.
pub const DOCS_BEGIN: &str = "<!-- BEGIN fur bench -->";
pub const DOCS_END: &str = "<!-- END fur bench -->";

/// The line naming the sections a document's tables hold.
const SECTIONS_LINE: &str = "<!-- sections: ";

fn sections_line(sections: &[Section]) -> String {
    let names: Vec<&str> = sections.iter().map(|s| s.name()).collect();
    format!("{SECTIONS_LINE}{} -->", names.join(", "))
}

/// The sections the tables of `text`'s region hold: those its sections line names,
/// every section for tables without the line, none for an empty region.
fn sections_held(text: &str) -> Option<Vec<String>> {
    let (before, after) = fur_core::files::region(text, DOCS_BEGIN, DOCS_END)?;
    let inside = text[before.len()..text.len() - after.len()].trim();
    if inside.is_empty() {
        return Some(Vec::new());
    }
    Some(
        match inside
            .lines()
            .next()
            .and_then(|l| l.strip_prefix(SECTIONS_LINE))
        {
            Some(rest) => rest
                .trim_end_matches("-->")
                .split(',')
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty())
                .collect(),
            None => Section::ALL.iter().map(|s| s.name().to_string()).collect(),
        },
    )
}

/// Checks, before a run of `sections`, that `path` is a Markdown file with the
/// benchmark's markers whose tables (if any) are of the same sections: a run of some
/// sections never replaces a document's tables of others.
pub fn check_docs(path: &Path, sections: &[Section]) -> Result<()> {
    fur_core::files::check_region(path, DOCS_BEGIN, DOCS_END)?;
    let text =
        fur_core::files::read_text_bounded(path, fur_core::files::MAX_SCENE_BYTES, "document")
            .map_err(|message| {
                Error::Core(CoreError::Io {
                    operation: "read the document",
                    path: path.to_path_buf(),
                    message,
                })
            })?;
    let held = sections_held(&text).unwrap_or_default();
    let running: Vec<String> = sections.iter().map(|s| s.name().to_string()).collect();
    if !held.is_empty() && held != running {
        return Err(Error::parameter(format!(
            "{} holds the tables of one run of the sections {}; this run measures {}: run \
             the same sections (`--only {}`) so its figures all come from one run",
            path.display(),
            held.join(", "),
            running.join(", "),
            held.join(" --only "),
        )));
    }
    Ok(())
}

/// Replaces the tables between the markers of the Markdown file at `path` with
/// `markdown` (a run of `sections`' `results.md`), headed by the sections line,
/// leaving the rest of the document as it is.
pub fn write_docs(path: &Path, sections: &[Section], markdown: &str) -> Result<()> {
    let tables = format!("{}\n\n{}", sections_line(sections), markdown.trim());
    Ok(fur_core::files::write_region(
        path, DOCS_BEGIN, DOCS_END, &tables,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("fur-docs-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("doc.md");
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn the_tables_replace_only_the_region_between_the_markers() {
        let path = temp(
            "region",
            &format!(
                "# Benchmark\n\nHow to read.\n\n{DOCS_BEGIN}\nold table\n{DOCS_END}\n\nNotes.\n"
            ),
        );
        write_docs(&path, &Section::ALL, "| new | table |").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("# Benchmark\n\nHow to read."), "{text}");
        assert!(
            text.contains("| new | table |") && !text.contains("old table"),
            "{text}"
        );
        assert!(text.trim_end().ends_with("Notes."), "{text}");
        std::fs::write(&path, "no markers here").unwrap();
        let err = write_docs(&path, &Section::ALL, "x")
            .unwrap_err()
            .to_string();
        assert!(err.contains(DOCS_BEGIN), "{err}");
    }

    /// An empty region takes any run; tables of one set of sections are replaced only
    /// by a run of the same set; tables without a sections line are a full run's.
    #[test]
    fn a_run_replaces_only_tables_of_its_own_sections() {
        let empty = temp("empty", &format!("{DOCS_BEGIN}\n{DOCS_END}\n"));
        check_docs(&empty, &[Section::Stages]).unwrap();
        write_docs(&empty, &[Section::Stages], "| view |").unwrap();
        check_docs(&empty, &[Section::Stages]).unwrap();
        let err = check_docs(&empty, &Section::ALL).unwrap_err().to_string();
        assert!(err.contains("--only stages"), "{err}");
        let full = temp("full", &format!("{DOCS_BEGIN}\n| old |\n{DOCS_END}\n"));
        check_docs(&full, &Section::ALL).unwrap();
        let err = check_docs(&full, &[Section::Frame])
            .unwrap_err()
            .to_string();
        assert!(err.contains("this run measures frame"), "{err}");
    }
}
