//! Files in and out: inputs are read only from regular files and only up to a stated
//! size; outputs replace a regular file through a temporary file and a rename (never
//! half-written), and are written straight through anything else (a device, a FIFO,
//! standard output as `-`, a symbolic link's target), which is never replaced.

use std::fs::{File, Metadata};
use std::io::{Read as _, Write as _};
use std::os::unix::fs::FileTypeExt as _;
use std::path::{Path, PathBuf};

pub use crate::error::size_text;
use crate::error::{Error, Result};

/// The largest model (OBJ, glTF, .glb) or glTF buffer read, in bytes.
pub const MAX_MODEL_BYTES: u64 = 2 << 30;
/// The largest texture image file read, in bytes.
pub const MAX_TEXTURE_BYTES: u64 = 512 << 20;
/// The largest OBJ material library read, in bytes.
pub const MAX_MATERIAL_BYTES: u64 = 64 << 20;
/// The largest scene file read, in bytes.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The output name that means standard output.
pub const STDOUT: &str = "-";

/// What kind of file system object `metadata` describes, for messages.
pub fn kind_name(metadata: &Metadata) -> &'static str {
    let t = metadata.file_type();
    if t.is_dir() {
        "a folder"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_symlink() {
        "a symbolic link"
    } else {
        "a regular file"
    }
}

/// Reads the whole of `path`, which must be a regular file (a symbolic link to one is
/// followed) of at most `limit` bytes; `what` names the input in messages ("model",
/// "texture"). The size is checked before reading, and the read stops past `limit`
/// even if the file grows meanwhile. The error says what is wrong, without the path
/// (callers put it in their own error).
pub fn read_bounded(path: &Path, limit: u64, what: &str) -> std::result::Result<Vec<u8>, String> {
    let metadata = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        _ => e.to_string(),
    })?;
    if !metadata.is_file() {
        return Err(format!(
            "it is {}, not a regular file; a {what} is read only from a regular file",
            kind_name(&metadata)
        ));
    }
    if metadata.len() > limit {
        return Err(format!(
            "it is {}, over the {} limit for a {what}",
            size_text(metadata.len()),
            size_text(limit)
        ));
    }
    let file = File::open(path).map_err(|e| e.to_string())?;
    // The open file is checked again: the path may have been swapped meanwhile.
    let opened = file.metadata().map_err(|e| e.to_string())?;
    if !opened.is_file() {
        return Err(format!(
            "it is {}, not a regular file; a {what} is read only from a regular file",
            kind_name(&opened)
        ));
    }
    read_at_most(file, limit, opened.len(), what)
}

/// Reads `source` to its end, refusing it past `limit` bytes: at most `limit + 1`
/// bytes are read from it (the one past the limit says it is over), whatever the
/// source; `expected` (its stated size) only sizes the first allocation.
pub fn read_at_most(
    source: impl std::io::Read,
    limit: u64,
    expected: u64,
    what: &str,
) -> std::result::Result<Vec<u8>, String> {
    let mut bytes = Vec::with_capacity(expected.min(limit) as usize);
    source
        .take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "it grew past the {} limit for a {what} while being read",
            size_text(limit)
        ));
    }
    Ok(bytes)
}

/// Checks that `path` is a regular file (a symbolic link to one is followed) without
/// reading it; the error says what it is instead.
pub fn read_bounded_check(path: &Path) -> std::result::Result<(), String> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(m) => Err(format!("it is {}, not a regular file", kind_name(&m))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err("no such file".into()),
        Err(e) => Err(e.to_string()),
    }
}

/// Reads `path` as UTF-8 text with [`read_bounded`].
pub fn read_text_bounded(
    path: &Path,
    limit: u64,
    what: &str,
) -> std::result::Result<String, String> {
    let bytes = read_bounded(path, limit, what)?;
    String::from_utf8(bytes).map_err(|e| format!("it is not UTF-8 text ({e})"))
}

/// How an output path is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// Standard output (`-`).
    Stdout,
    /// A new file or a regular file: written to a temporary file in `final_path`'s folder
    /// and renamed over `final_path` (a symbolic link's target, so the link stays).
    Replace { final_path: PathBuf },
    /// Anything else (a device, a FIFO, a link to one, or a link that points nowhere yet):
    /// opened and written in place, never replaced.
    Through,
}

/// Decides how `path` is written; refuses a folder.
pub fn output_kind(path: &Path) -> std::result::Result<OutputKind, String> {
    if path.as_os_str() == STDOUT {
        return Ok(OutputKind::Stdout);
    }
    let link = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Ok(OutputKind::Replace {
                final_path: path.to_path_buf(),
            })
        }
        Err(e) => return Err(e.to_string()),
    };
    let (metadata, final_path) = if link.file_type().is_symlink() {
        match std::fs::canonicalize(path) {
            Ok(target) => match std::fs::metadata(&target) {
                Ok(m) => (m, target),
                Err(_) => return Ok(OutputKind::Through),
            },
            // A link to nothing (yet): writing through it creates its target.
            Err(_) => return Ok(OutputKind::Through),
        }
    } else {
        (link, path.to_path_buf())
    };
    if metadata.is_dir() {
        Err("it is a folder; give a file name".into())
    } else if metadata.is_file() {
        Ok(OutputKind::Replace { final_path })
    } else {
        Ok(OutputKind::Through)
    }
}

