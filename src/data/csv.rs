//! The CSV format of robot logs.
//!
//! Columns: `t`, then per joint `q_<joint>`, `qd_<joint>`, optionally
//! `qdd_<joint>`, and `tau_<joint>` (SI units: s, rad, rad/s, rad/s², N·m),
//! in any order; extra columns are ignored. Files without `qdd_*` get q̈ from
//! the zero-phase filtered derivative of q̇ ([`super::filter`]). Readers
//! reject NaN/inf, values beyond [`MAX_ABS_VALUE`] (t: [`MAX_ABS_TIME`]),
//! missing or repeated columns, non-increasing time, ragged rows and more
//! than [`MAX_ROWS`] rows with an error naming the row and column. The file
//! is streamed: memory grows with the rows kept, not the file's size.

use super::dataset::Dataset;
use super::error::DataError;
use super::filter::estimate_qdd;
use super::write::write_whole;
use std::path::Path;

/// The most data rows a file may have (10 million: about 3 hours at 1 kHz).
pub const MAX_ROWS: usize = 10_000_000;
/// The largest magnitude of a q, q̇, q̈ or τ value (rad, rad/s, rad/s², N·m):
/// no robot moves or pushes like that, and beyond it products in the
/// regressor lose all precision long before they overflow.
pub const MAX_ABS_VALUE: f64 = 1e8;
/// The largest magnitude of a time stamp (s): room for Unix time.
pub const MAX_ABS_TIME: f64 = 1e12;
/// The most columns a header may have.
pub const MAX_COLUMNS: usize = 100_000;
/// The longest line (bytes): a file without line breaks is not read whole.
pub const MAX_LINE_BYTES: usize = 1 << 24;

/// A reader that fails on a line longer than [`MAX_LINE_BYTES`], so that one
/// record can never take more memory than that.
struct LineLimit<R> {
    inner: R,
    line: usize,
}

impl<R: std::io::Read> std::io::Read for LineLimit<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        for &b in &buf[..n] {
            self.line = if b == b'\n' { 0 } else { self.line + 1 };
            if self.line > MAX_LINE_BYTES {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!("a line longer than {MAX_LINE_BYTES} bytes"),
                ));
            }
        }
        Ok(n)
    }
}

/// Options for reading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Cut-off (Hz) of the zero-phase filter used when q̈ must be computed.
    pub cutoff_hz: f64,
    /// Whether `tau_*` columns are required.
    pub require_tau: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            cutoff_hz: 30.0,
            require_tau: true,
        }
    }
}

impl Dataset {
    /// Reads a CSV file for the given joints.
    pub fn read_csv(path: &Path, joints: &[&str], opts: ReadOptions) -> Result<Self, DataError> {
        let p = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|source| DataError::Io {
            path: p.clone(),
            source,
        })?;
        Self::parse_from(std::io::BufReader::new(file), &p, joints, opts)
    }

    /// Parses CSV text; `path` names it in errors.
    pub fn parse_csv(
        text: &str,
        path: &str,
        joints: &[&str],
        opts: ReadOptions,
    ) -> Result<Self, DataError> {
        Self::parse_from(text.as_bytes(), path, joints, opts)
    }

    fn parse_from(
        input: impl std::io::Read,
        path: &str,
        joints: &[&str],
        opts: ReadOptions,
    ) -> Result<Self, DataError> {
        let mut rdr = ::csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .flexible(true)
            .from_reader(LineLimit {
                inner: input,
                line: 0,
            });
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| DataError::Row {
                path: path.into(),
                row: 0,
                message: e.to_string(),
            })?
            .iter()
            .map(str::to_string)
            .collect();
        let cols = Columns::find(&header, path, joints, opts.require_tau)?;
        let mut d = Dataset {
            joints: joints.iter().map(|s| s.to_string()).collect(),
            t: vec![],
            q: vec![],
            qd: vec![],
            qdd: vec![],
            tau: vec![],
        };
        for (r, rec) in rdr.records().enumerate() {
            let rec = rec.map_err(|e| DataError::Row {
                path: path.into(),
                row: r + 1,
                message: e.to_string(),
            })?;
            if r >= MAX_ROWS {
                return Err(DataError::Row {
                    path: path.into(),
                    row: r + 1,
                    message: format!("more than {MAX_ROWS} data rows; split the log"),
                });
            }
            cols.push_row(&mut d, &rec, &header, path, r + 1)?;
        }
        if d.t.is_empty() {
            return Err(DataError::Row {
                path: path.into(),
                row: 1,
                message: "no data rows".into(),
            });
        }
        if cols.qdd.is_none() {
            d.qdd = qdd_of(&d, path, opts.cutoff_hz)?;
        }
        Ok(d)
    }

    /// The CSV text: `t, q_*, qd_*, qdd_*, tau_*` (tau only when present).
    pub fn to_csv(&self) -> String {
        let mut s = String::from("t");
        for p in ["q", "qd", "qdd", "tau"] {
            if p == "tau" && self.tau.is_empty() {
                continue;
            }
            for j in &self.joints {
                s += &format!(",{p}_{j}");
            }
        }
        s.push('\n');
        for k in 0..self.len() {
            s += &format!("{}", self.t[k]);
            for v in [&self.q, &self.qd, &self.qdd, &self.tau] {
                if v.is_empty() {
                    continue;
                }
                for x in &v[k] {
                    s += &format!(",{x:e}");
                }
            }
            s.push('\n');
        }
        s
    }

    /// Writes the CSV whole or not at all (temporary file, then rename).
    pub fn write_csv(&self, path: &Path) -> Result<(), DataError> {
        write_whole(path, &self.to_csv())
    }
}

