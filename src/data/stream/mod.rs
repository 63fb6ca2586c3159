//! A prepared CSV log (one with q̈ and q̇, as `simulate` writes: taken as
//! it is, [`super::prepare`]) streamed in blocks of rows: the calling
//! thread reads the next block while the thread pool parses and uses the
//! ones before, at most a few blocks at a time, so memory does not grow
//! with the file.
//!
//! Rows are read as [`read_logs`](super::read_logs) reads them: a line of
//! plain numbers by a fast parser that gives `str::parse`'s values, any
//! other line by the CSV automaton that reader runs, with its settings,
//! and the same checks of each value; rows are counted as that reader
//! counts them (empty lines are not rows). Its errors come in its order:
//! the first malformed row (or more than [`MAX_ROWS`](super::csv::MAX_ROWS)
//! rows), else no rows, else the first row whose time is not after the
//! row before's, within or across blocks. What it does not take line by
//! line (empty lines before the header, a `\r` line end in the header, a
//! quoted line break, text that is not UTF-8, an over-long line holding
//! `\r`-ended records, a header near the longest line) it leaves to the
//! whole-file reader by returning `None`.
//!
//! A raw log (no q̈) needs its whole segments for the zero-phase filter
//! and the derivatives: it is not streamed either.

mod blocks;
mod fields;
mod parse;
mod rows;
mod tally;

use super::csv::{Columns, MAX_LINE_BYTES, columns_of};
use super::error::DataError;
use super::options::ReadOptions;
use super::prepare::FileReport;
use blocks::{Text, blocks};
use fields::Splitter;
use parse::Parse;
pub use rows::Block;
use rows::row_error;
use std::io::Read;
use std::path::Path;
use tally::Tally;