/// Writes `bytes` to `path` as [`output_kind`] says: a regular file (or a new one)
/// through a temporary file renamed into place, so an interrupted or failed write never
/// leaves half a file and a replaced file keeps its permissions; a device, FIFO or `-`
/// written directly, every write error reported (`/dev/full`: "No space left on
/// device"). `what` names the output in errors ("image", "scene file").
pub fn write_output(path: &Path, bytes: &[u8], what: &'static str) -> Result<()> {
    let error = |message: String| Error::Io {
        operation: what,
        path: path.to_path_buf(),
        message,
    };
    match output_kind(path).map_err(error)? {
        OutputKind::Stdout => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)
                .and_then(|()| out.flush())
                .map_err(|e| error(e.to_string()))
        }
        OutputKind::Through => {
            let mut file = std::fs::OpenOptions::new()
                .write(true)
                .create(true)
                .truncate(false)
                .open(path)
                .map_err(|e| error(e.to_string()))?;
            file.write_all(bytes)
                .and_then(|()| file.flush())
                .map_err(|e| error(e.to_string()))
        }
        OutputKind::Replace { final_path } => {
            replace(&final_path, bytes).map_err(|e| error(e.to_string()))
        }
    }
}

/// Writes `bytes` to a temporary file beside `path` (removed if anything fails), syncs
/// it to disk and renames it over `path`, keeping the old file's permissions (a new
/// file's are those the umask gives).
fn replace(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    // A new file gets the permissions any new file gets here (0666 less the umask), not
    // the temporary file's private 0600.
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut file = builder.tempfile_in(dir)?;
    file.write_all(bytes)?;
    if let Ok(old) = std::fs::metadata(path) {
        file.as_file().set_permissions(old.permissions())?;
    }
    file.as_file().sync_all()?;
    file.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// Checks, before any work, that an output can be written at `path`: standard output,
/// a device or a FIFO as it is; otherwise not a folder, in a folder that exists or can
/// be made and where a file can be created.
pub fn check_output_file(path: &Path) -> Result<()> {
    let error = |message: String| Error::Io {
        operation: "write the output file",
        path: path.to_path_buf(),
        message,
    };
    match output_kind(path).map_err(error)? {
        OutputKind::Stdout | OutputKind::Through => Ok(()),
        OutputKind::Replace { final_path } => {
            let dir = final_path
                .parent()
                .filter(|d| !d.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            check_output_dir(dir)
        }
    }
}

/// Checks, before any work, that files can be written into the folder `dir`. Folders
/// it has to make for the check it takes away again (only while empty), so a run that
/// fails later leaves none behind; writing a file makes its folder ([`write_output`]).
pub fn check_output_dir(dir: &Path) -> Result<()> {
    if let Ok(m) = std::fs::metadata(dir) {
        if !m.is_dir() {
            return Err(Error::Io {
                operation: "write into the folder",
                path: dir.to_path_buf(),
                message: format!("it is {}, not a folder", kind_name(&m)),
            });
        }
    }
    // The folders that do not exist yet, deepest first.
    let missing: Vec<&Path> = dir
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .take_while(|a| std::fs::symlink_metadata(a).is_err())
        .collect();
    let made = std::fs::create_dir_all(dir).map_err(|e| Error::io("create the folder", dir, e));
    let probe = dir.join(format!(".fur-write-check-{}", std::process::id()));
    let written = made.and_then(|()| {
        File::create(&probe).map_err(|e| Error::io("write into the folder", dir, e))
    });
    let _ = std::fs::remove_file(&probe);
    for folder in missing {
        // Fails, harmlessly, on a folder something else has put a file into meanwhile.
        let _ = std::fs::remove_dir(folder);
    }
    written.map(drop)
}

/// Splits `text` around the region between the lines `begin` and `end`: (before, with
/// the begin line; after, from the end line).
pub fn region<'a>(text: &'a str, begin: &str, end: &str) -> Option<(&'a str, &'a str)> {
    let start = text.find(begin)? + begin.len();
    let stop = start + text[start..].find(end)?;
    Some((&text[..start], &text[stop..]))
}

fn read_document(path: &Path) -> Result<String> {
    read_text_bounded(path, MAX_SCENE_BYTES, "document").map_err(|message| Error::Io {
        operation: "read the document",
        path: path.to_path_buf(),
        message,
    })
}

/// Checks that `path` is a Markdown file holding a `begin` line followed by an `end`
/// line, and can be written.
pub fn check_region(path: &Path, begin: &str, end: &str) -> Result<()> {
    if region(&read_document(path)?, begin, end).is_none() {
        return Err(Error::Io {
            operation: "write the tables into",
            path: path.to_path_buf(),
            message: format!("it has no `{begin}` line followed by a `{end}` line"),
        });
    }
    check_output_file(path)
}

/// Replaces what lies between the `begin` and `end` lines of the Markdown file at
/// `path` with `markdown`, leaving the rest of the document as it is.
pub fn write_region(path: &Path, begin: &str, end: &str, markdown: &str) -> Result<()> {
    check_region(path, begin, end)?;
    let text = read_document(path)?;
    let (before, after) = region(&text, begin, end).expect("checked above");
    let updated = format!("{before}\n\n{}\n\n{after}", markdown.trim());
    write_output(path, updated.as_bytes(), "write the tables into")
}

#[cfg(test)]
mod tests;
