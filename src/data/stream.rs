//! A prepared CSV log (one with q̈, as `simulate` writes: taken as it is,
//! [`super::prepare`]) streamed in blocks of rows: the main thread reads
//! the next block while the thread pool parses and uses the ones before,
//! at most a few blocks at a time, so memory does not grow with the file.
//! Each row is checked as [`read_logs`](super::read_logs) checks it (the
//! same code), and time must increase within and across blocks.
//!
//! A raw log (no q̈) needs its whole segments for the zero-phase filter
//! and the derivatives: it is not streamed ([`stream_prepared_csv`] says
//! so by returning `None`), and is read whole.

use super::csv::{Columns, MAX_LINE_BYTES, MAX_ROWS, columns_of};
use super::error::DataError;
use super::prepare::FileReport;
use super::raw::RawLog;
use super::read::ReadOptions;
use crate::dynamics::Samples;
use std::io::Read;
use std::path::Path;
use std::sync::{Condvar, Mutex};

/// The most bytes of one block (whole lines; a longer line makes its
/// block longer, up to [`MAX_LINE_BYTES`]); a small file is cut into
/// about four blocks per thread, of at least [`MIN_BLOCK_BYTES`].
pub const BLOCK_BYTES: usize = 1 << 20;
/// The fewest bytes of a block (but the last).
pub const MIN_BLOCK_BYTES: usize = 1 << 16;

/// A block of a prepared log handed to the caller: its samples (t, q, q̇,
/// q̈ and τ when the file has them, SI units, the robot's joint order) and
/// the 1-based data row of its first sample.
pub struct Block<'a> {
    /// The first sample's data row (1-based, as errors count rows).
    pub first_row: usize,
    /// The samples.
    pub raw: &'a RawLog,
}

/// What one block's task returns: the caller's result, the block's first
/// and last time stamps, its number of samples and the time its parsing took (s).
type Done<R> = Result<(R, Option<(f64, f64)>, usize, f64), DataError>;

/// A streamed file: what reading it did, and the time spent parsing it
/// (s, summed over the blocks, which were parsed in parallel).
pub struct Streamed {
    /// What reading the file did.
    pub report: FileReport,
    /// Parsing time summed over the blocks (s).
    pub read_s: f64,
}

/// Streams `path` (a CSV with q̈ for every joint) through `each`, block by
/// block on the thread pool, and hands each block's result to `fold` in the
/// file's order on the caller's thread as soon as the blocks before it are
/// folded (`fold` returns `false` to stop reading); at most a few blocks
/// are read and not yet folded, so memory does not grow with the file.
/// Returns the file's report ([`Streamed`]), or `None` when the file is not
/// a prepared CSV (no q̈ columns: read it whole). Errors name the row and
/// column; the first in the file's order is returned.
pub fn stream_prepared_csv<R: Send>(
    path: &Path,
    joints: &[&str],
    opts: &ReadOptions,
    each: impl Fn(&Block) -> R + Sync,
    fold: impl FnMut(R) -> bool,
) -> Result<Option<Streamed>, DataError> {
    let len = std::fs::metadata(path).map_or(0, |m| m.len()) as usize;
    let block = (len / (4 * rayon::current_num_threads())).clamp(MIN_BLOCK_BYTES, BLOCK_BYTES);
    stream_in_blocks(path, joints, opts, (each, fold), block)
}

