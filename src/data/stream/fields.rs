//! The records of a line that is not plain numbers, split by the CSV
//! automaton the whole-file reader's CSV reader runs, with its settings
//! (`,` between fields, `"` quotes doubled inside, `\n`, `\r\n` or `\r`
//! ending a record, empty lines skipped, no byte-order mark taken off),
//! each field trimmed of white space as that reader trims it.

use csv_core::{ReadRecordResult, Reader};

/// The automaton and its buffers, reused from line to line.
pub(super) struct Splitter {
    reader: Reader,
    out: Vec<u8>,
    ends: Vec<usize>,
}

/// A record's fields: field `c` ends at `ends[c]` in `text`.
pub(super) struct Record<'a> {
    text: &'a str,
    ends: &'a [usize],
}

impl Record<'_> {
    /// The number of fields.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    /// Field `c` (`c < len()`), trimmed.
    pub fn field(&self, c: usize) -> &str {
        let start = c.checked_sub(1).map_or(0, |b| self.ends[b]);
        // the ends are character boundaries (checked when made)
        self.text
            .get(start..self.ends[c])
            .unwrap_or_default()
            .trim()
    }
}

impl Splitter {
    /// A splitter for lines past a file's first (a byte-order mark is
    /// text there, as it is to the whole-file reader).
    pub fn new() -> Self {
        let mut reader = Reader::new();
        // an empty line read: the automaton strips a mark only before its first
        let _ = reader.read_record(b"\n", &mut [0; 1], &mut [0; 1]);
        Self {
            reader,
            out: vec![],
            ends: vec![],
        }
    }

    /// Hands each record of `line` to `each`: `line` is one line's bytes
    /// with its `\n` (without it only at the end of the file). `Ok(false)`
    /// when a quoted field goes on past the line (it is not read here;
    /// the splitter is then not to be used again).
    pub fn records<E>(
        &mut self,
        line: &[u8],
        mut each: impl FnMut(&Record) -> Result<(), E>,
    ) -> Result<bool, E> {
        // the fields are never longer than the line; the ends grow as needed
        if self.out.len() <= line.len() {
            self.out.resize(line.len() + 1, 0);
        }
        if self.ends.is_empty() {
            self.ends.resize(64, 0);
        }
        let eof = !line.ends_with(b"\n");
        let (mut input, mut out, mut ends) = (line, 0, 0);
        loop {
            let (state, i, o, e) =
                (self.reader).read_record(input, &mut self.out[out..], &mut self.ends[ends..]);
            (input, out, ends) = (&input[i..], out + o, ends + e);
            match state {
                ReadRecordResult::Record => {
                    let Some(record) = self.record(out, ends) else {
                        return Ok(false);
                    };
                    each(&record)?;
                    (out, ends) = (0, 0);
                    if input.is_empty() && !eof {
                        return Ok(true);
                    }
                }
                // (an empty input tells the automaton the file ended)
                ReadRecordResult::InputEmpty if !eof => return Ok(out == 0 && ends == 0),
                ReadRecordResult::InputEmpty => {}
                ReadRecordResult::End => return Ok(true),
                ReadRecordResult::OutputEndsFull => self.ends.resize(2 * self.ends.len(), 0),
                ReadRecordResult::OutputFull => self.out.resize(2 * self.out.len(), 0),
            }
        }
    }

    /// The record of the first `out` bytes and `ends` field ends, unless
    /// it is not UTF-8 text cut at character boundaries.
    fn record(&self, out: usize, ends: usize) -> Option<Record<'_>> {
        let text = std::str::from_utf8(&self.out[..out]).ok()?;
        let ends = &self.ends[..ends];
        ends.iter()
            .all(|&e| text.is_char_boundary(e))
            .then_some(Record { text, ends })
    }
}

#[cfg(test)]
mod tests {
    use super::Splitter;

    /// Lines are split into the records and trimmed fields the CSV crate
    /// reads from the same text, quoted and padded fields, `\r` inside
    /// a byte-order mark and 200 fields included; a quoted field that goes
    /// on past its line is left alone.
    #[test]
    fn lines_split_as_the_csv_reader_splits_them() {
        // more fields than the splitter first has room for
        let many = (0..200)
            .map(|k| format!("\"{k}\""))
            .collect::<Vec<_>>()
            .join(",")
            + "\n";
        let lines: [&[u8]; 11] = [
            many.as_bytes(),
            b"1,2,3\n",
            b" 1 ,\"2\", \"3\" \r\n",
            b"\"a,b\",\"c\"\"d\"\n",
            b"a\"b,c\n",
            b"1\r2\r\r3\n",
            b"\xef\xbb\xbf1,2\n",
            b"\r\n",
            b"x,\"y\"z\n",
            b"1,\"2", // the end of the file: the field ends with it
            b" \n",
        ];
        let mut s = Splitter::new();
        for line in lines {
            let mut got: Vec<Vec<String>> = vec![];
            let whole = s.records(line, |r| {
                got.push((0..r.len()).map(|c| r.field(c).to_string()).collect());
                Ok::<_, ()>(())
            });
            // the whole-file reader's reading of the line after a first record
            let text = [b"h\n", line].concat();
            let mut rdr = ::csv::ReaderBuilder::new()
                .trim(::csv::Trim::All)
                .flexible(true)
                .from_reader(&text[..]);
            let want: Vec<Vec<String>> = (rdr.records())
                .map(|r| r.unwrap().iter().map(str::to_string).collect())
                .collect();
            assert_eq!(
                (whole, got),
                (Ok(true), want),
                "{:?}",
                String::from_utf8_lossy(line)
            );
        }
        for open in [&b"1,\"a\n"[..], b"a\"b,\"c\n", b"\"a\"\"\n"] {
            assert_eq!(s.records(open, |_| Ok::<_, ()>(())), Ok(false));
        }
    }
}
