//! Errors of the SDPA reader and writer.

use std::path::PathBuf;

/// What can go wrong reading, writing or converting an SDPA file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SdpaError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A malformed line.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The file ended early.
    #[error("unexpected end of file: {0}")]
    UnexpectedEof(String),
    /// Building or converting the conic problem failed.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
}