/// [`stream_prepared_csv`] in blocks of `block` bytes.
fn stream_in_blocks<R: Send>(
    path: &Path,
    joints: &[&str],
    opts: &ReadOptions,
    (each, mut fold): (impl Fn(&Block) -> R + Sync, impl FnMut(R) -> bool),
    block: usize,
) -> Result<Option<Streamed>, DataError> {
    let p = path.display().to_string();
    let io = |source| DataError::Io {
        path: p.clone(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(io)?;
    let (header, mut rest) = read_header(&mut file, &p)?;
    let Some(cols) = prepared_columns(&header, &p, joints, opts)? else {
        return Ok(None);
    };
    let at = Parse {
        cols: &cols,
        header: &header,
        path: &p,
        joints: joints.len(),
    };
    let (mut last, mut rows, mut read_s) = (None::<f64>, 0usize, 0.0);
    let mut failed = None;
    // each block's samples checked against the block before, then folded
    let mut take = |done: Done<R>| {
        let checked = done.and_then(|(value, span, count, parse)| {
            if let (Some(prev), Some((first, _))) = (last, span)
                && first <= prev
            {
                return Err(not_after(&p, rows + 1, first, prev));
            }
            (last, rows, read_s) = (span.map(|s| s.1).or(last), rows + count, read_s + parse);
            Ok(value)
        });
        match checked {
            Ok(value) => fold(value),
            Err(e) => {
                failed = Some(e);
                false
            }
        }
    };
    let task = |text: &[u8], first_row| at.block(text, first_row, &each);
    let read = blocks((&mut file, &mut rest, block), &p, task, &mut take);
    // a block's own error comes before a read error further on
    if let Some(e) = failed {
        return Err(e);
    }
    read?;
    if rows == 0 {
        return Err(DataError::Row {
            path: p,
            row: 1,
            message: "no data rows".into(),
        });
    }
    let report = FileReport {
        path: p,
        rows,
        taken_as_prepared: true,
        segments: 1,
        samples: rows,
        velocity: opts.velocity,
        ..FileReport::default()
    };
    Ok(Some(Streamed { report, read_s }))
}

/// The columns of a prepared log (with q̈, and then q̇), or `None` when
/// the log is not one (it is read whole: that reader names any problem).
fn prepared_columns(
    header: &[String],
    path: &str,
    joints: &[&str],
    opts: &ReadOptions,
) -> Result<Option<Columns>, DataError> {
    let mapping = (opts.mapping.as_ref(), opts.mapping_is_default);
    if mapping.0.is_some_and(|m| m.q.is_none()) {
        return Ok(None); // the whole-file reader names the problem
    }
    let cols = columns_of(header, path, mapping, joints, opts.require_tau)?;
    if cols.qdd.is_none() {
        return Ok(None);
    }
    if !cols.has_qd() {
        return Err(DataError::Array {
            path: path.into(),
            array: "qd".into(),
            message: "the file has q̈ (taken as prepared) but no q̇".into(),
        });
    }
    Ok(Some(cols))
}

/// The header line (parsed as CSV, fields trimmed) and what was read past it.
fn read_header(file: &mut std::fs::File, path: &str) -> Result<(Vec<String>, Vec<u8>), DataError> {
    let mut buf = vec![];
    let mut chunk = vec![0u8; 1 << 16];
    let end = loop {
        if let Some(i) = buf.iter().position(|&b| b == b'\n') {
            break i;
        }
        if buf.len() > MAX_LINE_BYTES {
            return Err(row_error(
                path,
                0,
                format!("a line longer than {MAX_LINE_BYTES} bytes"),
            ));
        }
        let k = file.read(&mut chunk).map_err(|source| DataError::Io {
            path: path.into(),
            source,
        })?;
        if k == 0 {
            break buf.len();
        }
        buf.extend_from_slice(&chunk[..k]);
    };
    let mut rdr = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .has_headers(false)
        .from_reader(&buf[..end]);
    let mut rec = ::csv::StringRecord::new();
    let read = rdr.read_record(&mut rec);
    let header = match read {
        Ok(true) => rec.iter().map(str::to_string).collect(),
        Ok(false) => vec![],
        Err(e) => return Err(row_error(path, 0, e.to_string())),
    };
    let rest = buf.get(end + 1..).unwrap_or_default().to_vec();
    Ok((header, rest))
}

/// Reads `file` (after `rest`, the bytes already read) in blocks of whole
/// lines of about `size` bytes, runs `task(block, first_row)` on each on the
/// thread pool and hands the results to `take` in order, on this thread, as
/// they come (`take` returns `false` to stop). At most `2 × threads + 1`
/// blocks are read and not yet taken. An error reading the file ends the
/// reading; the blocks read before it are still taken.
fn blocks<R: Send>(
    (file, rest, size): (&mut std::fs::File, &mut Vec<u8>, usize),
    path: &str,
    task: impl Fn(&[u8], usize) -> R + Sync,
    take: &mut impl FnMut(R) -> bool,
) -> Result<(), DataError> {
    let limit = 2 * rayon::current_num_threads() + 1;
    let queue = Queue::default();
    // the blocks' buffers, reused: fresh pages cost more than the parsing
    let pool: Mutex<Vec<Vec<u8>>> = Mutex::new(vec![]);
    let mut read_error = Ok(());
    rayon::in_place_scope(|s| {
        let (mut issued, mut taken, mut first_row) = (0usize, 0usize, 1usize);
        // room for one more block: the oldest taken until fewer than `limit` are out
        let mut stopped = false;
        loop {
            if !queue.take_until(&mut taken, (issued + 1).saturating_sub(limit), take) {
                stopped = true;
                break;
            }
            let spare = (pool.lock().ok()).and_then(|mut p| p.pop());
            let block = match next_block((file, rest, size), spare.unwrap_or_default(), path) {
                Ok(Some(b)) => b,
                Ok(None) => break,
                Err(e) => {
                    read_error = Err(e);
                    break;
                }
            };
            let lines = block.iter().filter(|&&b| b == b'\n').count() + 1;
            if first_row + lines > MAX_ROWS + 1 {
                let message = format!("more than {MAX_ROWS} data rows; split the log");
                read_error = Err(row_error(path, MAX_ROWS + 1, message));
                break;
            }
            let (task, queue, pool, index) = (&task, &queue, &pool, issued);
            s.spawn(move |_| {
                let sent = Sent { queue, index };
                let r = task(&block, first_row);
                if let Ok(mut p) = pool.lock() {
                    p.push(block);
                }
                sent.send(r);
            });
            issued += 1;
            first_row += lines;
        }
        // the rest, in order (unless `take` stopped: then they are dropped)
        if !stopped {
            queue.take_until(&mut taken, issued, take);
        }
    });
    read_error
}

/// Finished blocks' results by index, for the reading thread to take in
/// order; `None` for a task that panicked (the scope then panics too).
struct Queue<R> {
    done: Mutex<std::collections::BTreeMap<usize, Option<R>>>,
    ready: Condvar,
}

impl<R> Default for Queue<R> {
    fn default() -> Self {
        Self {
            done: Mutex::default(),
            ready: Condvar::new(),
        }
    }
}

impl<R> Queue<R> {
    fn put(&self, index: usize, r: Option<R>) {
        let mut d = (self.done.lock()).unwrap_or_else(std::sync::PoisonError::into_inner);
        d.insert(index, r);
        self.ready.notify_one();
    }

    /// Hands results to `take` in order from `*taken`: waiting for each
    /// until `*taken` reaches `until`, then those already there. `false`
    /// when `take` stopped or a task panicked.
    fn take_until(
        &self,
        taken: &mut usize,
        until: usize,
        take: &mut impl FnMut(R) -> bool,
    ) -> bool {
        loop {
            let mut d = (self.done.lock()).unwrap_or_else(std::sync::PoisonError::into_inner);
            let next = loop {
                match d.remove(taken) {
                    Some(r) => break r,
                    None if *taken >= until => return true,
                    None => {
                        d = (self.ready.wait(d)).unwrap_or_else(std::sync::PoisonError::into_inner)
                    }
                }
            };
            drop(d);
            *taken += 1;
            if !next.is_some_and(&mut *take) {
                return false;
            }
        }
    }
}

/// A block's place in the [`Queue`]: filled by its result, or by `None` if
/// its task unwinds.
struct Sent<'q, R> {
    queue: &'q Queue<R>,
    index: usize,
}

impl<R> Sent<'_, R> {
    fn send(self, r: R) {
        self.queue.put(self.index, Some(r));
        std::mem::forget(self);
    }
}

