//! The CSV format of robot logs.
//!
//! Columns: `t`, then per joint `q_<joint>`, optionally `qd_<joint>`,
//! `qdd_<joint>` and `tau_<joint>` (SI units: s, rad, rad/s, rad/s², N·m),
//! in any order; extra columns are ignored; a [`Mapping`] names other
//! columns and units. A file with `qdd_*` is taken as prepared; one without
//! is a raw log ([`super::prepare`]). Readers reject NaN/inf, values beyond
//! [`MAX_ABS_VALUE`] (t: [`MAX_ABS_TIME`]), missing or repeated columns,
//! ragged rows and more than [`MAX_ROWS`] rows with an error naming the row
//! and column. The file is streamed: memory grows with the rows kept, not
//! the file's size.

use super::dataset::Dataset;
use super::error::DataError;
use super::mapping::{Kind, Mapping};
pub use super::raw::{MAX_ABS_TIME, MAX_ABS_VALUE, MAX_ROWS};
use super::raw::{RawLog, joint_positions};
use super::write::write_whole;
use crate::dynamics::Samples;
use std::path::Path;
/// The most columns a header may have.
pub const MAX_COLUMNS: usize = 100_000;
/// The longest line (bytes): a file without line breaks is not read whole.
pub const MAX_LINE_BYTES: usize = 1 << 24;

/// A reader that fails on a line longer than [`MAX_LINE_BYTES`], so that one
/// record can never take more memory than that.
pub(crate) struct LineLimit<R> {
    inner: R,
    line: usize,
}

impl<R> LineLimit<R> {
    /// `inner`, failing on a line longer than [`MAX_LINE_BYTES`].
    pub(crate) fn new(inner: R) -> Self {
        Self { inner, line: 0 }
    }
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

impl Dataset {
    /// The CSV text: `t`, the base's columns when the log has a base
    /// (module [`floating_csv`](super::floating_csv)), `q_*, qd_*, qdd_*,
    /// tau_*` (tau only when present), then the contact wrenches' columns.
    pub fn to_csv(&self) -> String {
        let mut s = self.csv_header().join(",");
        s.push('\n');
        for k in 0..self.len() {
            s += &format!("{}", self.t[k]);
            for x in &self.csv_row(k)[1..] {
                s += &format!(",{x:e}");
            }
            s.push('\n');
        }
        s
    }

    /// Sample `k`'s values in the order of [`csv_header`](Self::csv_header).
    pub fn csv_row(&self, k: usize) -> Vec<f64> {
        let mut row = vec![self.t[k]];
        let base = self.base.iter().flat_map(|b| [&b.pose, &b.twist, &b.accel]);
        for v in base.chain([&self.q, &self.qd, &self.qdd, &self.tau]) {
            if !v.is_empty() {
                row.extend(&v[k]);
            }
        }
        for c in &self.contacts {
            // (a channel shorter than the log, which `check` names: NaN)
            let w = c.wrench.get(6 * k..6 * k + 6);
            row.extend(w.map_or([f64::NAN; 6].to_vec(), <[f64]>::to_vec));
        }
        row
    }

    /// The column names [`to_csv`](Self::to_csv) writes.
    pub fn csv_header(&self) -> Vec<String> {
        let mut h = vec!["t".to_string()];
        if self.base.is_some() {
            h.extend(super::base::base_columns());
        }
        for p in ["q", "qd", "qdd", "tau"] {
            if p != "tau" || !self.tau.is_empty() {
                h.extend(self.joints.iter().map(|j| format!("{p}_{j}")));
            }
        }
        for c in &self.contacts {
            h.extend(super::base::contact_columns(c));
        }
        h
    }

