//! The data's split in time: a training part first, the held-out part last;
//! residuals are stored sample-major (`r[k·n + i]`: sample k, joint i).

use std::ops::Range;

/// Rows of the training and held-out parts.
#[derive(Clone, Debug)]
pub struct Split {
    /// Joints n.
    pub joints: usize,
    /// Samples in all.
    pub samples: usize,
    /// The first held-out sample.
    pub first_heldout: usize,
    /// Training rows `0..split·n`.
    pub train: Range<usize>,
    /// Held-out rows `split·n..samples·n`.
    pub heldout: Range<usize>,
}

impl Split {
    /// The first `⌊samples · fraction⌋` samples train.
    pub fn new(samples: usize, joints: usize, fraction: f64) -> Self {
        let split = ((samples as f64) * fraction) as usize;
        Self {
            joints,
            samples,
            first_heldout: split,
            train: 0..split * joints,
            heldout: split * joints..samples * joints,
        }
    }

    /// Per-block held-out gains `MSE(r) − MSE(after)` (of joint `only`'s
    /// rows, or of every joint's): the held-out samples in `blocks`
    /// consecutive blocks of equal length (±1 sample; a remainder of a few
    /// samples is not a block of its own, whose mean would weigh as much
    /// as a full block's).
    pub fn block_gains(
        &self,
        r: &[f64],
        after: &[f64],
        blocks: usize,
        only: Option<usize>,
    ) -> Vec<f64> {
        let n = self.joints;
        let va = self.heldout.clone();
        let m = va.len() / n;
        let b = blocks.max(2).min(m.max(1));
        let (skip, step) = only.map_or((0, 1), |i| (i, n));
        (0..b)
            .map(|j| {
                let (s, e) = (va.start + j * m / b * n, va.start + (j + 1) * m / b * n);
                let rows = (s + skip..e).step_by(step);
                let count = rows.len().max(1) as f64;
                rows.map(|i| r[i] * r[i] - after[i] * after[i]).sum::<f64>() / count
            })
            .collect()
    }

    /// Joint i's values of the held-out rows of `r`.
    pub fn heldout_of(&self, r: &[f64], i: usize) -> Vec<f64> {
        r[self.heldout.clone()]
            .iter()
            .skip(i)
            .step_by(self.joints)
            .copied()
            .collect()
    }
}