impl<R> Drop for Sent<'_, R> {
    fn drop(&mut self) {
        self.queue.put(self.index, None);
    }
}

/// The next block of whole lines (the last may lack its line break), or
/// `None` at the end of the file; read into `buf` (emptied first).
fn next_block(
    (file, rest, size): (&mut std::fs::File, &mut Vec<u8>, usize),
    mut buf: Vec<u8>,
    path: &str,
) -> Result<Option<Vec<u8>>, DataError> {
    buf.clear();
    buf.append(rest);
    loop {
        let want = size.saturating_sub(buf.len()).max(1 << 12) as u64;
        // read_to_end fills the spare room without zeroing it first
        let k = (&mut *file)
            .take(want)
            .read_to_end(&mut buf)
            .map_err(|source| DataError::Io {
                path: path.into(),
                source,
            })?;
        let eof = k == 0;
        if eof {
            return Ok((!buf.is_empty()).then_some(buf));
        }
        if buf.len() >= size {
            match buf.iter().rposition(|&b| b == b'\n') {
                Some(i) => {
                    rest.extend_from_slice(&buf[i + 1..]);
                    buf.truncate(i); // without the line break
                    return Ok(Some(buf));
                }
                None if buf.len() > MAX_LINE_BYTES => {
                    let message = format!("a line longer than {MAX_LINE_BYTES} bytes");
                    return Err(row_error(path, 0, message));
                }
                None => {} // one long line: read on
            }
        }
    }
}

