//! A robot log in memory: samples of t, q, q̇, q̈, τ for named joints and,
//! when the log has them, the base's motion and contact wrenches
//! ([`base`](super::base)).

use super::base::{BaseMotion, ContactChannel};
use crate::dynamics::Samples;

/// Samples of joint positions, velocities, accelerations and torques, and
/// of the base's motion and contact wrenches where the robot has them.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    /// Joint names (column suffixes).
    pub joints: Vec<String>,
    /// Sample times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Positions, one row of n per sample.
    pub q: Samples,
    /// Velocities.
    pub qd: Samples,
    /// Accelerations.
    pub qdd: Samples,
    /// Torques (no rows when the file has none, e.g. a trajectory to predict on).
    pub tau: Samples,
    /// Where each segment starts (sample indices, the first 0), when the
    /// data are several files or a log split at its gaps: no filter or
    /// derivative crossed a boundary. Empty: one segment.
    pub segments: Vec<usize>,
    /// The base's motion, for a robot whose root is free (`None`: a fixed
    /// base).
    pub base: Option<BaseMotion>,
    /// The wrenches measured at contact frames (every external wrench on a
    /// floating base; none is the usual fixed-base log).
    pub contacts: Vec<ContactChannel>,
}

impl Dataset {
    /// No samples, for `joints`.
    pub fn empty(joints: &[&str]) -> Self {
        let n = joints.len();
        Self {
            joints: joints.iter().map(|j| j.to_string()).collect(),
            t: vec![],
            q: Samples::new(n),
            qd: Samples::new(n),
            qdd: Samples::new(n),
            tau: Samples::new(n),
            segments: vec![],
            base: None,
            contacts: vec![],
        }
    }

    /// Appends the samples of `s` as a new segment; when its times do not
    /// follow ours, they are shifted to start one of its steps after our
    /// last (times stay increasing). The base's motion and the contact
    /// channels are appended too (channels matched by frame and axes;
    /// [`check`](Self::check) names a series whose length then differs).
    pub fn append_segment(&mut self, mut s: Dataset) {
        if let Some(&last) = self.t.last() {
            follow(last, &mut s.t);
        }
        if !self.is_empty() {
            if self.segments.is_empty() {
                self.segments.push(0);
            }
            self.segments.push(self.len());
        }
        self.append_beyond_joints(s.base.take(), std::mem::take(&mut s.contacts));
        self.t.append(&mut s.t);
        self.q.append(&mut s.q);
        self.qd.append(&mut s.qd);
        self.qdd.append(&mut s.qdd);
        self.tau.append(&mut s.tau);
    }

    /// The sample ranges of the segments (one: the whole).
    pub fn segment_ranges(&self) -> Vec<std::ops::Range<usize>> {
        let mut starts = self.segments.clone();
        if starts.is_empty() {
            starts.push(0);
        }
        starts.push(self.len());
        starts.windows(2).map(|w| w[0]..w[1]).collect()
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Keeps only the samples in `range`, in place (no copy); series with
    /// no rows (no torques) stay so.
    pub fn keep(&mut self, range: std::ops::Range<usize>) {
        self.t.truncate(range.end);
        self.t.drain(..range.start.min(self.t.len()));
        for v in [&mut self.q, &mut self.qd, &mut self.qdd, &mut self.tau] {
            v.keep(range.clone());
        }
        self.keep_beyond_joints(&range);
        self.segments = segments_within(&self.segments, &range);
    }

    /// The samples `range` as a new data set.
    pub fn slice(&self, range: std::ops::Range<usize>) -> Dataset {
        let cut = |v: &Samples| {
            if v.is_empty() {
                v.clone()
            } else {
                v.slice(range.clone())
            }
        };
        let (base, contacts) = self.slice_beyond_joints(&range);
        Dataset {
            joints: self.joints.clone(),
            t: self.t[range.clone()].to_vec(),
            q: cut(&self.q),
            qd: cut(&self.qd),
            qdd: cut(&self.qdd),
            tau: cut(&self.tau),
            segments: segments_within(&self.segments, &range),
            base,
            contacts,
        }
    }
}

/// The segment starts of `segments` inside `range`, relative to its start
/// (empty: one segment).
fn segments_within(segments: &[usize], range: &std::ops::Range<usize>) -> Vec<usize> {
    let inner: Vec<usize> = (segments.iter())
        .filter(|&&k| k > range.start && k < range.end)
        .map(|k| k - range.start)
        .collect();
    if inner.is_empty() {
        vec![]
    } else {
        [vec![0], inner].concat()
    }
}

/// Shifts the times `t` of a file that does not start after `last` (the
/// previous file's last time) to start one of its own steps after it
/// (1 ms for a single sample): files laid end to end, times increasing.
pub(crate) fn follow(last: f64, t: &mut [f64]) {
    if let Some(&first) = t.first()
        && first <= last
    {
        let step = t.get(1).map_or(1e-3, |t1| t1 - first);
        t.iter_mut().for_each(|x| *x += last + step - first);
    }
}
