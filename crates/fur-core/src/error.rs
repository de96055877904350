//! The core's error type: every failure a user can cause or act on without a device,
//! named (the GPU layer's own errors wrap it).

use std::path::PathBuf;

/// Result alias used throughout the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in the scene, its files and the CPU references.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("cannot read model {path}: {message}")]
    Model { path: PathBuf, message: String },

    /// A texture image that cannot be read, decoded or used.
    #[error("cannot read texture {path}: {message}")]
    Texture { path: PathBuf, message: String },

    /// A groom file (guide curves) that cannot be read, decoded or bound to the body.
    #[error("cannot read groom {path}: {message}")]
    Groom { path: PathBuf, message: String },

    #[error("invalid parameter: {0}")]
    Parameter(String),

    #[error("cannot write image {path}: {message}")]
    ImageWrite { path: PathBuf, message: String },

    /// A file-system operation (write, create a folder, rename) on a path failed.
    #[error("cannot {operation} {path}: {message}")]
    Io {
        operation: &'static str,
        path: PathBuf,
        message: String,
    },

    #[error("interrupted")]
    Interrupted,

    /// A scene file that cannot be read, parsed or applied; line 0 when no line applies.
    #[error("scene file {}: {message}", location(path, *line, *column))]
    SceneFile {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
}

impl Error {
    /// An [`Error::Io`] from an `std::io::Error`.
    pub fn io(operation: &'static str, path: &std::path::Path, error: std::io::Error) -> Self {
        Error::Io {
            operation,
            path: path.to_path_buf(),
            message: error.to_string(),
        }
    }
}

/// `path:line:column`, or the path alone without a line.
fn location(path: &std::path::Path, line: usize, column: usize) -> String {
    if line == 0 {
        path.display().to_string()
    } else {
        format!("{}:{line}:{column}", path.display())
    }
}

/// A byte count for people: `2 GiB`, `3.5 MiB`, `120 bytes`.
pub fn size_text(bytes: u64) -> String {
    const GIB: f64 = (1u64 << 30) as f64;
    const MIB: f64 = (1u64 << 20) as f64;
    let b = bytes as f64;
    if b >= GIB {
        format!("{} GiB", trim_number(b / GIB))
    } else if b >= MIB {
        format!("{} MiB", trim_number(b / MIB))
    } else {
        format!("{bytes} bytes")
    }
}

fn trim_number(x: f64) -> String {
    let text = format!("{x:.1}");
    text.strip_suffix(".0").map_or(text.clone(), str::to_string)
}
