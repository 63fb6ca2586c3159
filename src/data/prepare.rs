//! From a raw log to identification data: what a careful hand does to a
//! real robot's log, done the same way every time and reported.
//!
//! A file that already has q̈ is taken as prepared (its rows as they are;
//! time must increase). Otherwise, per file:
//! 1. **repeated rows** — a host-side logger repeats the last state when no
//!    new one arrived: a row whose q, q̇ and τ equal the previous row's bit
//!    for bit, or whose time stamp does, is dropped (counted);
//! 2. **gaps** — a step longer than [`GAP_STEPS`] times the median step
//!    ends a segment; no filter or derivative crosses a segment boundary
//!    (nor a file boundary); segments shorter than [`MIN_SEGMENT`] samples
//!    are dropped (counted);
//! 3. **resampling** — each segment is resampled at the median step by
//!    linear interpolation (steps of real loggers vary several-fold);
//! 4. **one zero-phase low-pass** (2nd-order Butterworth, forward and
//!    backward: [`super::filter::filtfilt`]) on q and τ alike (and on the
//!    file's q̇ when it is used), so that τ stays aligned with the
//!    derivatives; the cut-off is the caller's or chosen from the data
//!    ([`super::spectrum::choose_cutoff`]);
//! 5. **derivatives** — q̇ from the filtered q (default) or the file's
//!    filtered q̇, q̈ from q̇, by central differences;
//! 6. **ends** — one period of the cut-off is trimmed at each segment end,
//!    where the filter's start-up and the one-sided differences are.

use super::dataset::Dataset;
use super::error::DataError;
use super::filter::{differentiate_columns, filtfilt_columns};
use super::raw::RawLog;
use super::warning::ReadWarning;
use crate::dynamics::Samples;
use crate::numfmt::short;
use serde::Serialize;

/// A step this many times the median step (or longer) is a gap.
pub const GAP_STEPS: f64 = 20.0;
/// The fewest samples a segment keeps (shorter ones are dropped).
pub const MIN_SEGMENT: usize = 32;

/// Where q̇ comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Velocity {
    /// Differentiated from the filtered q (the default: a logged velocity
    /// is often filtered by the drive and lags the position).
    #[default]
    Differentiate,
    /// The file's q̇, through the same low-pass.
    File,
}

/// How raw logs are prepared.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Prepare {
    /// The low-pass cut-off (Hz); `None`: chosen from the data.
    pub cutoff_hz: Option<f64>,
    /// Where q̇ comes from.
    pub velocity: Velocity,
}

/// What preparing one file did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FileReport {
    /// The file.
    pub path: String,
    /// Its rows as read.
    pub rows: usize,
    /// Whether it had q̈ and was taken as prepared (the rest then does not apply).
    pub taken_as_prepared: bool,
    /// Rows dropped as repeats of the previous one (same state or same stamp).
    pub repeated_rows_dropped: usize,
    /// The median, smallest and largest step between the rows kept (s).
    pub steps_s: [f64; 3],
    /// The gaps the file was split at (s each).
    pub gaps_s: Vec<f64>,
    /// Segments used.
    pub segments: usize,
    /// Samples in segments shorter than [`MIN_SEGMENT`], dropped.
    pub short_segment_samples_dropped: usize,
    /// The uniform rate the segments were resampled at (Hz).
    pub resampled_hz: f64,
    /// The low-pass cut-off (Hz).
    pub cutoff_hz: f64,
    /// How the cut-off was chosen.
    pub cutoff_from: String,
    /// Where q̇ came from.
    pub velocity: Velocity,
    /// Samples trimmed at each segment end.
    pub trimmed_per_end: usize,
    /// Samples given to the identification.
    pub samples: usize,
    /// What reading the file skipped or substituted.
    pub warnings: Vec<ReadWarning>,
}

