//! The blocks' results taken in the file's order: samples counted, time
//! checked across blocks, the first failure kept, results folded; and what
//! that comes to, in the order the whole-file reader finds its errors.

use super::super::csv::MAX_ROWS;
use super::super::error::DataError;
use super::parse::Done;
use super::rows::{Fail, not_after, row_error, too_many_rows};
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

/// The blocks taken so far.
pub(super) struct Tally<'a, F> {
    pub path: &'a str,
    /// The caller's fold of each block's result (`false`: no more).
    pub fold: F,
    /// Set when no more results are folded.
    pub stop: &'a AtomicBool,
    last: Option<f64>,
    rows: usize,
    read_s: f64,
    late: Option<DataError>,
    failed: Option<Fail>,
}

impl<'a, F> Tally<'a, F> {
    pub fn new(path: &'a str, fold: F, stop: &'a AtomicBool) -> Self {
        Self {
            path,
            fold,
            stop,
            last: None,
            rows: 0,
            read_s: 0.0,
            late: None,
            failed: None,
        }
    }

    /// Takes the next block's result; `false` to stop reading (a failure).
    /// After a time error, or once the fold says no more, the rest is
    /// still read: a malformed row further on is the error to report.
    pub fn take<R>(&mut self, done: Done<R>) -> bool
    where
        F: FnMut(R) -> bool,
    {
        let p = match done {
            Ok(p) => p,
            Err(f) => {
                self.failed = Some(f.within_max_rows(self.path));
                return false;
            }
        };
        if let (Some(prev), Some((first, _))) = (self.last, p.span)
            && first <= prev
            && self.late.is_none()
        {
            self.late = Some(not_after(self.path, self.rows + 1, first, prev));
        }
        self.late = self.late.take().or(p.late);
        self.last = p.span.map(|s| s.1).or(self.last);
        (self.rows, self.read_s) = (self.rows + p.count, self.read_s + p.parse_s);
        if self.rows > MAX_ROWS {
            self.failed = Some(too_many_rows(self.path).into());
            return false;
        }
        let more = match p.value {
            Some(v) if self.late.is_none() && !self.stop.load(Relaxed) => (self.fold)(v),
            _ => false,
        };
        if !more {
            self.stop.store(true, Relaxed);
        }
        true
    }

    /// The rows read and the parsing time (s), given how the reading
    /// ended; `None` when the file is left to the whole-file reader.
    pub fn finish(self, read: Result<(), Fail>) -> Result<Option<(usize, f64)>, DataError> {
        let read = read.map_err(|f| f.within_max_rows(self.path));
        match self.failed.map_or(read, Err) {
            Err(Fail::Error(e)) => return Err(e),
            Err(Fail::Whole(_)) => return Ok(None),
            Ok(()) => {}
        }
        if self.rows == 0 {
            return Err(row_error(self.path, 1, "no data rows".into()));
        }
        match self.late {
            Some(e) => Err(e),
            None => Ok(Some((self.rows, self.read_s))),
        }
    }
}
