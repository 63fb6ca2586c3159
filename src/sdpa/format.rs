//! The SDPA text format: reading and writing an [`SdpaProblem`].
//!
//! The parser reads the whole header and every entry before anything is
//! sized from the header: no buffer is reserved from a declared m, number of
//! blocks or block size, so a hostile header costs what its file costs.

use super::check::{MAX_VARIABLES, entry_fault, first_duplicate};
use super::error::SdpaError;
use super::options::SdpaOptions;
use super::problem::SdpaProblem;
use std::fmt::Write as _;
use std::path::Path;

/// Lines of SDPA text as tokens, with their 1-based numbers; `,{}()` are
/// blanks.
struct Lines<'a> {
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
}

impl<'a> Lines<'a> {
    /// The text after its leading comment lines (`"` or `*`) and blank lines.
    fn new(text: &'a str) -> Self {
        let mut lines = text.lines().enumerate().peekable();
        while let Some((_, l)) = lines.peek() {
            let s = l.trim_start();
            if s.starts_with('"') || s.starts_with('*') || s.is_empty() {
                lines.next();
            } else {
                break;
            }
        }
        Self { lines }
    }

    /// The next non-empty line's tokens with its 1-based number.
    fn next_line(&mut self) -> Option<(usize, Vec<&'a str>)> {
        let blank = |c: char| c.is_whitespace() || ",{}()".contains(c);
        for (i, l) in self.lines.by_ref() {
            let toks: Vec<&str> = l.split(blank).filter(|t| !t.is_empty()).collect();
            if !toks.is_empty() {
                return Some((i + 1, toks));
            }
        }
        None
    }
}

fn parse_error(line: usize, message: String) -> SdpaError {
    SdpaError::Parse { line, message }
}

/// A non-negative integer.
fn count(tok: &str, line: usize, what: &str) -> Result<usize, SdpaError> {
    tok.parse::<usize>().map_err(|_| {
        parse_error(
            line,
            format!("{what}: '{tok}' is not an integer in 0..={}", usize::MAX),
        )
    })
}

/// A finite number; Fortran-style exponents (1.0D+00) appear in some files.
fn finite(tok: &str, line: usize, what: &str) -> Result<f64, SdpaError> {
    let v: f64 = tok
        .replace(['D', 'd'], "e")
        .parse()
        .map_err(|_| parse_error(line, format!("{what}: cannot read '{tok}' as a number")))?;
    if !v.is_finite() {
        return Err(parse_error(
            line,
            format!("{what}: '{tok}' is non-finite (NaN, infinite or beyond ±1.8e308)"),
        ));
    }
    Ok(v)
}

/// The first token of the next line: `m` or the number of blocks (the rest
/// of the line is a comment).
fn header_count(t: &mut Lines, what: &str) -> Result<(usize, usize), SdpaError> {
    let (line, toks) = t
        .next_line()
        .ok_or_else(|| SdpaError::UnexpectedEof(format!("expected {what}")))?;
    Ok((line, count(toks[0], line, what)?))
}

/// `nb` non-zero block sizes, over as many lines as they take; the rest of
/// the last line is a comment.
fn block_sizes(t: &mut Lines, nb: usize) -> Result<Vec<i64>, SdpaError> {
    let mut blocks = Vec::new();
    while blocks.len() < nb {
        let (line, toks) = t.next_line().ok_or_else(|| {
            SdpaError::UnexpectedEof(format!(
                "the header declares {nb} blocks but the file ends after {} block sizes",
                blocks.len()
            ))
        })?;
        for tok in toks.into_iter().take(nb - blocks.len()) {
            let what = || format!("block size {} of {nb}", blocks.len() + 1);
            let b: i64 = tok
                .parse()
                .map_err(|_| parse_error(line, format!("{}: '{tok}' is not an integer", what())))?;
            if b == 0 {
                return Err(parse_error(line, format!("{}: block size 0", what())));
            }
            blocks.push(b);
        }
    }
    Ok(blocks)
}

/// The `m` entries of c, over as many lines as they take.
fn costs(t: &mut Lines, m: usize) -> Result<Vec<f64>, SdpaError> {
    let mut c = Vec::new();
    while c.len() < m {
        let (line, toks) = t.next_line().ok_or_else(|| {
            SdpaError::UnexpectedEof(format!(
                "the header declares m = {m} but the file ends after {} entries of the cost vector c",
                c.len()
            ))
        })?;
        for tok in toks {
            if c.len() == m {
                return Err(parse_error(
                    line,
                    format!("more than m = {m} entries in the cost vector c"),
                ));
            }
            c.push(finite(
                tok,
                line,
                &format!("cost vector entry c{}", c.len() + 1),
            )?);
        }
    }
    Ok(c)
}

type Entry = (usize, usize, usize, usize, f64);

