//! Errors of the SDPA reader and writer.

use std::path::PathBuf;

/// A number of GiB for a message: three decimals, or three significant
/// digits in exponent form when large.
pub(crate) fn gib(x: f64) -> String {
    if x < 1e6 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

/// What can go wrong reading, writing or converting an SDPA file. Every
/// variant names the place: the file, its 1-based line, the block or the
/// entry (docs/inputs.md, "SDPA problems").
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
    /// The file is not UTF-8 text.
    #[error("{path}: line {line}: not UTF-8 text")]
    Encoding {
        /// The file.
        path: PathBuf,
        /// 1-based line of the first invalid byte.
        line: usize,
    },
    /// A malformed line, a number that is not one, a non-finite value, or
    /// an entry outside the declared sizes.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The file ended before the header's declared sizes were met.
    #[error("unexpected end of file: {0}")]
    UnexpectedEof(String),
    /// The same matrix entry given twice (either triangle).
    #[error(
        "line {line}: entry (matrix {matrix}, block {block}, {row}, {col}) was already given on line {first_line}; \
         give each entry once (either triangle, not both)"
    )]
    Duplicate {
        /// 1-based line of the repeat.
        line: usize,
        /// 1-based line of the first occurrence.
        first_line: usize,
        /// Matrix number (0 = F₀).
        matrix: usize,
        /// 1-based block number.
        block: usize,
        /// 1-based row (≤ col).
        row: usize,
        /// 1-based column.
        col: usize,
    },
    /// A problem built in code (not parsed) that breaks the format's rules.
    #[error("{what}: {message}")]
    Invalid {
        /// Where: `entries[k]`, `blocks[k]`, `c[k]`.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// A size whose arithmetic overflows, or beyond a fixed limit of the
    /// solver's indices.
    #[error("{what} = {value}: {reason}")]
    Limit {
        /// The size (e.g. "block 1 side").
        what: String,
        /// Its value.
        value: String,
        /// The limit or the overflow.
        reason: String,
    },
    /// The solve would need more memory than allowed.
    #[error(
        "{what} would need about {} GiB ({detail}), more than the limit of {} GiB; \
         raise the limit (max_memory_gib) only if the machine has that much",
        gib(*.needed_gib),
        gib(*.limit_gib)
    )]
    TooLarge {
        /// What would need it: "the solve", "reading FILE".
        what: String,
        /// The estimate in GiB.
        needed_gib: f64,
        /// The limit in GiB.
        limit_gib: f64,
        /// The estimate's parts.
        detail: String,
    },
    /// An invalid reader option.
    #[error("invalid SDPA option {name}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Why.
        reason: String,
    },
    /// Building one block's constraint failed (e.g. two finite values whose
    /// sum overflows to infinity).
    #[error("block {block}: {source}")]
    Block {
        /// 1-based block number.
        block: usize,
        /// The conic layer's error.
        source: crate::conic::ConicError,
    },
    /// Building or converting the conic problem failed.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
}