/// What parsing a block needs.
struct Parse<'a> {
    cols: &'a Columns,
    header: &'a [String],
    path: &'a str,
    joints: usize,
}

impl Parse<'_> {
    /// Parses the lines of `block` (data rows from `first_row`), checks
    /// that time increases and hands the samples to `each`.
    fn block<R>(&self, block: &[u8], first_row: usize, each: &impl Fn(&Block) -> R) -> Done<R> {
        // each thread's samples buffer, reused from block to block
        thread_local! {
            static RAW: std::cell::RefCell<RawLog> = std::cell::RefCell::default();
        }
        RAW.with_borrow_mut(|raw| {
            let t0 = std::time::Instant::now();
            self.empty(raw);
            let text = std::str::from_utf8(block).map_err(|e| {
                let before = &block[..e.valid_up_to()];
                let row = first_row + before.iter().filter(|&&b| b == b'\n').count();
                row_error(self.path, row, "is not UTF-8 text".into())
            })?;
            let mut fields: Vec<&str> = Vec::with_capacity(self.header.len());
            let mut values: Vec<f64> = Vec::with_capacity(self.header.len());
            for (k, line) in text.split('\n').enumerate() {
                let row = first_row + k;
                let line = line.strip_suffix('\r').unwrap_or(line);
                if line.trim().is_empty() {
                    continue; // a blank line, as the whole-file reader skips it
                }
                let plain =
                    numbers(line.as_bytes(), &mut values) && values.len() == self.header.len();
                if !(plain && self.cols.push_values(raw, &values)) {
                    // anything else (spaces, quotes, a bad value) as the whole-file reader reads it
                    fields.clear();
                    fields.extend(line.split(',').map(unquoted));
                    let f = &fields;
                    (self.cols).push_fields(
                        raw,
                        (f.len(), |c| f[c]),
                        self.header,
                        self.path,
                        row,
                    )?;
                }
                let n = raw.t.len();
                if n > 1 && raw.t[n - 1] <= raw.t[n - 2] {
                    return Err(not_after(self.path, row, raw.t[n - 1], raw.t[n - 2]));
                }
            }
            let span = raw.t.first().zip(raw.t.last()).map(|(a, b)| (*a, *b));
            let (count, parse) = (raw.t.len(), t0.elapsed().as_secs_f64());
            Ok((each(&Block { first_row, raw }), span, count, parse))
        })
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

/// The numbers of a line of plain numbers separated by commas (no spaces,
/// no quotes) into `values`; `false` when the line is anything else.
/// Each is the closest `f64`, as `str::parse` gives it.
fn numbers(mut line: &[u8], values: &mut Vec<f64>) -> bool {
    values.clear();
    loop {
        let Ok((v, used)) = fast_float2::parse_partial::<f64, _>(line) else {
            return false;
        };
        values.push(v);
        match line.get(used) {
            None => return true,
            Some(b',') => line = &line[used + 1..],
            Some(_) => return false,
        }
    }
}

/// A field trimmed and without one pair of enclosing double quotes.
fn unquoted(f: &str) -> &str {
    let f = f.trim();
    f.strip_prefix('"')
        .and_then(|x| x.strip_suffix('"'))
        .map_or(f, str::trim)
}

fn row_error(path: &str, row: usize, message: String) -> DataError {
    DataError::Row {
        path: path.into(),
        row,
        message,
    }
}

/// Time at `row` not after the previous row's, as the whole-file reader says it.
fn not_after(path: &str, row: usize, t: f64, prev: f64) -> DataError {
    DataError::Value {
        path: path.into(),
        row,
        column: "t".into(),
        message: format!("time {t} is not after the previous row's {prev}"),
    }
}

#[cfg(test)]
mod tests {
    use super::{Block, stream_in_blocks};
    use crate::data::{DataError, Dataset, ReadOptions, Samples};

    const J: [&str; 2] = ["a", "b"];

    /// A prepared log of `k` samples.
    fn log(k: usize) -> Dataset {
        let row = |s: usize, c: f64| -> Vec<f64> { vec![c * s as f64 + 0.25, -c * s as f64] };
        let rows = |c: f64| Samples::from_rows(&(0..k).map(|s| row(s, c)).collect::<Vec<_>>());
        Dataset {
            joints: J.iter().map(|j| j.to_string()).collect(),
            t: (0..k).map(|s| 1e-3 * s as f64).collect(),
            q: rows(0.01),
            qd: rows(0.1),
            qdd: rows(1.0),
            tau: rows(3.0),
            segments: vec![],
        }
    }

    /// Every block's samples, in order, with its first row.
    fn streamed(text: &str, block: usize) -> Result<Option<Vec<(usize, Dataset)>>, DataError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("log.csv");
        std::fs::write(&path, text).unwrap();
        let each = |b: &Block| {
            let r = b.raw;
            let d = Dataset {
                joints: J.iter().map(|j| j.to_string()).collect(),
                t: r.t.clone(),
                q: r.q.clone(),
                qd: r.qd.clone().unwrap(),
                qdd: r.qdd.clone().unwrap(),
                tau: r.tau.clone().unwrap(),
                segments: vec![],
            };
            (b.first_row, d)
        };
        let mut blocks = vec![];
        let fold = |b| {
            blocks.push(b);
            true
        };
        let out = stream_in_blocks(&path, &J, &ReadOptions::default(), (each, fold), block)?;
        Ok(out.map(|s| {
            let samples = blocks.iter().map(|b: &(usize, Dataset)| b.1.len());
            assert_eq!(s.report.samples, samples.sum::<usize>());
            blocks
        }))
    }

    /// Blocks of a few kilobytes hold every sample once, in order, as
    /// the whole-file reader reads them; a raw log (no q̈) is not streamed.
    #[test]
    fn blocks_together_are_the_whole_file() {
        let d = log(5000);
        let text = d.to_csv();
        let whole = Dataset::parse_csv(&text, "log.csv", &J, ReadOptions::default()).unwrap();
        let blocks = streamed(&text, 4096).unwrap().unwrap();
        assert!(blocks.len() > 50, "{}", blocks.len());
        let mut joined = Dataset::empty(&J);
        let mut next = 1;
        for (first, b) in blocks {
            assert_eq!(first, next);
            next += b.len();
            for s in 0..b.len() {
                joined.t.push(b.t[s]);
                joined.q.push(&b.q[s]);
                joined.qd.push(&b.qd[s]);
                joined.qdd.push(&b.qdd[s]);
                joined.tau.push(&b.tau[s]);
            }
        }
        assert_eq!(
            (joined.t, joined.q, joined.tau),
            (whole.t, whole.q, whole.tau)
        );
        assert_eq!((joined.qd, joined.qdd), (whole.qd, whole.qdd));
        let raw: String = text
            .lines()
            .map(|l| {
                // t, q, q̇ and τ: no q̈
                let f: Vec<&str> = l.split(',').collect();
                [0, 1, 2, 3, 4, 7, 8].map(|c| f[c]).join(",") + "\n"
            })
            .collect();
        assert!(streamed(&raw, 4096).unwrap().is_none());
    }

    /// A line of plain numbers is read as `str::parse` reads each field;
    /// a field `str::parse` refuses is never read as a number, and a line
    /// with spaces or quotes goes to the whole-file reader's code.
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
            if super::numbers(f.as_bytes(), &mut values) {
                let (v, s) = (values[0], std.as_ref().map_err(|_| f).unwrap());
                assert!(
                    v.to_bits() == s.to_bits() || (v.is_nan() && s.is_nan()),
                    "{f}"
                );
            }
            // every field std parses, the plain path parses (but padded or quoted ones)
            if std.is_ok() && !f.starts_with(' ') && !f.ends_with(' ') {
                assert!(super::numbers(f.as_bytes(), &mut values), "{f}");
            }
        }
        // a line: every field, or none
        assert!(super::numbers(b"1,2.5,-3e2", &mut values) && values == [1.0, 2.5, -300.0]);
        assert!(!super::numbers(b"1, 2", &mut values) && !super::numbers(b"1,,2", &mut values));
        assert!(!super::numbers(b"1,2,", &mut values));
    }

    /// Spaces and quotes around values (the whole-file reader's code) give
    /// the values the whole-file reader gives.
    #[test]
    fn padded_and_quoted_values_are_read_as_whole() {
        let text = log(300).to_csv();
        let padded: String = (text.lines().enumerate())
            .map(|(k, l)| match k % 3 {
                1 => l.replace(',', " , ") + "\r\n",
                2 if k > 0 => {
                    l.split(',')
                        .map(|f| format!("\"{f}\""))
                        .collect::<Vec<_>>()
                        .join(",")
                        + "\n"
                }
                _ => l.to_string() + "\n",
            })
            .collect();
        let whole = Dataset::parse_csv(&padded, "log.csv", &J, ReadOptions::default()).unwrap();
        let blocks = streamed(&padded, 4096).unwrap().unwrap();
        let t: Vec<f64> = blocks.iter().flat_map(|b| b.1.t.clone()).collect();
        let tau: Vec<f64> = blocks
            .iter()
            .flat_map(|b| b.1.tau.as_flat().to_vec())
            .collect();
        assert_eq!((t, tau), (whole.t.clone(), whole.tau.as_flat().to_vec()));
        assert_eq!(whole.len(), 300);
    }

    /// Results are folded as they come: never more than 2 × threads + 1
    /// blocks' results exist at once, whatever the file's length; a fold
    /// that says stop ends the reading.
    #[test]
    fn results_are_folded_as_they_come() {
        use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};
        struct Alive<'a>(&'a AtomicUsize);
        impl Drop for Alive<'_> {
            fn drop(&mut self) {
                self.0.fetch_sub(1, SeqCst);
            }
        }
        let (alive, most, taken) = (
            AtomicUsize::new(0),
            AtomicUsize::new(0),
            AtomicUsize::new(0),
        );
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("log.csv");
        std::fs::write(&path, log(20_000).to_csv()).unwrap();
        let each = |_: &Block| {
            most.fetch_max(alive.fetch_add(1, SeqCst) + 1, SeqCst);
            Alive(&alive)
        };
        let run = |stop_after: usize| {
            taken.store(0, SeqCst);
            let fold = |a: Alive| {
                drop(a);
                taken.fetch_add(1, SeqCst) + 1 < stop_after
            };
            stream_in_blocks(&path, &J, &ReadOptions::default(), (each, fold), 4096).unwrap()
        };
        let report = run(usize::MAX).unwrap().report;
        assert_eq!(report.samples, 20_000);
        let blocks = taken.load(SeqCst);
        let limit = 2 * rayon::current_num_threads() + 1;
        assert!(
            blocks > 100 && most.load(SeqCst) <= limit,
            "{blocks} {most:?}"
        );
        run(3);
        assert_eq!(taken.load(SeqCst), 3);
        assert_eq!(alive.load(SeqCst), 0); // every result dropped
    }

    /// A bad value deep in the file and time that goes back across a
    /// block boundary are errors naming their row and column.
    #[test]
    fn errors_name_the_row_and_column_in_any_block() {
        let text = log(5000).to_csv();
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        lines[4001] = lines[4001].replacen(',', ",x", 1);
        let e = streamed(&(lines.join("\n") + "\n"), 4096)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("row 4001") && e.contains("q_a") && e.contains("'x"),
            "{e}"
        );
        // time back at a block boundary: the row after the first block's last
        let blocks = streamed(&text, 4096).unwrap().unwrap();
        let at = blocks[5].0; // the sixth block's first data row
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        let rest = lines[at].split_once(',').unwrap().1.to_string();
        lines[at] = format!("0,{rest}");
        let e = streamed(&(lines.join("\n") + "\n"), 4096)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("row {at}")) && e.contains("not after"),
            "{e}"
        );
    }
}