/// Prepares one raw log into segments of identification data.
pub fn prepare(
    raw: RawLog,
    opts: &Prepare,
    require_tau: bool,
) -> Result<(Vec<Dataset>, FileReport), DataError> {
    let mut report = FileReport {
        path: raw.path.clone(),
        rows: raw.len(),
        velocity: opts.velocity,
        warnings: raw.warnings.clone(),
        ..FileReport::default()
    };
    if raw.is_empty() {
        return Err(DataError::Row {
            path: raw.path,
            row: 1,
            message: "no data rows".into(),
        });
    }
    if require_tau && raw.tau.is_none() {
        return Err(DataError::Array {
            path: raw.path,
            array: "tau".into(),
            message: "no torques (the mapping's [tau], or the tau_<joint> columns)".into(),
        });
    }
    if raw.qdd.is_some() {
        report.taken_as_prepared = true;
        let d = as_prepared(raw)?;
        report.samples = d.len();
        report.segments = 1;
        return Ok((vec![d], report));
    }
    if opts.velocity == Velocity::File && raw.qd.is_none() {
        return Err(DataError::Array {
            path: raw.path,
            array: "qd".into(),
            message: "velocities from the file were asked for, and it has none".into(),
        });
    }
    let raw = drop_repeats(raw, &mut report)?;
    let pieces = split_at_gaps(&raw, &mut report);
    // the rate to a micro-hertz: 1/0.02 s is 50 Hz, not 49.99999999999999
    let fs = (1e6 / report.steps_s[0]).round() / 1e6;
    report.resampled_hz = fs;
    let uniform: Vec<RawLog> = pieces
        .iter()
        .map(|r| resample(&raw, r.clone(), fs))
        .collect();
    let (cutoff, from) = match opts.cutoff_hz {
        Some(c) => (c, "given".to_string()),
        None => super::spectrum::choose_cutoff(&uniform, fs),
    };
    check_cutoff(&raw.path, &uniform, fs, cutoff)?;
    (report.cutoff_hz, report.cutoff_from) = (cutoff, from);
    report.trimmed_per_end = (fs / cutoff).ceil() as usize;
    let out: Vec<Dataset> = uniform
        .iter()
        .filter_map(|u| filtered(u, fs, cutoff, opts.velocity, report.trimmed_per_end))
        .collect();
    report.segments = out.len();
    report.samples = out.iter().map(Dataset::len).sum();
    if out.is_empty() {
        return Err(DataError::Row {
            path: raw.path,
            row: 1,
            message: format!(
                "no segment of at least {MIN_SEGMENT} samples is left after dropping repeated rows and splitting at gaps"
            ),
        });
    }
    Ok((out, report))
}

/// The cut-off `cutoff` (Hz) below the Nyquist frequency of `fs` and high
/// enough that one period of it, trimmed at each end, leaves the longest of
/// the `uniform` segments (of the file `path`) the `2 trim + 3` samples a
/// segment keeps at least.
fn check_cutoff(path: &str, uniform: &[RawLog], fs: f64, cutoff: f64) -> Result<(), DataError> {
    let longest = uniform.iter().map(RawLog::len).max().unwrap_or(0);
    let lowest = 2.0 * fs / (longest.max(MIN_SEGMENT) as f64 - 3.0);
    match cutoff >= lowest && cutoff < fs / 2.0 {
        true => Ok(()),
        false => Err(DataError::Cutoff {
            path: path.into(),
            cutoff_hz: cutoff,
            nyquist_hz: fs / 2.0,
            lowest_hz: lowest,
            longest,
        }),
    }
}

/// Steps 1–3 of the module doc on a raw log without q̈: repeated rows
/// dropped, split at gaps, each piece resampled at the median step; the
/// uniform pieces and their rate (Hz). What the low-pass then does to them
/// is [`filter_segment`] (a cut-off chosen on them, say).
pub fn uniform_segments(raw: RawLog) -> Result<(Vec<RawLog>, f64), DataError> {
    let mut report = FileReport::default();
    let raw = drop_repeats(raw, &mut report)?;
    let pieces = split_at_gaps(&raw, &mut report);
    let fs = (1e6 / report.steps_s[0]).round() / 1e6;
    let uniform = pieces.into_iter().map(|r| resample(&raw, r, fs)).collect();
    Ok((uniform, fs))
}

/// Steps 4–6 of the module doc on one uniform segment (rate `fs` Hz):
/// low-passed at `cutoff` Hz, differentiated, `trim` samples dropped at
/// each end; `None` when too short once trimmed.
pub fn filter_segment(
    u: &RawLog,
    fs: f64,
    cutoff: f64,
    velocity: Velocity,
    trim: usize,
) -> Option<Dataset> {
    filtered(u, fs, cutoff, velocity, trim)
}

/// A file with q̈, as it is: time must increase, q̇ must be there.
fn as_prepared(raw: RawLog) -> Result<Dataset, DataError> {
    if let Some(r) = raw.t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(DataError::Value {
            path: raw.path,
            row: r + 2,
            column: "t".into(),
            message: super::raw::not_after(raw.t[r + 1], raw.t[r], "row"),
        });
    }
    let Some(qd) = raw.qd else {
        return Err(DataError::Array {
            path: raw.path,
            array: "qd".into(),
            message: "the file has q̈ (taken as prepared) but no q̇".into(),
        });
    };
    Ok(Dataset {
        joints: vec![],
        t: raw.t,
        q: raw.q,
        qd,
        qdd: raw.qdd.unwrap_or_default(),
        tau: raw.tau.unwrap_or_default(),
        segments: vec![],
        base: None,
        contacts: vec![],
    })
}

