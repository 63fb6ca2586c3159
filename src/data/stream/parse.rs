//! A block of a prepared CSV log parsed into samples: a line of plain
//! numbers by a fast parser, any other line by the CSV automaton the
//! whole-file reader runs, with its settings ([`Splitter`]), so that both
//! read the same values and name the same rows.

use super::super::csv::Columns;
use super::super::error::DataError;
use super::super::raw::RawLog;
use super::blocks::Text;
use super::fields::Splitter;
use super::rows::{Block, Fail, not_after};
use crate::dynamics::Samples;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

/// What one block's task returns.
pub(super) struct Parsed<R> {
    /// The caller's result (`None` once the caller takes no more).
    pub value: Option<R>,
    /// The block's first and last time stamps.
    pub span: Option<(f64, f64)>,
    /// Its number of samples.
    pub count: usize,
    /// The time its parsing took (s).
    pub parse_s: f64,
    /// The first row in it whose time is not after the row before's: an
    /// error only if no row of the file is malformed (the whole-file
    /// reader checks time after reading every row).
    pub late: Option<DataError>,
}

/// A block's [`Parsed`], or why it has none.
pub(super) type Done<R> = Result<Parsed<R>, Fail>;

/// What parsing a block needs.
pub(super) struct Parse<'a> {
    pub cols: &'a Columns,
    pub header: &'a [String],
    pub path: &'a str,
    pub joints: usize,
    /// Set when the caller takes no more results: the blocks are still
    /// parsed (for their errors), not handed to the caller.
    pub stop: &'a AtomicBool,
}

impl Parse<'_> {
    /// Parses the records of `text` and hands the samples to `each`.
    pub fn block<R>(&self, text: &Text, each: &impl Fn(&Block) -> R) -> Done<R> {
        // each thread's samples buffer, reused from block to block; taken
        // out while in use (`each` may run another block on this thread)
        thread_local! {
            static RAW: std::cell::RefCell<RawLog> = std::cell::RefCell::default();
        }
        let t0 = std::time::Instant::now();
        let mut raw = RAW.take();
        self.empty(&mut raw);
        let done = self.fill(text, &mut raw).map(|late| {
            let span = raw.t.first().zip(raw.t.last()).map(|(a, b)| (*a, *b));
            let parse_s = t0.elapsed().as_secs_f64();
            let block = Block {
                first_row: text.first_row,
                raw: &raw,
            };
            let go = late.is_none() && !self.stop.load(Relaxed);
            Parsed {
                value: go.then(|| each(&block)),
                span,
                count: raw.t.len(),
                parse_s,
                late,
            }
        });
        RAW.set(raw);
        done
    }

    /// The records of `text` into `raw`; returns the first row whose time
    /// is not after the one before, if any.
    fn fill(&self, text: &Text, raw: &mut RawLog) -> Result<Option<DataError>, Fail> {
        let whole = Fail::Whole(text.first_row);
        let lines = std::str::from_utf8(text.bytes).map_err(|_| whole)?;
        let mut values: Vec<f64> = Vec::with_capacity(self.header.len());
        let mut split = None;
        let (mut row, mut late) = (text.first_row, None); // the next record's row
        // (a `char` pattern: the line breaks are found by a fast byte search)
        for line in lines.split_inclusive('\n').map(str::as_bytes) {
            let body = line.strip_suffix(b"\n").unwrap_or(line);
            let body = body.strip_suffix(b"\r").unwrap_or(body);
            if body.is_empty() {
                continue; // the whole-file reader skips it, and does not count it
            }
            if numbers(body, self.header.len(), &mut values) && self.cols.push_values(raw, &values)
            {
                self.check_time(raw, row, &mut late);
                row += 1;
                continue;
            }
            let split = split.get_or_insert_with(Splitter::new);
            let read = split.records(line, |record| {
                let fields = (record.len(), |c| record.field(c));
                (self.cols).push_fields(raw, fields, self.header, self.path, row)?;
                self.check_time(raw, row, &mut late);
                row += 1;
                Ok::<_, DataError>(())
            })?;
            if !read {
                return Err(Fail::Whole(row)); // a quoted field goes on past the line
            }
        }
        if row - text.first_row != text.records {
            return Err(Fail::Whole(text.first_row)); // counted otherwise
        }
        Ok(late)
    }

    /// Keeps in `late`, if it is the first, the last sample's time not
    /// after the one before (in this block).
    fn check_time(&self, raw: &RawLog, row: usize, late: &mut Option<DataError>) {
        let n = raw.t.len();
        if late.is_none() && n > 1 && raw.t[n - 1] <= raw.t[n - 2] {
            *late = Some(not_after(self.path, row, raw.t[n - 1], raw.t[n - 2]));
        }
    }

    /// `raw` emptied for this file's samples (its room kept).
    fn empty(&self, raw: &mut RawLog) {
        if raw.q.width() != self.joints || raw.path != self.path {
            *raw = RawLog {
                path: self.path.into(),
                q: Samples::new(self.joints),
                ..RawLog::default()
            };
        }
        raw.t.clear();
        raw.q.clear();
        // this file's series, empty (a block of blank lines still has them)
        let series = [&mut raw.qd, &mut raw.qdd, &mut raw.tau];
        for (s, has) in series.into_iter().zip(self.cols.series()) {
            match (s.as_mut(), has) {
                (Some(s), true) => s.clear(),
                (None, true) => *s = Some(Samples::new(self.joints)),
                (_, false) => *s = None,
            }
        }
    }
}

