//! What the blocks of a streamed log are to the caller, and the errors
//! and failures that name their rows.

use super::super::csv::MAX_ROWS;
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

/// Why a block, or the reading, gave no result: an error naming its row
/// and column, or text this reader does not take (a quoted line break,
/// text that is not UTF-8, an over-long line of `\r`-ended records, rows
/// it counts otherwise than the whole-file reader), from the given data
/// row on: the file is then read whole, which reads or names it.
pub(super) enum Fail {
    Error(DataError),
    Whole(usize),
}

impl From<DataError> for Fail {
    fn from(e: DataError) -> Self {
        Self::Error(e)
    }
}

impl Fail {
    /// The failure as the whole-file reader meets it when the file has
    /// more than [`MAX_ROWS`] rows: an error past that row is never
    /// reached, the row count is refused first.
    pub fn within_max_rows(self, path: &str) -> Self {
        let row = match &self {
            Self::Error(DataError::Row { row, .. } | DataError::Value { row, .. }) => *row,
            Self::Whole(row) => *row,
            Self::Error(_) => 0,
        };
        if row > MAX_ROWS {
            return too_many_rows(path).into();
        }
        self
    }
}

/// More than [`MAX_ROWS`] data rows, as the whole-file reader says it.
pub(super) fn too_many_rows(path: &str) -> DataError {
    let message = format!("more than {MAX_ROWS} data rows; split the log");
    row_error(path, MAX_ROWS + 1, message)
}