/// Drops rows that repeat the previous kept row's state (q, q̇, τ bit for
/// bit) or stamp; time going backwards is an error naming the row.
fn drop_repeats(raw: RawLog, report: &mut FileReport) -> Result<RawLog, DataError> {
    let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    let mut keep = vec![0usize];
    for k in 1..raw.len() {
        let last = *keep.last().expect("one kept");
        if raw.t[k] < raw.t[last] {
            return Err(DataError::Value {
                path: raw.path.clone(),
                row: k + 1,
                column: "t".into(),
                message: format!(
                    "time {} goes back from {}",
                    short(raw.t[k]),
                    short(raw.t[last])
                ),
            });
        }
        let repeat = raw.t[k] == raw.t[last]
            || (same(&raw.q[k], &raw.q[last])
                && raw.qd.as_ref().is_none_or(|v| same(&v[k], &v[last]))
                && raw.tau.as_ref().is_none_or(|v| same(&v[k], &v[last])));
        if !repeat {
            keep.push(k);
        }
    }
    report.repeated_rows_dropped = raw.len() - keep.len();
    if keep.len() == raw.len() {
        return Ok(RawLog { qdd: None, ..raw });
    }
    let pick = |v: Samples| {
        let mut out = Samples::with_capacity(v.width(), keep.len());
        keep.iter().for_each(|&k| out.push(&v[k]));
        out
    };
    Ok(RawLog {
        t: keep.iter().map(|&k| raw.t[k]).collect(),
        q: pick(raw.q),
        qd: raw.qd.map(pick),
        qdd: None,
        tau: raw.tau.map(pick),
        path: raw.path,
        warnings: raw.warnings,
    })
}

/// The row ranges between gaps (steps ≥ [`GAP_STEPS`] × median), those of
/// at least [`MIN_SEGMENT`] rows; the steps and gaps go to the report.
fn split_at_gaps(raw: &RawLog, report: &mut FileReport) -> Vec<std::ops::Range<usize>> {
    let steps: Vec<f64> = raw.t.windows(2).map(|w| w[1] - w[0]).collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(1.0);
    let mut cuts = vec![0];
    for (k, s) in steps.iter().enumerate() {
        if *s >= GAP_STEPS * median {
            cuts.push(k + 1);
            report.gaps_s.push(*s);
        }
    }
    cuts.push(raw.len());
    let small: Vec<f64> = steps
        .iter()
        .copied()
        .filter(|s| *s < GAP_STEPS * median)
        .collect();
    let (lo, hi) = small
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), s| (a.min(*s), b.max(*s)));
    report.steps_s = [median, lo, hi];
    let ranges: Vec<_> = cuts.windows(2).map(|w| w[0]..w[1]).collect();
    report.short_segment_samples_dropped = ranges
        .iter()
        .filter(|r| r.len() < MIN_SEGMENT)
        .map(|r| r.len())
        .sum();
    ranges
        .into_iter()
        .filter(|r| r.len() >= MIN_SEGMENT)
        .collect()
}

/// Rows `r` of `raw` resampled at `fs` Hz from their first stamp, by
/// linear interpolation.
fn resample(raw: &RawLog, r: std::ops::Range<usize>, fs: f64) -> RawLog {
    let (t0, t1) = (raw.t[r.start], raw.t[r.end - 1]);
    let n = ((t1 - t0) * fs).floor() as usize + 1;
    let mut k = r.start;
    let mut at = Vec::with_capacity(n);
    for i in 0..n {
        let t = t0 + i as f64 / fs;
        while k + 2 < r.end && raw.t[k + 1] <= t {
            k += 1;
        }
        let w = ((t - raw.t[k]) / (raw.t[k + 1] - raw.t[k])).clamp(0.0, 1.0);
        at.push((t, k, w));
    }
    let lerp = |v: &Samples| {
        let mut out = Samples::with_capacity(v.width(), at.len());
        for &(_, k, w) in &at {
            let (a, b) = (&v[k], &v[k + 1]);
            out.push_with(|j| a[j] + w * (b[j] - a[j]));
        }
        out
    };
    RawLog {
        path: raw.path.clone(),
        t: at.iter().map(|a| a.0).collect(),
        q: lerp(&raw.q),
        qd: raw.qd.as_ref().map(lerp),
        qdd: None,
        tau: raw.tau.as_ref().map(lerp),
        warnings: vec![],
    }
}

/// One uniform segment low-passed and differentiated, its ends trimmed;
/// `None` when too short once trimmed.
fn filtered(u: &RawLog, fs: f64, cutoff: f64, velocity: Velocity, trim: usize) -> Option<Dataset> {
    let n = u.len();
    if n < MIN_SEGMENT.max(trim.saturating_mul(2).saturating_add(3)) {
        return None;
    }
    let lp = |v: &Samples| filtfilt_columns(v, cutoff, fs);
    let q = lp(&u.q);
    let qd = match (velocity, &u.qd) {
        (Velocity::File, Some(v)) => lp(v),
        _ => differentiate_columns(&q, &u.t),
    };
    let qdd = differentiate_columns(&qd, &u.t);
    let mut d = Dataset {
        joints: vec![],
        t: u.t.clone(),
        q,
        qd,
        qdd,
        tau: u.tau.as_ref().map(lp).unwrap_or_default(),
        segments: vec![],
        base: None,
        contacts: vec![],
    };
    d.keep(trim..n - trim); // the ends dropped in place
    Some(d)
}
