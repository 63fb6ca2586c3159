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
    /// Held-out rows `split·n..samples·n`.
    pub heldout: Range<usize>,
}

impl Split {
    /// Samples `0..split` train, the rest are held out.
    pub fn at(samples: usize, joints: usize, split: usize) -> Self {
        Self {
            joints,
            samples,
            first_heldout: split,
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
