//! Reading logs: one or several files (each its own segment), in any of
//! the formats ([`csv`](super::csv), [`npz`](super::npz)), through one
//! [`Mapping`](super::mapping::Mapping), prepared ([`super::prepare`]) and joined.

use super::dataset::Dataset;
use super::error::DataError;
use super::options::ReadOptions;
use super::prepare::{FileReport, Prepare, prepare};
use super::raw::RawLog;
use std::path::Path;

/// Logs read and prepared: the samples, joined, and what was done to each
/// file.
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    /// The samples of every segment of every file, in order
    /// ([`Dataset::segments`] marks where each starts).
    pub data: Dataset,
    /// Per file, what preparing it did.
    pub files: Vec<FileReport>,
    /// Time spent reading the files (s), summed over the files (they are
    /// read in parallel: the sum can exceed the wall time).
    pub read_s: f64,
    /// Time spent preparing them (filtering, differentiating; s), summed
    /// over the files.
    pub filter_s: f64,
}

/// Reads `paths` (`.csv`, `.npz`, `.npy`, `.mcap`, by extension; anything
/// else as CSV) for the robot's `joints`, prepares each and joins them.
pub fn read_logs(
    paths: &[&Path],
    joints: &[&str],
    opts: &ReadOptions,
) -> Result<Reading, DataError> {
    use rayon::prelude::*;
    opts.check()?;
    // each file read and prepared on its own (in parallel), then joined in order
    let each = paths
        .par_iter()
        .map(|p| {
            let t0 = std::time::Instant::now();
            let raw = read_raw(p, joints, opts)?;
            let t1 = std::time::Instant::now();
            let prepared = prepare(raw, &prep_of(opts), opts.require_tau)?;
            Ok((prepared, [t1 - t0, t1.elapsed()]))
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<Vec<_>, DataError>>()?; // the first file's error, whichever thread met it first
    let sum = |k: usize| each.iter().map(|e| e.1[k].as_secs_f64()).sum();
    let (read_s, filter_s) = (sum(0), sum(1));
    let mut r = joined(each.into_iter().map(|e| e.0), joints)?;
    (r.read_s, r.filter_s) = (read_s, filter_s);
    Ok(r)
}

/// Reads the logs of a floating-base robot `model` (the column set of
/// [`floating_csv`](super::floating_csv), from CSV or `.npz`), each
/// checked against the robot, with samples and a contact wrench, laid end
/// to end as fixed-base files are (times increasing). Refused before
/// reading when the files could need more than `max_bytes` in memory (a
/// sample's numbers take at most 4× its text).
pub fn read_floating_logs(
    model: &crate::dynamics::Model,
    paths: &[&Path],
    max_bytes: u64,
) -> Result<Vec<Dataset>, DataError> {
    let bytes: u64 = (paths.iter())
        .filter_map(|p| std::fs::metadata(p).ok())
        .map(|m| m.len())
        .sum();
    if bytes.saturating_mul(4) > max_bytes {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        return Err(DataError::Option {
            option: "max_memory_gib",
            value: format!("{:.1}", gib(max_bytes)),
            message: format!(
                "{:.1} GB of logs could need {:.1} GiB in memory, over the limit",
                bytes as f64 / 1e9,
                gib(bytes.saturating_mul(4))
            ),
        });
    }
    let mut logs = (paths.iter())
        .map(|p| read_floating_log(model, p, max_bytes / 16))
        .collect::<Result<Vec<_>, DataError>>()?;
    super::base::lay_end_to_end(&mut logs);
    Ok(logs)
}

/// One floating-base log, checked (at most `values` numbers in an `.npz`:
/// they are held about twice, read then laid out).
fn read_floating_log(
    model: &crate::dynamics::Model,
    p: &Path,
    values: u64,
) -> Result<Dataset, DataError> {
    let ext = p.extension().map(|e| e.to_string_lossy().to_lowercase());
    let file = |message: &str| DataError::File {
        path: p.display().to_string(),
        message: message.into(),
    };
    if matches!(ext.as_deref(), Some("npy" | "mcap")) {
        return Err(file(
            "a floating-base log is read from CSV or a NumPy .npz archive of its columns (docs/floating-base.md); .npy and MCAP are not read for a floating base yet",
        ));
    }
    let log = match ext.as_deref() {
        Some("npz") => super::floating_csv::read_floating_npz(model, p, values)?,
        _ => super::floating_csv::read_floating_csv(model, p)?,
    };
    usable_floating_log(model, log, &p.display().to_string())
}

/// A floating-base log `name` as identification needs it: checked against
/// the robot, with samples and a contact wrench (the readers' and the
/// Python binding's columns' last step).
pub fn usable_floating_log(
    model: &crate::dynamics::Model,
    log: Dataset,
    name: &str,
) -> Result<Dataset, DataError> {
    let file = |message: &str| DataError::File {
        path: name.into(),
        message: message.into(),
    };
    log.check(model).map_err(|e| file(&e.to_string()))?;
    if log.is_empty() {
        return Err(file("no samples (a header only)"));
    }
    if log.contacts.is_empty() {
        return Err(file(
            "no contact wrench columns (force_<link>_x…): the base rows balance the contact wrenches, so a floating-base log needs every one acting on the robot (docs/floating-base.md)",
        ));
    }
    Ok(log)
}

/// Reads `paths` as [`read_logs`] does, without preparing them: the logs
/// as recorded (a file with q̈ has it in [`RawLog::qdd`]).
pub fn read_raw_logs(
    paths: &[&Path],
    joints: &[&str],
    opts: &ReadOptions,
) -> Result<Vec<RawLog>, DataError> {
    use rayon::prelude::*;
    opts.check()?;
    (paths.par_iter())
        .map(|p| read_raw(p, joints, opts))
        .collect::<Vec<_>>()
        .into_iter()
        .collect()
}

fn prep_of(opts: &ReadOptions) -> Prepare {
    Prepare {
        cutoff_hz: opts.cutoff_hz,
        velocity: opts.velocity,
    }
}

/// Whether [`read_logs`] reads `path` as CSV (by its extension: anything
/// but `.npz`, `.npy`, `.mcap` and the formats it refuses).
pub fn read_as_csv(path: &Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    !matches!(
        ext.as_deref(),
        Some("npz" | "npy" | "mcap" | "bag" | "db3" | "parquet")
    )
}

/// One file, raw.
fn read_raw(path: &Path, joints: &[&str], opts: &ReadOptions) -> Result<RawLog, DataError> {
    let mapping = opts.mapping.as_ref();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("mcap") && mapping.is_some_and(|m| m.q.is_none()) {
        return Err(DataError::Array {
            path: path.display().to_string(),
            array: "q".into(),
            message: "the mapping gives no [q] (a topic alone applies to ROS 2 bags only)".into(),
        });
    }
    match ext.as_deref() {
        Some("npz") => super::npz::read_npz(path, mapping, opts.mapping_is_default, joints),
        Some("npy") => super::npz::read_npy(path, joints),
        Some("mcap") => super::ros2::read_mcap(path, mapping, joints),
        Some(ext @ ("bag" | "db3" | "parquet")) => Err(DataError::Array {
            path: path.display().to_string(),
            array: "(file)".into(),
            message: format!(
                "a .{ext} file is not read: convert it (examples/convert_{}.py, docs/inputs.md)",
                if ext == "parquet" {
                    "lerobot"
                } else {
                    "rosbag"
                }
            ),
        }),
        _ => {
            if let Some(raw) = read_prepared_csv(path, joints, opts)? {
                return Ok(raw);
            }
            let p = path.display().to_string();
            let file = std::fs::File::open(path).map_err(|source| DataError::Io {
                path: p.clone(),
                source,
            })?;
            super::csv::read_raw(
                std::io::BufReader::new(file),
                &p,
                (mapping, opts.mapping_is_default),
                joints,
                opts.require_tau,
            )
        }
    }
}

/// A prepared CSV log (q̇ and q̈ for every joint) parsed in blocks on the
/// thread pool ([`super::stream`]): the samples and the errors of the
/// whole-file reader, faster; `None` when that reader is to read the file
/// (not a prepared log, or text the blocks leave to it).
fn read_prepared_csv(
    path: &Path,
    joints: &[&str],
    opts: &ReadOptions,
) -> Result<Option<RawLog>, DataError> {
    let mut out: Option<RawLog> = None;
    let fold = |part: RawLog| {
        match &mut out {
            None => out = Some(part),
            Some(o) => o.append(part),
        }
        true
    };
    let read = super::stream::stream_prepared_csv(path, joints, opts, |b| b.raw.clone(), fold)?;
    Ok(read.and(out))
}

/// Raw logs (recorded samples, from a reader or the caller's arrays)
/// prepared as [`read_logs`] prepares files, and joined in order, each a
/// segment (see [`joined`]).
pub fn prepare_logs(
    raws: Vec<RawLog>,
    joints: &[&str],
    opts: &ReadOptions,
) -> Result<Reading, DataError> {
    opts.check()?;
    let each = (raws.into_iter())
        .map(|raw| prepare(raw, &prep_of(opts), opts.require_tau))
        .collect::<Result<Vec<_>, _>>()?;
    joined(each.into_iter(), joints)
}

/// Prepared files joined: segments in file order; a file whose time stamps
/// do not follow the previous one's is shifted to start one step after it
/// (times stay increasing; the segments stay apart).
fn joined(
    each: impl Iterator<Item = (Vec<Dataset>, FileReport)>,
    joints: &[&str],
) -> Result<Reading, DataError> {
    let mut data = Dataset::empty(joints);
    let mut files = vec![];
    for (segments, report) in each {
        for s in segments {
            if !data.is_empty() && data.tau.is_empty() != s.tau.is_empty() {
                return Err(DataError::Array {
                    path: report.path,
                    array: "tau".into(),
                    message: "torques in some files and not in others".into(),
                });
            }
            data.append_segment(s);
        }
        files.push(report);
    }
    Ok(Reading {
        data,
        files,
        read_s: 0.0,
        filter_s: 0.0,
    })
}

impl Dataset {
    /// Reads a log file for the given joints ([`read_logs`] of one file).
    pub fn read_csv(path: &Path, joints: &[&str], opts: ReadOptions) -> Result<Self, DataError> {
        read_logs(&[path], joints, &opts).map(|r| r.data)
    }

    /// Parses CSV text (one file's); `path` names it in errors.
    pub fn parse_csv(
        text: &str,
        path: &str,
        joints: &[&str],
        opts: ReadOptions,
    ) -> Result<Self, DataError> {
        let raw = super::csv::read_raw(
            text.as_bytes(),
            path,
            (opts.mapping.as_ref(), opts.mapping_is_default),
            joints,
            opts.require_tau,
        )?;
        prepare_logs(vec![raw], joints, &opts).map(|r| r.data)
    }
}