    /// Writes the CSV whole or not at all (temporary file, then rename).
    pub fn write_csv(&self, path: &Path) -> Result<(), DataError> {
        write_whole(path, &self.to_csv())
    }
}

/// Reads a CSV stream through `mapping` (default: the format's own
/// names; when it is only the robot's default, a header with `t` and not
/// the mapping's time column is read with the format's own names) into a
/// raw log for the robot's `joints`.
pub(crate) fn read_raw(
    input: impl std::io::Read,
    path: &str,
    (mapping, only_default): (Option<&Mapping>, bool),
    joints: &[&str],
    require_tau: bool,
) -> Result<RawLog, DataError> {
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
    let cols = columns_of(&header, path, (mapping, only_default), joints, require_tau)?;
    let mut d = RawLog {
        path: path.into(),
        q: Samples::new(joints.len()),
        ..RawLog::default()
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
        cols.push_fields(&mut d, (rec.len(), |c| &rec[c]), &header, path, r + 1)?;
    }
    Ok(d)
}

/// The columns of `header` for the robot's `joints`, through `mapping` or
/// the format's own names (see [`read_raw`]).
pub(super) fn columns_of(
    header: &[String],
    path: &str,
    (mapping, only_default): (Option<&Mapping>, bool),
    joints: &[&str],
    require_tau: bool,
) -> Result<Columns, DataError> {
    refuse_base_columns(header, path)?;
    let default = Mapping::csv_default();
    let mut mapping = mapping.unwrap_or(&default);
    let has = |name: &str| header.iter().any(|h| h == name);
    if only_default && has("t") && !has(mapping.time_name()) {
        mapping = &default; // the format's own names, not the robot's default mapping
    }
    Columns::find(header, path, mapping, joints, require_tau)
}

/// A floating base's log (the base's whole pose: `base_x` … `base_qw`) read
/// for a robot with a fixed base would lose the base's motion: an error
/// naming the first of its columns and how to load the robot with a free
/// root. (A column or two of a base's name alone is an extra column, as any.)
pub(super) fn refuse_base_columns(header: &[String], path: &str) -> Result<(), DataError> {
    let pose: Vec<String> = super::base::base_columns().take(7).collect();
    if !pose.iter().all(|c| header.contains(c)) {
        return Ok(());
    }
    Err(DataError::Value {
        path: path.into(),
        row: 0,
        column: pose[0].clone(),
        message: "a floating base's log (its pose), for a robot loaded with a fixed base: load it with a free-flying root (the floating-base option or [floating_base])".into(),
    })
}

/// Where each quantity's columns are in the header (per robot joint), and
/// the factor of each to SI units.
pub(super) struct Columns {
    t: (usize, f64),
    q: (Vec<usize>, f64),
    qd: Option<(Vec<usize>, f64)>,
    pub(super) qdd: Option<(Vec<usize>, f64)>,
    tau: Option<(Vec<usize>, f64)>,
}

impl Columns {
    /// The mapping's columns: the time and q (and τ if `require_tau`) must
    /// be there, every other
    /// quantity is all there or absent (a partial set is an error; with
    /// the default names, `qd_*` and `tau_*` may be absent).
    pub(super) fn find(
        header: &[String],
        path: &str,
        mapping: &Mapping,
        joints: &[&str],
        require_tau: bool,
    ) -> Result<Self, DataError> {
        let index = check_header(header, path)?;
        let missing = |name: &str| DataError::MissingColumn {
            path: path.into(),
            column: name.into(),
            header: header.join(","),
        };
        let t = *index
            .get(mapping.time_name())
            .ok_or_else(|| missing(mapping.time_name()))?;
        let order = mapping.joint_order(joints);
        let mut found: [Option<(Vec<usize>, f64)>; 4] = Default::default();
        for (slot, k) in found.iter_mut().zip(Kind::ALL) {
            let Some(qm) = mapping.quantity(k) else {
                continue;
            };
            let names = qm.per_joint(&order).ok_or_else(|| DataError::Mapping {
                path: path.into(),
                message: format!(
                    "[{}]: a CSV needs one column per joint: `{{joint}}` in source, or columns",
                    k.prefix()
                ),
            })?;
            let have: Vec<Option<usize>> = names
                .iter()
                .map(|n| index.get(n.as_str()).copied())
                .collect();
            let needed = k == Kind::Q || (k == Kind::Tau && require_tau);
            if have.iter().all(Option::is_none) && !needed {
                continue;
            }
            if let Some(m) = names.iter().zip(&have).find(|(_, h)| h.is_none()) {
                return Err(missing(m.0));
            }
            let label = names.first().cloned().unwrap_or_default();
            let pos = joint_positions(joints, &order, path, &label)?;
            let cols = pos.iter().map(|&p| have[p].expect("checked")).collect();
            *slot = Some((cols, qm.scale().unwrap_or(1.0)));
        }
        let [q, qd, qdd, tau] = found;
        Ok(Self {
            t: (t, mapping.time_scale().unwrap_or(1.0)),
            q: q.ok_or_else(|| missing("q"))?,
            qd,
            qdd,
            tau,
        })
    }

