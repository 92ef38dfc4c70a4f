//! Errors of the writers and readers. Every [`IoError`] names the file,
//! because "permission denied" without a path is useless in a batch run;
//! what is wrong with the fabric or the options is an [`ExportError`], which
//! also stands alone where no file is involved
//! ([`render_preview`](super::render_preview)).

use std::io;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum IoError {
    #[error("cannot write {}: {source}", path.display())]
    Write { path: PathBuf, source: io::Error },

    #[error("cannot read {}: {source}", path.display())]
    Read { path: PathBuf, source: io::Error },

    /// Malformed or mistyped JSON; `line` and `column` are 1-based as
    /// serde_json reports them.
    #[error("{}:{line}:{column}: invalid fabric JSON: {message}", path.display())]
    Json {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },

    /// The fabric cannot be written (or was read but is inconsistent).
    #[error("{}: {source}", path.display())]
    Export { path: PathBuf, source: ExportError },
}

/// Why a fabric cannot be exported with the given options. Found before any
/// byte is written, so a bad state never replaces a good file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExportError {
    #[error("yarn {yarn} uses yarn spec {spec}, but only {count} are defined")]
    SpecOutOfRange { yarn: usize, spec: usize, count: usize },

    #[error("yarn {yarn} point {point} refers to node {node}, but there are {count} nodes")]
    NodeOutOfRange {
        yarn: usize,
        point: usize,
        node: usize,
        count: usize,
    },

    #[error("contact {contact} refers to a missing node or yarn point")]
    ContactOutOfRange { contact: usize },

    #[error("node {node} has a non-finite position (diverged simulation?)")]
    NonFinitePosition { node: usize },

    #[error("yarn spec {spec} has radius {radius}; a drawable radius is finite and positive")]
    BadRadius { spec: usize, radius: f64 },

    #[error("the fabric has no yarn points to draw")]
    NothingToDraw,

    #[error("invalid image scale {0}: pixels per mm and width must be positive")]
    BadScale(String),

    #[error("the image would be {width} x {height} pixels, more than the limit of {max} per side")]
    ImageTooLarge { width: u64, height: u64, max: u32 },
}
