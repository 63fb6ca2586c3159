//! A block of a prepared CSV log parsed into samples: a line of plain
//! numbers by a fast parser, any other line by the CSV reader the
//! whole-file reader uses, with its settings, so that both read the same
//! values and name the same rows.

use super::super::csv::Columns;
use super::super::error::DataError;
use super::super::raw::RawLog;
use super::blocks::Text;
use super::rows::{Block, not_after, row_error};
use crate::dynamics::Samples;

/// Why a block gave no result: an error naming its row and column, or a
/// line this reader does not take (a quoted line break, text that is not
/// UTF-8, rows it counts otherwise than the whole-file reader): the file
/// is then read whole, which reads or names it.
pub(super) enum Fail {
    Error(DataError),
    Whole,
}

impl From<DataError> for Fail {
    fn from(e: DataError) -> Self {
        Self::Error(e)
    }
}

/// What one block's task returns: the caller's result, the block's first
/// and last time stamps, its number of samples and the time its parsing took (s).
pub(super) type Done<R> = Result<(R, Option<(f64, f64)>, usize, f64), Fail>;

/// What parsing a block needs.
pub(super) struct Parse<'a> {
    pub cols: &'a Columns,
    pub header: &'a [String],
    pub path: &'a str,
    pub joints: usize,
}

impl Parse<'_> {
    /// Parses the records of `text`, checks that time increases and hands
    /// the samples to `each`.
    pub fn block<R>(&self, text: &Text, each: &impl Fn(&Block) -> R) -> Done<R> {
        // each thread's samples buffer, reused from block to block
        thread_local! {
            static RAW: std::cell::RefCell<RawLog> = std::cell::RefCell::default();
        }
        RAW.with_borrow_mut(|raw| {
            let t0 = std::time::Instant::now();
            self.empty(raw);
            let lines = std::str::from_utf8(text.bytes).map_err(|_| Fail::Whole)?;
            let mut values: Vec<f64> = Vec::with_capacity(self.header.len());
            let mut row = text.first_row; // the next record's
            for line in lines.split('\n') {
                let line = line.strip_suffix('\r').unwrap_or(line);
                if line.is_empty() {
                    continue; // the whole-file reader skips it, and does not count it
                }
                let plain = numbers(line.as_bytes(), self.header.len(), &mut values)
                    && self.cols.push_values(raw, &values);
                if plain {
                    self.check_time(raw, row)?;
                    row += 1;
                } else {
                    row = self.records(line, raw, row)?;
                }
            }
            if row - text.first_row != text.records {
                return Err(Fail::Whole); // counted otherwise: the whole reader decides
            }
            let span = raw.t.first().zip(raw.t.last()).map(|(a, b)| (*a, *b));
            let (count, parse) = (raw.t.len(), t0.elapsed().as_secs_f64());
            let block = Block {
                first_row: text.first_row,
                raw,
            };
            Ok((each(&block), span, count, parse))
        })
    }

    /// The records of a line that is not plain numbers (spaces, quotes, a
    /// `\r` inside, a bad value), read by the CSV reader with the whole-file
    /// reader's settings from `row` on; returns the next record's row.
    fn records(&self, line: &str, raw: &mut RawLog, mut row: usize) -> Result<usize, Fail> {
        if line.bytes().filter(|&b| b == b'"').count() % 2 == 1 {
            return Err(Fail::Whole); // a quoted field goes on past the line
        }
        let mut rdr = ::csv::ReaderBuilder::new()
            .trim(::csv::Trim::All)
            .flexible(true)
            .has_headers(false)
            .from_reader(line.as_bytes());
        let mut rec = ::csv::StringRecord::new();
        loop {
            match rdr.read_record(&mut rec) {
                Ok(false) => return Ok(row),
                Ok(true) => {}
                Err(e) => return Err(row_error(self.path, row, e.to_string()).into()),
            }
            let fields = (rec.len(), |c| &rec[c]);
            (self.cols).push_fields(raw, fields, self.header, self.path, row)?;
            self.check_time(raw, row)?;
            row += 1;
        }
    }

    /// The last sample's time after the one before (in this block).
    fn check_time(&self, raw: &RawLog, row: usize) -> Result<(), DataError> {
        let n = raw.t.len();
        if n > 1 && raw.t[n - 1] <= raw.t[n - 2] {
            return Err(not_after(self.path, row, raw.t[n - 1], raw.t[n - 2]));
        }
        Ok(())
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