/// One line `matno blkno i j value`, checked against m and the blocks;
/// returned 0-based with `i ≤ j`.
fn entry(line: usize, toks: &[&str], m: usize, blocks: &[i64]) -> Result<Entry, SdpaError> {
    if toks.len() < 5 {
        return Err(parse_error(
            line,
            format!(
                "expected 'matno blkno i j value', found {} fields",
                toks.len()
            ),
        ));
    }
    let mat = count(toks[0], line, "matrix number")?;
    let blk = count(toks[1], line, "block number")?;
    let i = count(toks[2], line, "row")?;
    let j = count(toks[3], line, "column")?;
    let v = finite(toks[4], line, "value")?;
    if let Some(msg) = entry_fault(m, blocks, mat, blk, i, j) {
        return Err(parse_error(line, msg));
    }
    Ok((mat, blk - 1, i.min(j) - 1, i.max(j) - 1, v))
}

impl SdpaProblem {
    /// Number of variables m.
    pub fn m(&self) -> usize {
        self.c.len()
    }

    /// Reads a file with the default [`SdpaOptions`].
    pub fn read(path: &Path) -> Result<Self, SdpaError> {
        Self::read_with(path, &SdpaOptions::default())
    }

    /// Reads a file, first checking that reading it fits the memory limit
    /// (about [`READ_BYTES_PER_FILE_BYTE`](super::memory::READ_BYTES_PER_FILE_BYTE)
    /// bytes per byte of file).
    pub fn read_with(path: &Path, opts: &SdpaOptions) -> Result<Self, SdpaError> {
        opts.validate()?;
        let io = |e| SdpaError::Io {
            path: path.to_path_buf(),
            source: e,
        };
        let most = (opts.max_memory_bytes() / super::memory::READ_BYTES_PER_FILE_BYTE) as u64;
        let bytes = match crate::io::read_capped(path, most) {
            Ok(b) => b,
            Err(crate::io::Capped::Io(e)) => return Err(io(e)),
            Err(crate::io::Capped::TooLarge(len)) => {
                // the limit's own error, with the numbers
                super::memory::check_read(path, len, opts)?;
                return Err(io(std::io::Error::other("larger than the read limit")));
            }
        };
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count();
            SdpaError::Encoding {
                path: path.to_path_buf(),
                line,
            }
        })?;
        Self::parse(&text)
    }

    /// Parses SDPA sparse text: the header (m ≤ [`MAX_VARIABLES`], the
    /// number of blocks, their sizes), c, then the entries, each checked
    /// against the header; an entry given twice is an error naming both
    /// lines. Nothing is allocated from the declared sizes.
    pub fn parse(text: &str) -> Result<Self, SdpaError> {
        let mut t = Lines::new(text);
        let (line, m) = header_count(&mut t, "the number of constraint matrices m")?;
        if m > MAX_VARIABLES {
            return Err(parse_error(
                line,
                format!("m = {m} is more than the limit of {MAX_VARIABLES} variables"),
            ));
        }
        let (_, nb) = header_count(&mut t, "the number of blocks")?;
        let blocks = block_sizes(&mut t, nb)?;
        let c = costs(&mut t, m)?;
        let mut entries = Vec::new();
        let mut lines = Vec::new();
        while let Some((line, toks)) = t.next_line() {
            entries.push(entry(line, &toks, m, &blocks)?);
            lines.push(line);
        }
        let key = |k: usize| -> (usize, usize, usize, usize) {
            let e: &Entry = &entries[k];
            (e.0, e.1, e.2, e.3)
        };
        if let Some((a, b)) = first_duplicate(entries.len(), key) {
            let (matrix, blk, i, j) = key(a);
            return Err(SdpaError::Duplicate {
                line: lines[b],
                first_line: lines[a],
                matrix,
                block: blk + 1,
                row: i + 1,
                col: j + 1,
            });
        }
        Ok(Self { c, blocks, entries })
    }

    /// The SDPA sparse text.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "\"written by momentlmi");
        let _ = writeln!(s, "{}", self.m());
        let _ = writeln!(s, "{}", self.blocks.len());
        let _ = writeln!(
            s,
            "{}",
            self.blocks
                .iter()
                .map(|b| b.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        );
        let _ = writeln!(
            s,
            "{}",
            self.c
                .iter()
                .map(|v| format!("{v:e}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        for &(mat, blk, i, j, v) in &self.entries {
            let _ = writeln!(s, "{} {} {} {} {:e}", mat, blk + 1, i + 1, j + 1, v);
        }
        s
    }

    /// Writes the file whole (to a uniquely named temporary file beside it,
    /// registered with [`crate::tempfiles`], then renamed).
    pub fn write(&self, path: &Path) -> Result<(), SdpaError> {
        use std::io::Write;
        let io = |e| SdpaError::Io {
            path: path.to_path_buf(),
            source: e,
        };
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let mut tmp = crate::tempfiles::TempFile::new_in(dir, ".momentlmi-").map_err(io)?;
        tmp.write_all(self.to_text().as_bytes()).map_err(io)?;
        tmp.persist(path).map_err(io)
    }
}
