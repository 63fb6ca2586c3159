//! The folds of the diagnosis' cross-validation: contiguous parts of the
//! data, each held out in turn while the others fit. A real residual is
//! coloured and drifts, so a part is a whole file (a run) when several are
//! given, else a block of time; the last folds are also the held-out part
//! of the final model (`--model-out`), the first ones its fitting part.

use crate::data::Dataset;
use std::ops::Range;

/// Time folds of one record unless told otherwise.
pub const TIME_FOLDS: usize = 5;
/// The most files taken as folds one each (more are grouped in time folds).
pub const MAX_FILE_FOLDS: usize = 10;
/// The fewest samples a file must have to be a fold of its own.
pub const MIN_FOLD_SAMPLES: usize = 50;
/// The fewest folds: a per-joint hypothesis' joints are chosen, within
/// each fold's fitting part, on the other folds held out in turn, which
/// needs two of them (two files are cut into blocks of time instead).
pub const MIN_FOLDS: usize = 3;

/// Contiguous sample ranges that cover the data in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Folds {
    /// The folds' sample ranges, in order.
    pub ranges: Vec<Range<usize>>,
    /// The first `fit` folds fit the final model; the rest hold it out.
    pub fit: usize,
    /// The folds are the data's files (segments), not blocks of time.
    pub by_file: bool,
}

impl Folds {
    /// The folds of `data`: its files when it has [`MIN_FOLDS`] …
    /// [`MAX_FILE_FOLDS`] of at least [`MIN_FOLD_SAMPLES`] samples each (the
    /// last file held out), else `time_folds` (at least [`MIN_FOLDS`]) equal
    /// blocks of time (the first `⌊time_folds · train_fraction⌉` fitting, at
    /// least one each way).
    pub fn new(data: &Dataset, time_folds: usize, train_fraction: f64) -> Self {
        let segs = data.segment_ranges();
        let files = (MIN_FOLDS..=MAX_FILE_FOLDS).contains(&segs.len())
            && segs.iter().all(|s| s.len() >= MIN_FOLD_SAMPLES);
        if files {
            return Self {
                fit: segs.len() - 1,
                ranges: segs,
                by_file: true,
            };
        }
        let (n, k) = (data.len(), time_folds.max(MIN_FOLDS));
        let fit = ((k as f64 * train_fraction).round() as usize).clamp(1, k - 1);
        Self {
            ranges: (0..k).map(|j| j * n / k..(j + 1) * n / k).collect(),
            fit,
            by_file: false,
        }
    }

    /// Number of folds.
    pub fn len(&self) -> usize {
        self.ranges.len()
    }

    /// Whether there are none (never, once built).
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// The first sample of the held-out part.
    pub fn first_heldout(&self) -> usize {
        self.ranges[self.fit].start
    }

    /// The fold holding sample `k`.
    pub fn of_sample(&self, k: usize) -> usize {
        self.ranges.partition_point(|r| r.end <= k)
    }

    /// In words, for reports: `"5 blocks of time"`, `"3 files"`.
    pub fn describe(&self) -> String {
        match self.by_file {
            true => format!("{} files", self.len()),
            false => format!("{} blocks of time", self.len()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Folds;
    use crate::data::Dataset;

    fn data(lengths: &[usize]) -> Dataset {
        let mut d = Dataset::empty(&["j"]);
        for &len in lengths {
            let mut s = Dataset::empty(&["j"]);
            for k in 0..len {
                s.t.push(k as f64 * 0.01);
                s.q.push(&[0.0]);
                s.qd.push(&[0.0]);
                s.qdd.push(&[0.0]);
                s.tau.push(&[0.0]);
            }
            d.append_segment(s);
        }
        d
    }

    /// Files become folds (the last one held out); one record, or files
    /// too short to stand alone, become blocks of time.
    #[test]
    fn files_are_folds_else_blocks_of_time() {
        let f = Folds::new(&data(&[300, 200, 250]), 5, 0.6);
        assert!(f.by_file);
        assert_eq!(f.ranges, [0..300, 300..500, 500..750]);
        assert_eq!((f.fit, f.first_heldout()), (2, 500));
        assert_eq!(f.of_sample(299), 0);
        assert_eq!(f.of_sample(300), 1);
        let one = Folds::new(&data(&[1000]), 5, 0.6);
        assert!(!one.by_file);
        assert_eq!(one.ranges.len(), 5);
        assert_eq!((one.fit, one.first_heldout()), (3, 600));
        let short = Folds::new(&data(&[600, 20]), 5, 0.6);
        assert!(!short.by_file && short.len() == 5);
    }
}
