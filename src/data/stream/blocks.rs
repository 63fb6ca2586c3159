//! A file read in blocks of whole lines by the calling thread, each block
//! handed to a task on the thread pool, and the tasks' results taken back
//! in the file's order, as they come, with at most a few blocks out.

use super::super::csv::{MAX_LINE_BYTES, MAX_ROWS};
use super::super::error::DataError;
use super::rows::{Fail, row_error, too_many_rows};
use std::io::Read;
use std::sync::{Condvar, Mutex};

/// A block's text and where it sits: the 1-based data row of its first
/// record and its number of records (non-empty lines, as the whole-file
/// CSV reader counts rows: `\n`, `\r\n` and `\r` end a line).
pub(super) struct Text<'a> {
    pub bytes: &'a [u8],
    pub first_row: usize,
    pub records: usize,
}

/// Reads `file` (after `rest`, the bytes already read) in blocks of whole
/// lines of about `size` bytes, runs `task` on each on the thread pool and
/// hands the results to `take` in order, on this thread, as they come
/// (`take` returns `false` to stop). At most `2 × threads + 1` blocks are
/// out (handed to a task and not yet taken), each's bytes held until it is
/// taken, and together (but one block) at most that many times `size`
/// bytes: long lines make fewer blocks out; one more block is being read.
/// Up to as many buffers of at most `4 × size` bytes are kept for reuse.
///
/// A failure reading the file ends the reading (the blocks read before it
/// are still taken), as does a block that starts past [`MAX_ROWS`] rows.
pub(super) fn blocks<R: Send>(
    (file, rest, size): (&mut std::fs::File, &mut Vec<u8>, usize),
    path: &str,
    task: impl Fn(&Text) -> R + Sync,
    take: &mut impl FnMut(R) -> bool,
) -> Result<(), Fail> {
    let limit = 2 * rayon::current_num_threads() + 1;
    let queue = Queue::default();
    // the blocks' buffers, reused: fresh pages cost more than the parsing
    let pool: Mutex<Vec<Vec<u8>>> = Mutex::new(vec![]);
    let mut failure = Ok(());
    rayon::in_place_scope(|s| {
        let (mut issued, mut taken, mut first_row) = (0usize, 0usize, 1usize);
        let mut out = std::collections::VecDeque::new(); // the bytes of the blocks out
        loop {
            let spare = (pool.lock().ok()).and_then(|mut p| p.pop());
            let next = next_block((file, rest, size), spare.unwrap_or_default(), path);
            let block = match next.map_err(|f| f.at_row(path, first_row)) {
                Ok(Some(b)) => b,
                Ok(None) => break,
                Err(f) => {
                    failure = Err(f);
                    break;
                }
            };
            let records = records(&block);
            if records > 0 && first_row > MAX_ROWS {
                failure = Err(too_many_rows(path).into());
                break;
            }
            // room for this block: the oldest taken until it fits
            let fits = |out: &std::collections::VecDeque<usize>| {
                out.len() < limit && out.iter().sum::<usize>() + block.len() <= limit * size
            };
            while !out.is_empty() && !fits(&out) {
                let until = taken + 1; // (and any others already done)
                if !queue.take_until(&mut taken, until, take) {
                    return; // `take` stopped: the blocks out are dropped
                }
                out.drain(..out.len() - (issued - taken));
            }
            out.push_back(block.len());
            let (task, queue, pool, index) = (&task, &queue, &pool, issued);
            s.spawn(move |_| {
                let sent = Sent { queue, index };
                let text = Text {
                    bytes: &block,
                    first_row,
                    records,
                };
                let r = task(&text);
                // a buffer grown by a long line is not kept
                if block.capacity() <= 4 * size
                    && let Ok(mut p) = pool.lock()
                {
                    p.push(block);
                }
                sent.send(r);
            });
            issued += 1;
            first_row += records;
        }
        // the rest, in order
        queue.take_until(&mut taken, issued, take);
    });
    failure
}