/// Where each quantity's columns are in the header.
struct Columns {
    t: usize,
    q: Vec<usize>,
    qd: Vec<usize>,
    qdd: Option<Vec<usize>>,
    tau: Option<Vec<usize>>,
}

impl Columns {
    /// `t`, `q_*`, `qd_*` (and `tau_*` when required) must be there;
    /// `qdd_*` (and optional `tau_*`) are all there or none is.
    fn find(
        header: &[String],
        path: &str,
        joints: &[&str],
        require_tau: bool,
    ) -> Result<Self, DataError> {
        let index = check_header(header, path)?;
        let col = |name: &str| index.get(name).copied();
        let need = |name: String| -> Result<usize, DataError> {
            col(&name).ok_or_else(|| DataError::MissingColumn {
                path: path.into(),
                column: name,
                header: header.join(","),
            })
        };
        let all = |p: &str| -> Result<Vec<usize>, DataError> {
            joints.iter().map(|j| need(format!("{p}_{j}"))).collect()
        };
        // optional columns: all of them or none (a partial set is an error)
        let any = |p: &str| -> Result<Option<Vec<usize>>, DataError> {
            if joints.iter().any(|j| col(&format!("{p}_{j}")).is_some()) {
                all(p).map(Some)
            } else {
                Ok(None)
            }
        };
        Ok(Self {
            t: need("t".into())?,
            q: all("q")?,
            qd: all("qd")?,
            qdd: any("qdd")?,
            tau: if require_tau {
                Some(all("tau")?)
            } else {
                any("tau")?
            },
        })
    }

    /// Reads one record (1-based data `row`) into `d`, checking its length,
    /// every value and that time increases.
    fn push_row(
        &self,
        d: &mut Dataset,
        rec: &::csv::StringRecord,
        header: &[String],
        path: &str,
        row: usize,
    ) -> Result<(), DataError> {
        if rec.len() != header.len() {
            return Err(DataError::Row {
                path: path.into(),
                row,
                message: format!("has {} fields, the header has {}", rec.len(), header.len()),
            });
        }
        let get = |c: usize| -> Result<f64, DataError> {
            let raw = &rec[c];
            let bad = |message: String| DataError::Value {
                path: path.into(),
                row,
                column: header[c].clone(),
                message,
            };
            let v: f64 = raw
                .parse()
                .map_err(|_| bad(format!("'{raw}' is not a number")))?;
            if !v.is_finite() {
                return Err(bad(format!("non-finite value '{raw}'")));
            }
            let limit = if c == self.t {
                MAX_ABS_TIME
            } else {
                MAX_ABS_VALUE
            };
            if v.abs() > limit {
                return Err(bad(format!("{raw} is beyond ±{limit:e}")));
            }
            Ok(v)
        };
        let many = |ix: &[usize]| ix.iter().map(|&c| get(c)).collect::<Result<Vec<f64>, _>>();
        let t = get(self.t)?;
        if let Some(&prev) = d.t.last()
            && t <= prev
        {
            return Err(DataError::Value {
                path: path.into(),
                row,
                column: "t".into(),
                message: format!("time {t} is not after the previous row's {prev}"),
            });
        }
        d.t.push(t);
        d.q.push(many(&self.q)?);
        d.qd.push(many(&self.qd)?);
        if let Some(ix) = &self.qdd {
            d.qdd.push(many(ix)?);
        }
        if let Some(ix) = &self.tau {
            d.tau.push(many(ix)?);
        }
        Ok(())
    }
}

/// At most [`MAX_COLUMNS`] columns, each named once; returns each name's
/// column.
fn check_header<'h>(
    header: &'h [String],
    path: &str,
) -> Result<std::collections::HashMap<&'h str, usize>, DataError> {
    let bad = |message: String| DataError::Row {
        path: path.into(),
        row: 0,
        message,
    };
    if header.len() > MAX_COLUMNS {
        return Err(bad(format!(
            "{} columns; at most {MAX_COLUMNS}",
            header.len()
        )));
    }
    let mut seen = std::collections::HashMap::with_capacity(header.len());
    for (c, h) in header.iter().enumerate() {
        if let Some(first) = seen.insert(h.as_str(), c) {
            return Err(bad(format!(
                "column '{h}' appears twice (columns {} and {})",
                first + 1,
                c + 1
            )));
        }
    }
    Ok(seen)
}

/// q̈ from q̇ with a cut-off below the file's Nyquist frequency.
fn qdd_of(d: &Dataset, path: &str, cutoff_hz: f64) -> Result<Vec<Vec<f64>>, DataError> {
    let n = d.len();
    let nyquist = if n > 1 {
        0.5 * (n - 1) as f64 / (d.t[n - 1] - d.t[0])
    } else {
        f64::INFINITY
    };
    if !(cutoff_hz > 0.0 && cutoff_hz < nyquist) {
        return Err(DataError::Cutoff {
            path: path.into(),
            cutoff_hz,
            nyquist_hz: nyquist,
        });
    }
    Ok(estimate_qdd(&d.t, &d.qd, cutoff_hz))
}