/// The most bytes of one block (whole lines; a longer line makes its
/// block longer, up to [`MAX_LINE_BYTES`]); a small file is cut into
/// about four blocks per thread, of at least [`MIN_BLOCK_BYTES`].
pub const BLOCK_BYTES: usize = 1 << 20;
/// The fewest bytes of a block (but the last).
pub const MIN_BLOCK_BYTES: usize = 1 << 16;

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
/// folded; at most a few blocks are read and not yet folded, so memory
/// does not grow with the file. When `fold` returns `false` it is handed
/// no more, and `each` is not run on later blocks, but the file is still
/// read to its end for its errors (as the whole-file reader would).
///
/// Returns the file's report ([`Streamed`]), or `None` when the file is to
/// be read whole: not a prepared CSV (no q̈, or q̈ but no q̇), or text
/// this reader leaves to the whole-file reader (see the module). That
/// `None` can come after blocks before the text were folded: the caller
/// discards what it folded. An error is the one the whole-file reader
/// reports: the first malformed row, else the first row whose time is not
/// after the one before. Callable from any thread, the pool's included.
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
    (each, fold): (impl Fn(&Block) -> R + Sync, impl FnMut(R) -> bool),
    block: usize,
) -> Result<Option<Streamed>, DataError> {
    let p = path.display().to_string();
    let mut file = std::fs::File::open(path).map_err(|source| DataError::Io {
        path: p.clone(),
        source,
    })?;
    let Some((header, mut rest)) = read_header(&mut file, &p)? else {
        return Ok(None);
    };
    let Some(cols) = prepared_columns(&header, &p, joints, opts)? else {
        return Ok(None);
    };
    let stop = std::sync::atomic::AtomicBool::new(false);
    let at = Parse {
        cols: &cols,
        header: &header,
        path: &p,
        joints: joints.len(),
        stop: &stop,
    };
    let mut tally = Tally::new(&p, fold, &stop);
    let task = |text: &Text| at.block(text, &each);
    let read = blocks((&mut file, &mut rest, block), &p, task, &mut |d| {
        tally.take(d)
    });
    let Some((rows, read_s)) = tally.finish(read)? else {
        return Ok(None);
    };
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

/// The columns of a prepared log (with q̈ and q̇), or `None` when the log
/// is not one (it is read whole: that reader names any problem, in its order).
fn prepared_columns(
    header: &[String],
    path: &str,
    joints: &[&str],
    opts: &ReadOptions,
) -> Result<Option<Columns>, DataError> {
    let mapping = (opts.mapping.as_ref(), opts.mapping_is_default);
    if mapping.0.is_some_and(|m| m.q.is_none()) {
        return Ok(None);
    }
    let cols = columns_of(header, path, mapping, joints, opts.require_tau)?;
    Ok((cols.qdd.is_some() && cols.has_qd()).then_some(cols))
}

/// The header line (parsed as CSV, fields trimmed) and what was read past
/// it; `None` when the whole-file reader is to read it: empty lines before
/// it, a lone `\r` ending it, a quoted field going on past it, or a length
/// near [`MAX_LINE_BYTES`].
fn read_header(
    file: &mut std::fs::File,
    path: &str,
) -> Result<Option<(Vec<String>, Vec<u8>)>, DataError> {
    let (mut buf, mut searched) = (vec![], 0);
    let (end, eof) = loop {
        let k = (&mut *file).take(1 << 16).read_to_end(&mut buf);
        let k = k.map_err(|source| DataError::Io {
            path: path.into(),
            source,
        })?;
        let at = buf[searched..]
            .iter()
            .position(|&b| b == b'\n' || b == b'\r');
        if let Some(i) = at.map(|i| searched + i) {
            // a `\r` is a line end only before `\n` here; its next byte may be unread
            if buf[i] == b'\n' || buf.get(i + 1) == Some(&b'\n') {
                break (i, false);
            }
            if buf.len() > i + 1 {
                return Ok(None);
            }
            searched = i;
        } else {
            searched = buf.len();
        }
        if k == 0 {
            break (buf.len(), true);
        }
        if buf.len() > MAX_LINE_BYTES {
            return Ok(None);
        }
    };
    let skip: usize = match (eof, buf.get(end)) {
        (true, _) => 0,
        (false, Some(b'\r')) => 2,
        _ => 1,
    };
    let line = &buf[..end];
    let bom = line.strip_prefix(b"\xef\xbb\xbf").unwrap_or(line);
    // with the `\r` of a `\r\n`: the whole-file reader counts it in the line
    let too_long = end + skip.saturating_sub(1) > MAX_LINE_BYTES;
    let read = Splitter::new().records(&buf[..end + skip], |_| Ok::<_, ()>(()));
    if bom.is_empty() || too_long || read != Ok(true) {
        return Ok(None);
    }
    let mut rdr = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .has_headers(false)
        .from_reader(line);
    let mut rec = ::csv::StringRecord::new();
    let header = match rdr.read_record(&mut rec) {
        Ok(true) => rec.iter().map(str::to_string).collect(),
        Ok(false) => vec![],
        Err(e) => return Err(row_error(path, 0, e.to_string())),
    };
    let rest = buf.get(end + skip..).unwrap_or_default().to_vec();
    Ok(Some((header, rest)))
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
            base: None,
            contacts: vec![],
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
                base: None,
                contacts: vec![],
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

    /// Awkward text (empty and blank lines, `\r\n` and lone `\r`, quoted
    /// commas and line breaks, padded quotes, an extra text column) is read
    /// as the whole-file reader reads it: the same samples, or the same
    /// error with the same row, or left to it (`None`).
    #[test]
    fn awkward_text_is_read_as_whole() {
        let text = log(40).to_csv();
        let lines: Vec<&str> = text.lines().collect();
        let with = |k: usize, line: &str| {
            let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
            l[k] = line.into();
            l.join("\n") + "\n"
        };
        let note = |l: &str, v: &str| format!("{l},{v}");
        let noted: Vec<String> = (lines.iter().enumerate())
            .map(|(k, l)| note(l, if k == 0 { "note" } else { "x" }))
            .collect();
        let noted_with = |k: usize, v: &str| {
            let mut l = noted.clone();
            l[k] = note(lines[k], v);
            l.join("\n") + "\n"
        };
        let field = |k: usize, v: &str| {
            let mut f: Vec<&str> = lines[k].split(',').collect();
            f[1] = v;
            f.join(",")
        };
        let blank = |l: &[&str]| format!("{}\n\n \n{}", l[..20].join("\n"), l[20..].join("\n"));
        let mut bad = lines.clone();
        let x = field(25, "x");
        bad[25] = &x;
        let cases: Vec<(String, &str)> = vec![
            (blank(&lines).replace("\n \n", "\n\n"), "read"),
            (blank(&bad).replace("\n \n", "\n\n"), "error"), // a bad value after empty lines
            (blank(&lines), "error"),                        // a line of a space
            (text.replace('\n', "\r\n"), "read"),
            (text.replace('\n', "\r"), "whole"),
            (
                with(10, &(lines[10].to_string() + "\r" + lines[11])),
                "error",
            ), // time repeats
            (with(12, &field(12, " \"1e-3\" ")), "error"),
            (with(12, &field(12, "\"1e-3\"")), "read"),
            (noted_with(7, "\"a,b\""), "read"),
            (noted_with(7, "\"a\nb\""), "whole"),
            (noted_with(7, "a,b"), "error"),
            (noted_with(9, &"n".repeat(super::MAX_LINE_BYTES)), "error"), // a line too long
        ];
        for (k, (text, expect)) in cases.iter().enumerate() {
            assert_eq!(against_whole(text, 256), *expect, "case {k}");
        }
    }

    /// How the stream reads `text` in blocks of `block` bytes, checked
    /// against the whole-file reader: "read" (the same samples), "error"
    /// (the same message past the file's name) or "whole" (left to it).
    fn against_whole(text: &str, block: usize) -> &'static str {
        let whole = Dataset::parse_csv(text, "log.csv", &J, ReadOptions::default());
        match (streamed(text, block), &whole) {
            (Ok(None), _) => "whole",
            (Ok(Some(blocks)), Ok(w)) => {
                let t: Vec<f64> = blocks.iter().flat_map(|b| b.1.t.clone()).collect();
                let tau = blocks.iter().flat_map(|b| b.1.tau.as_flat().to_vec());
                assert_eq!(t, w.t);
                assert_eq!(tau.collect::<Vec<_>>(), w.tau.as_flat());
                "read"
            }
            (Err(e), Err(w)) => {
                // the same message past the file's name (a temporary path here)
                let after =
                    |e: &DataError| e.to_string().split_once("log.csv").unwrap().1.to_string();
                assert_eq!(after(&e), after(w));
                "error"
            }
            (s, w) => panic!("{:?} against {w:?}", s.map(|s| s.is_some())),
        }
    }

    /// `each` may use the thread pool itself (its tasks may then run
    /// other blocks on the same thread).
    #[test]
    fn each_may_use_the_pool() {
        use rayon::prelude::*;
        let text = log(50_000).to_csv();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("log.csv");
        std::fs::write(&path, text).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let each = |b: &Block| -> f64 {
            // waits inside: the thread runs other tasks (blocks) meanwhile
            let wait = std::time::Duration::from_micros(50);
            let part = |k: usize| (k..b.raw.len()).step_by(4).map(|s| b.raw.t[s]).sum::<f64>();
            (0..4)
                .into_par_iter()
                .map(|k| (std::thread::sleep(wait), part(k)).1)
                .sum()
        };
        let mut sum = 0.0;
        let fold = |x| {
            sum += x;
            true
        };
        let read = pool
            .install(|| stream_in_blocks(&path, &J, &ReadOptions::default(), (each, fold), 4096));
        assert_eq!(read.unwrap().unwrap().report.samples, 50_000);
        assert!(
            (sum - 1e-3 * (49_999.0 * 50_000.0 / 2.0)).abs() < 1e-3,
            "{sum}"
        );
    }

    /// The whole-file reader reads every row before it checks time and
    /// q̇: a malformed row anywhere comes before time going back (in a
    /// block or across blocks); text the line-by-line reading would take
    /// otherwise (a byte-order mark on a data line, empty lines before
    /// the header, a quoted line break after a quote inside an unquoted
    /// field, a quoted line break in the header) is read as it reads it.
    #[test]
    fn errors_and_odd_text_come_as_the_whole_reader_has_them() {
        let text = log(400).to_csv();
        let lines: Vec<&str> = text.lines().collect();
        let with = |changes: &[(usize, String)]| {
            let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
            for (k, line) in changes {
                l[*k] = line.clone();
            }
            l.join("\n") + "\n"
        };
        let bad = |k: usize| (k, lines[k].replacen(',', ",x", 1));
        let back = |k: usize| (k, lines[3].to_string());
        let starts: Vec<usize> = (streamed(&text, 4096).unwrap().unwrap())
            .iter()
            .map(|b| b.0)
            .collect();
        let edge = starts[2]; // a block's first row
        let no_qd: String = (text.lines())
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                [0, 1, 2, 5, 6, 7, 8].map(|c| f[c]).join(",") + "\n"
            })
            .collect();
        let notes = |k: usize, v: &str| format!("{},{v}", lines[k]);
        let noted = |odd: &str| {
            let l = (0..lines.len()).map(|k| match k {
                0 => notes(0, "n1,n2,n3"),
                20 => notes(20, odd),
                _ => notes(k, "a,b,c"),
            });
            l.collect::<Vec<_>>().join("\n") + "\n"
        };
        let cases: Vec<(String, &str)> = vec![
            (with(&[back(10), bad(300)]), "error"),
            (with(&[back(edge), bad(edge + 40)]), "error"),
            (with(&[back(edge), back(edge + 5)]), "error"),
            (with(&[bad(edge), back(edge + 1)]), "error"),
            (no_qd.replacen("\n0.001", "\nx", 1), "whole"),
            (with(&[(30, format!("\u{feff}{}", lines[30]))]), "error"),
            (format!("\n\r\n{text}"), "whole"),
            (noted("a\"b,\"c\nd\",e\"f"), "whole"),
            (noted("a\"b,c\"d,e"), "read"),
            (format!("{},\"x\ny\"\n{}", lines[0], noted("z")), "whole"),
        ];
        for (k, (text, expect)) in cases.iter().enumerate() {
            for block in [256, 4096] {
                assert_eq!(
                    against_whole(text, block),
                    *expect,
                    "case {k}, block {block}"
                );
            }
        }
        let e = streamed(&with(&[back(10), bad(300)]), 4096).unwrap_err();
        assert!(e.to_string().contains("row 300"), "{e}");
    }

    /// From a thread of the pool (a one-thread pool: the blocks' tasks wait
    /// in the caller's own queue) the file is streamed, not waited for forever.
    #[test]
    fn streams_from_a_thread_of_the_pool() {
        let text = log(3000).to_csv();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let blocks = pool.install(|| streamed(&text, 4096)).unwrap().unwrap();
        assert_eq!(blocks.iter().map(|b| b.1.len()).sum::<usize>(), 3000);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let inner =
            pool.install(|| rayon::join(|| streamed(&text, 4096), || streamed(&text, 8192)));
        assert_eq!(
            inner.0.unwrap().unwrap().len() > inner.1.unwrap().unwrap().len(),
            true
        );
    }

    /// Results are folded as they come: never more than 2 × threads + 1
    /// blocks' results exist at once, whatever the file's length, nor more
    /// bytes of blocks than as many blocks (a file of long lines has fewer
    /// out); after a fold that says stop, no more are folded and the
    /// blocks after those out are not handed to `each`.
    #[test]
    fn results_are_folded_as_they_come() {
        use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};
        struct Alive<'a>(&'a AtomicUsize);
        impl Drop for Alive<'_> {
            fn drop(&mut self) {
                self.0.fetch_sub(1, SeqCst);
            }
        }
        let (alive, most, taken, ran) = (
            AtomicUsize::new(0),
            AtomicUsize::new(0),
            AtomicUsize::new(0),
            AtomicUsize::new(0),
        );
        let dir = tempfile::tempdir().unwrap();
        let (path, long) = (dir.path().join("log.csv"), dir.path().join("long.csv"));
        let text = log(20_000).to_csv();
        std::fs::write(&path, &text).unwrap();
        // each line with a note of 3 blocks' bytes: one block out at a time
        let note = "n".repeat(3 * 4096);
        let noted = (text.lines().take(300).enumerate())
            .map(|(k, l)| format!("{l},{}\n", if k == 0 { "note" } else { &note }));
        std::fs::write(&long, noted.collect::<String>()).unwrap();
        let each = |_: &Block| {
            ran.fetch_add(1, SeqCst);
            most.fetch_max(alive.fetch_add(1, SeqCst) + 1, SeqCst);
            Alive(&alive)
        };
        let run = |path: &std::path::Path, stop_after: usize| {
            (
                taken.store(0, SeqCst),
                most.store(0, SeqCst),
                ran.store(0, SeqCst),
            );
            let fold = |a: Alive| {
                drop(a);
                taken.fetch_add(1, SeqCst) + 1 < stop_after
            };
            stream_in_blocks(path, &J, &ReadOptions::default(), (each, fold), 4096).unwrap()
        };
        let report = run(&path, usize::MAX).unwrap().report;
        assert_eq!(report.samples, 20_000);
        let blocks = taken.load(SeqCst);
        let limit = 2 * rayon::current_num_threads() + 1;
        assert!(
            blocks > 100 && most.load(SeqCst) <= limit,
            "{blocks} {most:?}"
        );
        assert_eq!(run(&long, usize::MAX).unwrap().report.samples, 299);
        let fit = (limit * 4096 / (note.len() + 100)).max(1);
        assert!(most.load(SeqCst) <= fit, "{most:?} > {fit}");
        assert_eq!(run(&path, 3).unwrap().report.samples, 20_000); // read to its end
        assert_eq!(taken.load(SeqCst), 3);
        assert!(ran.load(SeqCst) <= 3 + limit + 1, "{ran:?}");
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
