//! Errors of data files.

use crate::numfmt::clip;

/// Errors of data files, each naming the file and, where it applies, the
/// row (1-based data row, the header is row 0) and column.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// A required column is missing.
    #[error(
        "{path}: missing column '{}' (header has: {})",
        clip(column),
        clip(header)
    )]
    MissingColumn {
        /// The file.
        path: String,
        /// The column.
        column: String,
        /// The header found.
        header: String,
    },
    /// A floating-base log that does not fit its robot.
    #[error("floating-base log: {message}")]
    Log {
        /// What is wrong, naming the array.
        message: String,
    },
    /// A sample the robot's dynamics refuse (a non-unit quaternion, …).
    #[error("floating-base log, sample {sample} (data row {}): {source}", sample + 1)]
    Sample {
        /// The sample (0-based).
        sample: usize,
        /// Why.
        #[source]
        source: crate::dynamics::DynamicsError,
    },
    /// A bad value.
    #[error("{path}: row {row}, column '{}': {}", clip(column), clip(message))]
    Value {
        /// The file.
        path: String,
        /// 1-based data row.
        row: usize,
        /// The column.
        column: String,
        /// What is wrong.
        message: String,
    },
    /// A malformed row.
    #[error("{path}: row {row}: {}", clip(message))]
    Row {
        /// The file.
        path: String,
        /// 1-based data row.
        row: usize,
        /// What is wrong.
        message: String,
    },
    /// The low-pass cut-off is not below the file's Nyquist frequency, or
    /// so low that one period of it, trimmed at each end, leaves no segment.
    #[error(
        "{path}: the low-pass cut-off {} Hz must be below half the sampling rate ({} Hz) and at least {} Hz (one period of it is trimmed at each end of a segment: the longest one here is {longest} samples)",
        crate::numfmt::short(*cutoff_hz),
        crate::numfmt::sig4(*nyquist_hz),
        crate::numfmt::sig4(*lowest_hz)
    )]
    Cutoff {
        /// The file.
        path: String,
        /// The requested cut-off (Hz).
        cutoff_hz: f64,
        /// Half the file's mean sampling rate (Hz).
        nyquist_hz: f64,
        /// The lowest cut-off that leaves the longest segment (Hz).
        lowest_hz: f64,
        /// The longest segment (samples).
        longest: usize,
    },
    /// Two outputs that would be the same file (e.g. a data file named
    /// `x.json` whose record is `x.json`).
    #[error("{path}: {message}")]
    Output {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// An input file that cannot be used as a whole (no samples, a
    /// format not read for it).
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// A column mapping that cannot be used.
    #[error("{path}: mapping: {message}")]
    Mapping {
        /// The mapping file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// An array (or topic, or message field) of a log file that is
    /// missing, misnamed, of the wrong shape or type, or holds a bad value.
    #[error("{path}: {array}: {message}")]
    Array {
        /// The log file.
        path: String,
        /// The array, topic or field.
        array: String,
        /// What is wrong.
        message: String,
    },
    /// A reading option that means nothing whatever the file (a cut-off
    /// that is not a positive frequency).
    #[error("reading option {option} = {value}: {message}")]
    Option {
        /// The option (`cutoff_hz`).
        option: &'static str,
        /// Its value, written short.
        value: String,
        /// What it must be.
        message: String,
    },
    /// The record could not be serialised.
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: String,
        /// The serialiser's error.
        #[source]
        source: serde_json::Error,
    },
}