/// The numbers of a line of exactly `count` plain numbers separated by
/// commas (no spaces, no quotes) into `values`; `false` when the line is
/// anything else (it stops reading at the `count + 1`-th field). Each is
/// the closest `f64`, as `str::parse` gives it.
pub(super) fn numbers(mut line: &[u8], count: usize, values: &mut Vec<f64>) -> bool {
    values.clear();
    loop {
        let Ok((v, used)) = fast_float2::parse_partial::<f64, _>(line) else {
            return false;
        };
        values.push(v);
        match line.get(used) {
            None => return values.len() == count,
            Some(b',') if values.len() < count => line = &line[used + 1..],
            Some(_) => return false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::numbers;

    /// A line of plain numbers is read as `str::parse` reads each field;
    /// a field `str::parse` refuses is never read as a number, and a line
    /// with spaces or quotes goes to the CSV reader.
    #[test]
    fn plain_numbers_parse_as_str_parse_does() {
        let mut fields: Vec<String> = [
            "0",
            "-0",
            "+1",
            ".5",
            "5.",
            "1e5",
            "1E-5",
            "0.1e+3",
            "-2.5e-310",
            "4.9e-324",
            "1.7976931348623157e308",
            "1e400",
            "123456789012345678901234567890",
            "inf",
            "-inf",
            "NaN",
            "1e",
            "1.2.3",
            "--1",
            "0x10",
            "1_0",
            "",
            " 1",
            "1 ",
            "\"1\"",
            "e5",
            "+",
        ]
        .map(String::from)
        .into();
        for k in 0..2000 {
            let x = f64::from_bits(
                0x3ff0_0000_0000_0000 ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 2,
            );
            fields.extend([format!("{x}"), format!("{x:e}"), format!("{:.3}", -x)]);
        }
        let mut values = vec![];
        for f in &fields {
            let std = f.parse::<f64>();
            if numbers(f.as_bytes(), 1, &mut values) {
                let (v, s) = (values[0], std.as_ref().map_err(|_| f).unwrap());
                assert!(
                    v.to_bits() == s.to_bits() || (v.is_nan() && s.is_nan()),
                    "{f}"
                );
            }
            // every field std parses, the plain path parses (but padded or quoted ones)
            if std.is_ok() && !f.starts_with(' ') && !f.ends_with(' ') {
                assert!(numbers(f.as_bytes(), 1, &mut values), "{f}");
            }
        }
        // a line: every field, or none; exactly `count` of them
        assert!(numbers(b"1,2.5,-3e2", 3, &mut values) && values == [1.0, 2.5, -300.0]);
        assert!(!numbers(b"1, 2", 2, &mut values) && !numbers(b"1,,2", 3, &mut values));
        assert!(!numbers(b"1,2,", 3, &mut values));
        assert!(!numbers(b"1,2,3", 2, &mut values) && values.len() <= 2);
        assert!(!numbers(b"1,2", 3, &mut values));
    }
}
