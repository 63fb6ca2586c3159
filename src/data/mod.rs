//! # `data`: robot logs on disk
//!
//! The log format every layer above reads and writes, apart from the
//! simulator that makes logs:
//!
//! - [`Dataset`]: samples of t, q, q̇, q̈, τ for named joints;
//! - [`read_logs`]: one or several log files (CSV, NumPy `.npz`/`.npy`),
//!   ROS 2 bags of `sensor_msgs/msg/JointState` in MCAP ([`ros2`]),
//!   each its own segment, through one [`Mapping`] (which array or column is
//!   q, q̇, q̈, τ of which joint, in which unit), [`prepare`]d as a careful
//!   hand would (repeated rows dropped, split at gaps, resampled, one
//!   zero-phase low-pass on q and τ, derivatives), with a report per file;
//! - [`csv`](mod@csv): the CSV format (`t, q_<joint>[, qd_<joint>][, qdd_<joint>][, tau_<joint>]`,
//!   SI units, any column order) with validation naming the row and column;
//! - [`filter`]: the zero-phase Butterworth low-pass and the differentiator
//!   that give q̈ (and, for raw encoders, q̇) offline;
//! - [`stream`]: a prepared CSV log (with q̈) streamed in blocks of rows,
//!   parsed on the thread pool, for reductions that need one pass;
//! - [`rms`], [`rms_per_joint`]: the one RMS helper;
//! - [`target`]: what an output path names (a file, standard output, a device) and so
//!   how it is written;
//! - [`write`](mod@write): outputs written whole or not at all, and the JSON record
//!   written beside a CSV (how the data were made).

pub mod base;
pub mod csv;
mod dataset;
mod error;
pub mod filter;
pub mod floating_csv;
pub mod mapping;
pub mod npz;
mod options;
pub mod prepare;
mod raw;
mod read;
pub mod ros2;
pub mod spectrum;
mod stats;
pub mod stream;
pub mod target;
mod warning;
pub mod write;

pub use crate::dynamics::Samples;
pub use dataset::Dataset;
pub use error::DataError;
pub use filter::estimate_qdd;
pub use mapping::Mapping;
pub use options::ReadOptions;
pub use prepare::{FileReport, Prepare, Velocity};
pub use raw::RawLog;
pub use read::{
    Reading, prepare_logs, read_as_csv, read_floating_logs, read_logs, read_raw_logs,
    usable_floating_log,
};
pub use stats::{rms, rms_per_joint};
pub use target::Target;
pub use warning::ReadWarning;
pub use write::{
    Staged, record_path, same_file, stage_with_record, write_whole, write_with_record,
};