/// The number of records in `text`: runs of bytes other than `\r` and `\n`
/// (the whole-file CSV reader skips empty lines, and ends a line at `\n`,
/// `\r\n` or `\r`; a quoted line break is not told apart here).
pub(super) fn records(text: &[u8]) -> usize {
    let end = |b: u8| b == b'\n' || b == b'\r';
    let first = text.first().is_some_and(|&b| !end(b)) as usize;
    let (Some(a), Some(b)) = (text.get(..text.len().wrapping_sub(1)), text.get(1..)) else {
        return first;
    };
    // a record starts after each line end not followed by another; summed
    // in bytes over 255-byte runs, which the compiler makes wide (10× faster)
    let starts = a.chunks(255).zip(b.chunks(255)).map(|(a, b)| {
        let here = a.iter().zip(b).map(|(&x, &y)| (end(x) & !end(y)) as u8);
        here.fold(0u8, u8::wrapping_add) as usize
    });
    first + starts.sum::<usize>()
}

/// Why reading the next block failed: the file (an I/O error), or a line
/// longer than [`MAX_LINE_BYTES`] after the block's first `before` records
/// (the whole-file reader refuses it at its row; one holding `\r`-ended
/// records, `Whole: true`, it refuses at a row only it can tell).
pub(super) enum ReadFailure {
    Io(DataError),
    LongLine { before: usize, whole: bool },
}

impl ReadFailure {
    /// The failure of the block whose first record is data row `row`.
    fn at_row(self, path: &str, row: usize) -> Fail {
        match self {
            Self::Io(e) => e.into(),
            Self::LongLine {
                before,
                whole: true,
            } => Fail::Whole(row + before),
            Self::LongLine { before, .. } => {
                let message = format!("a line longer than {MAX_LINE_BYTES} bytes");
                row_error(path, row + before, message).into()
            }
        }
    }

    /// A long line that starts after the first `before` records of a block.
    fn long(line: &[u8], before: usize) -> Self {
        let whole = line.contains(&b'\r');
        Self::LongLine { before, whole }
    }
}

/// The next block of whole lines, each with its line break (the file's
/// last may lack it), or `None` at the end of the file; read into `buf`
/// (emptied first), what is read past the block kept in `rest`.
fn next_block(
    (file, rest, size): (&mut std::fs::File, &mut Vec<u8>, usize),
    mut buf: Vec<u8>,
    path: &str,
) -> Result<Option<Vec<u8>>, ReadFailure> {
    buf.clear();
    buf.append(rest);
    let mut cut = Cut::default();
    loop {
        let eof = match buf.len() < size {
            true => read_more(file, &mut buf, size, path)?,
            false => false,
        };
        if let Some(at) = cut.find(&buf, size) {
            rest.extend_from_slice(&buf[at..]);
            buf.truncate(at);
            return no_long_line(buf).map(Some);
        }
        if eof {
            return no_long_line(buf).map(|b| (!b.is_empty()).then_some(b));
        }
        if buf.len() > MAX_LINE_BYTES {
            return Err(ReadFailure::long(&buf, 0));
        }
        if buf.len() >= size {
            // one long line: as much again as read (at most 1 MiB)
            let upto = buf.len() + buf.len().min(1 << 20);
            if read_more(file, &mut buf, upto, path)? {
                return no_long_line(buf).map(Some);
            }
        }
    }
}

/// Reads more bytes into `buf`, up to `upto` in all; `true` at the end of
/// the file.
fn read_more(
    file: &mut std::fs::File,
    buf: &mut Vec<u8>,
    upto: usize,
    path: &str,
) -> Result<bool, ReadFailure> {
    let want = upto.saturating_sub(buf.len()) as u64;
    // read_to_end fills the spare room without zeroing it first
    let k = (file.take(want).read_to_end(buf)).map_err(|source| {
        ReadFailure::Io(DataError::Io {
            path: path.into(),
            source,
        })
    })?;
    Ok(k == 0)
}

