//! Training logs reduced while they are read: each block of rows of a
//! prepared CSV log ([`crate::data::stream`]) is parsed and reduced to its
//! Gram sums on the thread pool, and the blocks' sums are added in the
//! file's order. Nothing holds the samples: memory is a few blocks of text
//! and one small accumulator per block, whatever the number of samples,
//! and the result equals [`reduce_samples`](super::reduce_samples) of the
//! same samples read whole (to rounding: the sums are added in another
//! order).

use super::error::IdentifyError;
use super::reduce::{Reduced, StreamReducer};
use crate::data::stream::{Block, stream_prepared_csv};
use crate::data::{FileReport, ReadOptions};
use crate::dynamics::Model;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};

/// Logs reduced as they were read.
#[derive(Clone, Debug)]
pub struct StreamedLogs {
    /// Their reduction (`reduce_time_s`: reading and reducing, which overlap).
    pub reduced: Reduced,
    /// Per file, what reading it did.
    pub files: Vec<FileReport>,
    /// Time spent parsing the files (s), summed over their blocks (parsed
    /// in parallel, and overlapping the reduction: `reduced.reduce_time_s`
    /// includes it).
    pub read_s: f64,
}

/// Chunk of samples the blocks' reducers multiply out at once.
const CHUNK: usize = 256;

/// Reduces the training logs `paths` for `model` while reading them, when
/// every one is a prepared CSV log (with q̈; as [`read_logs`](crate::data::read_logs)
/// would take it as it is); `None` when one is not (another format, a
/// raw log that needs filtering, or text the streaming reader leaves to the
/// whole-file reader: read them all whole). A `None` can come after
/// earlier files (or blocks) were read and reduced for nothing, which costs
/// time, not the result. An error names the file, row and column, or the
/// sample (counted over all the files, as the whole reduction counts it).
pub fn reduce_logs(
    model: &Model,
    paths: &[&Path],
    opts: &ReadOptions,
) -> Result<Option<StreamedLogs>, IdentifyError> {
    let t0 = std::time::Instant::now();
    // a regular file only: a pipe cannot be read again by the whole reader
    let regular = |p: &&Path| std::fs::metadata(p).is_ok_and(|m| m.is_file());
    if !paths
        .iter()
        .all(|p| crate::data::read_as_csv(p) && regular(p))
    {
        return Ok(None);
    }
    let joints = model.joint_names();
    let mut total: Option<StreamReducer> = None;
    let (mut files, mut read_s, mut failed) = (vec![], 0.0, None);
    // after a failed sum, the files are still read for their own errors,
    // which come first (as when they are read whole), without summing
    let gave_up = AtomicBool::new(false);
    for path in paths {
        let offset = total.as_ref().map_or(0, StreamReducer::samples);
        let each = |b: &Block| (!gave_up.load(Relaxed)).then(|| reduce_block(model, b, offset));
        // each block's sums added as it comes, in the file's order
        let fold = |part: Option<Result<_, IdentifyError>>| {
            let Some(part) = part.filter(|_| failed.is_none()) else {
                return false;
            };
            let merged = part.and_then(|part| match total.take() {
                None => Ok(part),
                Some(t) => t.merge(part),
            });
            match merged {
                Ok(m) => total = Some(m),
                Err(e) => (failed, _) = (Some(e), gave_up.store(true, Relaxed)),
            }
            failed.is_none()
        };
        let Some(streamed) = stream_prepared_csv(path, &joints, opts, each, fold)? else {
            return Ok(None);
        };
        read_s += streamed.read_s;
        files.push(streamed.report);
    }
    if let Some(e) = failed {
        return Err(e);
    }
    let Some(total) = total else {
        return Err(IdentifyError::NoTrainingData {
            samples: 0,
            torques: 0,
        });
    };
    let mut reduced = total.finish()?;
    reduced.reduce_time_s = t0.elapsed().as_secs_f64();
    Ok(Some(StreamedLogs {
        reduced,
        files,
        read_s,
    }))
}

/// One block's samples reduced (`offset`: the samples of the files
/// before, so that errors count samples over all of them).
fn reduce_block<'m>(
    model: &'m Model,
    b: &Block,
    offset: usize,
) -> Result<StreamReducer<'m>, IdentifyError> {
    let raw = b.raw;
    // (a prepared log has q̇ and q̈; τ is there unless not required)
    let (Some(qd), Some(qdd), Some(tau)) = (&raw.qd, &raw.qdd, &raw.tau) else {
        return Err(IdentifyError::NoTrainingData {
            samples: raw.len(),
            torques: 0,
        });
    };
    let mut r = StreamReducer::starting_at(model, CHUNK, offset + b.first_row - 1);
    for s in 0..raw.len() {
        r.push(&raw.q[s], &qd[s], &qdd[s], &tau[s])?;
    }
    r.compact()
}
