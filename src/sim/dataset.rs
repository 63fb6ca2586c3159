//! Robot data sets and their CSV files.
//!
//! Columns: `t`, then per joint `q_<joint>`, `qd_<joint>`, optionally
//! `qdd_<joint>`, and `tau_<joint>` (SI units: s, rad, rad/s, rad/s², N·m),
//! in any order; extra columns are ignored. Files without `qdd_*` get q̈ from
//! the zero-phase filtered derivative of q̇ ([`super::filter`]). Readers
//! reject NaN/inf, missing columns, non-increasing time and ragged rows with
//! an error naming the row and column.

use super::filter::{differentiate, filtfilt};
use std::path::Path;

/// Errors of data files, each naming the file and where it applies the row
/// (1-based data row, the header is row 0) and column.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// The file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        message: String,
    },
    /// A required column is missing.
    #[error("{path}: missing column '{column}' (header has: {header})")]
    MissingColumn {
        /// The file.
        path: String,
        /// The column.
        column: String,
        /// The header found.
        header: String,
    },
    /// A bad value.
    #[error("{path}: row {row}, column '{column}': {message}")]
    Value {
        /// The file.
        path: String,
        /// 1-based data row.
        row: usize,
        /// The column.
        column: String,
        /// What is wrong.
        message: String,
    },
    /// A malformed row.
    #[error("{path}: row {row}: {message}")]
    Row {
        /// The file.
        path: String,
        /// 1-based data row.
        row: usize,
        /// What is wrong.
        message: String,
    },
}

