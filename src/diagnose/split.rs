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
