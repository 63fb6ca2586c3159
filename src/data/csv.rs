//! The CSV format of robot logs.
//!
//! Columns: `t`, then per joint `q_<joint>`, `qd_<joint>`, optionally
//! `qdd_<joint>`, and `tau_<joint>` (SI units: s, rad, rad/s, rad/s², N·m),
//! in any order; extra columns are ignored. Files without `qdd_*` get q̈ from
//! the zero-phase filtered derivative of q̇ ([`super::filter`]). Readers
//! reject NaN/inf, missing columns, non-increasing time and ragged rows with
//! an error naming the row and column.

use super::dataset::Dataset;
use super::error::DataError;
use super::filter::estimate_qdd;
use super::write::write_whole;
use std::path::Path;

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
        let text = std::fs::read_to_string(path).map_err(|source| DataError::Io {
            path: p.clone(),
            source,
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
        let mut rdr = ::csv::ReaderBuilder::new()
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
            let n = d.len();
            let nyquist = if n > 1 {
                0.5 * (n - 1) as f64 / (d.t[n - 1] - d.t[0])
            } else {
                f64::INFINITY
            };
            if !(opts.cutoff_hz > 0.0 && opts.cutoff_hz < nyquist) {
                return Err(DataError::Cutoff {
                    path: path.into(),
                    cutoff_hz: opts.cutoff_hz,
                    nyquist_hz: nyquist,
                });
            }
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