/// Samples of joint positions, velocities, accelerations and torques.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    /// Joint names (column suffixes).
    pub joints: Vec<String>,
    /// Sample times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Positions, one `Vec` of length n per sample.
    pub q: Vec<Vec<f64>>,
    /// Velocities.
    pub qd: Vec<Vec<f64>>,
    /// Accelerations.
    pub qdd: Vec<Vec<f64>>,
    /// Torques (empty when the file has none, e.g. a trajectory to predict on).
    pub tau: Vec<Vec<f64>>,
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
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The samples `range` as a new data set.
    pub fn slice(&self, range: std::ops::Range<usize>) -> Dataset {
        let cut = |v: &Vec<Vec<f64>>| {
            if v.is_empty() {
                vec![]
            } else {
                v[range.clone()].to_vec()
            }
        };
        Dataset {
            joints: self.joints.clone(),
            t: self.t[range.clone()].to_vec(),
            q: cut(&self.q),
            qd: cut(&self.qd),
            qdd: cut(&self.qdd),
            tau: cut(&self.tau),
        }
    }

    /// Reads a CSV file for the given joints.
    pub fn read_csv(path: &Path, joints: &[&str], opts: ReadOptions) -> Result<Self, DataError> {
        let p = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| DataError::Io {
            path: p.clone(),
            message: e.to_string(),
        })?;
        Self::parse_csv(&text, &p, joints, opts)
    }

    /// Parses CSV text; `path` names it in errors.
    pub fn parse_csv(
        text: &str,
        path: &str,
        joints: &[&str],
        opts: ReadOptions,
    ) -> Result<Self, DataError> {
        let mut rdr = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .flexible(true)
            .from_reader(text.as_bytes());
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
        let col = |name: &str| header.iter().position(|h| h == name);
        let need = |name: String| -> Result<usize, DataError> {
            col(&name).ok_or_else(|| DataError::MissingColumn {
                path: path.into(),
                column: name,
                header: header.join(","),
            })
        };
        let ti = need("t".into())?;
        let qi: Vec<usize> = joints
            .iter()
            .map(|j| need(format!("q_{j}")))
            .collect::<Result<_, _>>()?;
        let qdi: Vec<usize> = joints
            .iter()
            .map(|j| need(format!("qd_{j}")))
            .collect::<Result<_, _>>()?;
        let qddi: Option<Vec<usize>> = joints.iter().map(|j| col(&format!("qdd_{j}"))).collect();
        let taui: Option<Vec<usize>> = if opts.require_tau {
            Some(
                joints
                    .iter()
                    .map(|j| need(format!("tau_{j}")))
                    .collect::<Result<_, _>>()?,
            )
        } else {
            joints.iter().map(|j| col(&format!("tau_{j}"))).collect()
        };
        let mut d = Dataset {
            joints: joints.iter().map(|s| s.to_string()).collect(),
            t: vec![],
            q: vec![],
            qd: vec![],
            qdd: vec![],
            tau: vec![],
        };
        for (r, rec) in rdr.records().enumerate() {
            let row = r + 1;
            let rec = rec.map_err(|e| DataError::Row {
                path: path.into(),
                row,
                message: e.to_string(),
            })?;
            if rec.len() != header.len() {
                return Err(DataError::Row {
                    path: path.into(),
                    row,
                    message: format!("has {} fields, the header has {}", rec.len(), header.len()),
                });
            }
            let get = |c: usize| -> Result<f64, DataError> {
                let raw = &rec[c];
                let v: f64 = raw.parse().map_err(|_| DataError::Value {
                    path: path.into(),
                    row,
                    column: header[c].clone(),
                    message: format!("'{raw}' is not a number"),
                })?;
                if !v.is_finite() {
                    return Err(DataError::Value {
                        path: path.into(),
                        row,
                        column: header[c].clone(),
                        message: format!("non-finite value '{raw}'"),
                    });
                }
                Ok(v)
            };
            let t = get(ti)?;
            if let Some(&prev) = d.t.last() {
                if t <= prev {
                    return Err(DataError::Value {
                        path: path.into(),
                        row,
                        column: "t".into(),
                        message: format!("time {t} is not after the previous row's {prev}"),
                    });
                }
            }
            d.t.push(t);
            d.q.push(qi.iter().map(|&c| get(c)).collect::<Result<_, _>>()?);
            d.qd.push(qdi.iter().map(|&c| get(c)).collect::<Result<_, _>>()?);
            if let Some(ix) = &qddi {
                d.qdd
                    .push(ix.iter().map(|&c| get(c)).collect::<Result<_, _>>()?);
            }
            if let Some(ix) = &taui {
                d.tau
                    .push(ix.iter().map(|&c| get(c)).collect::<Result<_, _>>()?);
            }
        }
        if d.t.is_empty() {
            return Err(DataError::Row {
                path: path.into(),
                row: 1,
                message: "no data rows".into(),
            });
        }
        if qddi.is_none() {
            d.qdd = estimate_qdd(&d.t, &d.qd, opts.cutoff_hz);
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

/// Writes `text` to `path` via a temporary file and a rename.
pub fn write_whole(path: &Path, text: &str) -> Result<(), DataError> {
    let p = path.display().to_string();
    let tmp = path.with_file_name(format!(
        ".{}.tmp",
        path.file_name().and_then(|f| f.to_str()).unwrap_or("out")
    ));
    std::fs::write(&tmp, text)
        .and_then(|_| std::fs::rename(&tmp, path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            DataError::Io {
                path: p,
                message: e.to_string(),
            }
        })
}

/// q̈ from q̇: zero-phase low-pass at `cutoff_hz`, then central differences.
pub fn estimate_qdd(t: &[f64], qd: &[Vec<f64>], cutoff_hz: f64) -> Vec<Vec<f64>> {
    let n = qd.first().map_or(0, |v| v.len());
    let fs = if t.len() > 1 {
        (t.len() - 1) as f64 / (t[t.len() - 1] - t[0])
    } else {
        1.0
    };
    let mut out = vec![vec![0.0; n]; t.len()];
    for j in 0..n {
        let x: Vec<f64> = qd.iter().map(|r| r[j]).collect();
        let d = differentiate(&filtfilt(&x, cutoff_hz, fs), t);
        for (k, v) in d.into_iter().enumerate() {
            out[k][j] = v;
        }
    }
    out
}