/// Where a block ends: after the last line break in its first `size`
/// bytes, else after the first one past them; what was searched is not
/// searched again.
#[derive(Default)]
struct Cut {
    searched: Option<usize>,
}

impl Cut {
    fn find(&mut self, buf: &[u8], size: usize) -> Option<usize> {
        if buf.len() < size {
            return None;
        }
        let from = match self.searched {
            Some(from) => from,
            None => match buf[..size].iter().rposition(|&b| b == b'\n') {
                Some(i) => return Some(i + 1),
                None => size,
            },
        };
        match buf[from..].iter().position(|&b| b == b'\n') {
            Some(i) => Some(from + i + 1),
            None => {
                self.searched = Some(buf.len());
                None
            }
        }
    }
}

/// `block`, unless a line of it is longer than [`MAX_LINE_BYTES`] (the
/// whole-file reader refuses it).
fn no_long_line(block: Vec<u8>) -> Result<Vec<u8>, ReadFailure> {
    if block.len() <= MAX_LINE_BYTES {
        return Ok(block);
    }
    let mut start = 0;
    for line in block.split(|&b| b == b'\n') {
        if line.len() > MAX_LINE_BYTES {
            return Err(ReadFailure::long(line, records(&block[..start])));
        }
        start += line.len() + 1;
    }
    Ok(block)
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
            let next = loop {
                let mut d = (self.done.lock()).unwrap_or_else(std::sync::PoisonError::into_inner);
                match d.remove(taken) {
                    Some(r) => break r,
                    None if *taken >= until => return true,
                    None => self.wait(d),
                }
            };
            *taken += 1;
            if !next.is_some_and(&mut *take) {
                return false;
            }
        }
    }

    /// Waits for a result to be put. On a thread of the pool, the tasks
    /// may sit in this thread's own queue: it runs pool work meanwhile
    /// instead of sleeping (sleeping would wait for itself).
    fn wait(&self, d: std::sync::MutexGuard<'_, std::collections::BTreeMap<usize, Option<R>>>) {
        if rayon::current_thread_index().is_none() {
            drop(self.ready.wait(d));
            return;
        }
        drop(d);
        if rayon::yield_now() != Some(rayon::Yield::Executed) {
            // nothing to run here: the tasks are on other threads
            let d = (self.done.lock()).unwrap_or_else(std::sync::PoisonError::into_inner);
            let short = std::time::Duration::from_micros(100);
            drop(self.ready.wait_timeout(d, short));
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

#[cfg(test)]
mod tests {
    use super::records;

    /// Records are counted as the whole-file CSV reader counts rows.
    #[test]
    fn records_are_non_empty_lines() {
        let cases: [(&[u8], usize); 9] = [
            (b"", 0),
            (b"\n", 0),
            (b"1", 1),
            (b"1\n2", 2),
            (b"1\n2\n", 2),
            (b"1\n\n\n2\r\n\r\n3", 3),
            (b"1\r2\r3\r", 3),
            (b" \n", 1),
            (b"\r\n1", 1),
        ];
        for (text, n) in cases {
            assert_eq!(records(text), n, "{:?}", String::from_utf8_lossy(text));
            let mut rdr = ::csv::ReaderBuilder::new()
                .has_headers(false)
                .flexible(true)
                .from_reader(text);
            assert_eq!(
                rdr.records().count(),
                n,
                "{:?}",
                String::from_utf8_lossy(text)
            );
        }
        // runs across the counter's 255-byte steps: as many as the CSV reader reads
        let long: Vec<u8> = (0..5000u32)
            .map(|k| match k.wrapping_mul(2_654_435_761) >> 29 {
                0 | 1 => b'\n',
                2 => b'\r',
                _ => b'7',
            })
            .collect();
        let mut rdr = ::csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(&long[..]);
        assert_eq!(records(&long), rdr.records().count());
    }
}