    /// Whether the file has q̇ for every joint.
    pub(super) fn has_qd(&self) -> bool {
        self.qd.is_some()
    }

    /// Whether the file has each of q̇, q̈ and τ.
    pub(super) fn series(&self) -> [bool; 3] {
        [self.qd.is_some(), self.qdd.is_some(), self.tau.is_some()]
    }

    /// Reads one record of numbers already parsed (`values[c]`, field `c`'s)
    /// into `d` when each value it uses is finite and within the limits;
    /// otherwise reads nothing and returns `false`, for
    /// [`push_fields`](Self::push_fields) to name the problem.
    pub(super) fn push_values(&self, d: &mut RawLog, values: &[f64]) -> bool {
        let fine = |c: usize, s: f64, limit: f64| (values[c] * s).abs() <= limit;
        let series = [
            Some(&self.q),
            self.qd.as_ref(),
            self.qdd.as_ref(),
            self.tau.as_ref(),
        ];
        let all = |(ix, s): &(Vec<usize>, f64)| ix.iter().all(|&c| fine(c, *s, MAX_ABS_VALUE));
        if !(fine(self.t.0, self.t.1, MAX_ABS_TIME) && series.into_iter().flatten().all(all)) {
            return false;
        }
        let scaled = |(ix, s): &(Vec<usize>, f64), dst: &mut Samples| {
            dst.try_push_with(|j| Ok::<_, std::convert::Infallible>(values[ix[j]] * s))
        };
        d.t.push(values[self.t.0] * self.t.1);
        let _ = scaled(&self.q, &mut d.q);
        for (src, dst) in [
            (&self.qd, &mut d.qd),
            (&self.qdd, &mut d.qdd),
            (&self.tau, &mut d.tau),
        ] {
            if let Some(c) = src {
                let _ = scaled(c, dst.get_or_insert_with(|| Samples::new(c.0.len())));
            }
        }
        true
    }

    /// Reads one record (1-based data `row`; its number of fields and
    /// field `c` by `field(c)`) into `d`, checking its length and every
    /// value.
    pub(super) fn push_fields<'r>(
        &self,
        d: &mut RawLog,
        (len, field): (usize, impl Fn(usize) -> &'r str),
        header: &[String],
        path: &str,
        row: usize,
    ) -> Result<(), DataError> {
        if len != header.len() {
            return Err(DataError::Row {
                path: path.into(),
                row,
                message: format!("has {len} fields, the header has {}", header.len()),
            });
        }
        let get = |c: usize, scale: f64| -> Result<f64, DataError> {
            let raw = field(c);
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
            let v = v * scale;
            match super::raw::refusal(v, super::raw::limit(c == self.t.0)) {
                Some(why) => Err(bad(why)),
                None => Ok(v),
            }
        };
        let many =
            |(ix, s): &(Vec<usize>, f64), dst: &mut Samples| dst.try_push_with(|j| get(ix[j], *s));
        d.t.push(get(self.t.0, self.t.1)?);
        many(&self.q, &mut d.q)?;
        for (src, dst) in [
            (&self.qd, &mut d.qd),
            (&self.qdd, &mut d.qdd),
            (&self.tau, &mut d.tau),
        ] {
            if let Some(c) = src {
                many(c, dst.get_or_insert_with(|| Samples::new(c.0.len())))?;
            }
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
