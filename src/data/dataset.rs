//! A robot log in memory: samples of t, q, q̇, q̈, τ for named joints.

/// Samples of joint positions, velocities, accelerations and torques.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    /// Joint names (column suffixes).
    pub joints: Vec<String>,
    /// Sample times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Positions, one `Vec` of length n per sample.
    pub q: Vec<Vec<f64>>,
    /// Velocities.
    pub qd: Vec<Vec<f64>>,
    /// Accelerations.
    pub qdd: Vec<Vec<f64>>,
    /// Torques (empty when the file has none, e.g. a trajectory to predict on).
    pub tau: Vec<Vec<f64>>,
}

impl Dataset {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Keeps only the samples in `range`, in place (no copy); empty series
    /// (no torques) stay empty.
    pub fn keep(&mut self, range: std::ops::Range<usize>) {
        self.t.truncate(range.end);
        self.t.drain(..range.start.min(self.t.len()));
        for v in [&mut self.q, &mut self.qd, &mut self.qdd, &mut self.tau] {
            v.truncate(range.end);
            v.drain(..range.start.min(v.len()));
        }
    }

    /// The samples `range` as a new data set.
    pub fn slice(&self, range: std::ops::Range<usize>) -> Dataset {
        let cut = |v: &Vec<Vec<f64>>| {
            if v.is_empty() {
                vec![]
            } else {
                v[range.clone()].to_vec()
            }
        };
        Dataset {
            joints: self.joints.clone(),
            t: self.t[range.clone()].to_vec(),
            q: cut(&self.q),
            qd: cut(&self.qd),
            qdd: cut(&self.qdd),
            tau: cut(&self.tau),
        }
    }
}
