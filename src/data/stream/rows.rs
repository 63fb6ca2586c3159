//! What the blocks of a streamed log are to the caller, and the errors
//! that name their rows.

use super::super::error::DataError;
use super::super::raw::RawLog;

/// A block of a prepared log handed to the caller: its samples (t, q, q̇,
/// q̈ and τ when the file has them, SI units, the robot's joint order) and
/// the data row of its first sample.
pub struct Block<'a> {
    /// The first sample's data row, 1-based and counted as errors count
    /// rows (as the whole-file reader does: empty lines are not rows), so
    /// that sample `s` of the block is the file's sample `first_row + s`
    /// (1-based).
    pub first_row: usize,
    /// The samples.
    pub raw: &'a RawLog,
}

/// An error naming a data row (0: the header).
pub(super) fn row_error(path: &str, row: usize, message: String) -> DataError {
    DataError::Row {
        path: path.into(),
        row,
        message,
    }
}

/// Time at `row` not after the previous row's, as the whole-file reader says it.
pub(super) fn not_after(path: &str, row: usize, t: f64, prev: f64) -> DataError {
    DataError::Value {
        path: path.into(),
        row,
        column: "t".into(),
        message: format!("time {t} is not after the previous row's {prev}"),
    }
}
