//! A robot log in memory: samples of t, q, q̇, q̈, τ for named joints and,
//! when the log has them, the base's motion and contact wrenches
//! ([`base`](super::base)).

use crate::dynamics::{Samples, WrenchFrame};

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
        let more = (s.base.take(), std::mem::take(&mut s.contacts));
        self.append_beyond_joints(s.len(), more);
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

/// The base's motion over a log, one row per sample.
#[derive(Clone, Debug, PartialEq)]
pub struct BaseMotion {
    /// Position (world, m) then orientation quaternion `x, y, z, w`
    /// (base → world): width 7.
    pub pose: Samples,
    /// Twist in base coordinates, linear (m/s) then angular (rad/s):
    /// width 6.
    pub twist: Samples,
    /// The twist's time derivative, width 6.
    pub accel: Samples,
}

impl BaseMotion {
    /// No samples.
    pub fn new() -> Self {
        Self {
            pose: Samples::new(7),
            twist: Samples::new(6),
            accel: Samples::new(6),
        }
    }

    fn series(&mut self) -> [&mut Samples; 3] {
        [&mut self.pose, &mut self.twist, &mut self.accel]
    }

    /// `rows` rows of NaN (a part of a log that had no base).
    fn pad(&mut self, rows: usize) {
        for x in self.series() {
            let w = x.width();
            (0..rows).for_each(|_| x.push(&vec![f64::NAN; w]));
        }
    }
}

impl Default for BaseMotion {
    fn default() -> Self {
        Self::new()
    }
}

/// The wrenches measured at one frame over a log.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactChannel {
    /// The frame (a URDF link of the robot) where the wrench acts.
    pub frame: String,
    /// The axes the wrench is expressed in.
    pub expressed: WrenchFrame,
    /// Per sample, force (N) then moment about the frame origin (N·m):
    /// `samples × 6`, sample-major.
    pub wrench: Vec<f64>,
}

impl Dataset {
    /// Appends the base motion and contacts of a segment of `added`
    /// samples, called before its times are (a log with no samples yet
    /// takes them as they are); what one side lacks is NaN, which
    /// [`check`](Self::check) names.
    fn append_beyond_joints(
        &mut self,
        added: usize,
        (base, contacts): (Option<BaseMotion>, Vec<ContactChannel>),
    ) {
        let before = self.t.len();
        match (&mut self.base, base) {
            (Some(b), Some(mut more)) => (b.series().into_iter())
                .zip(more.series())
                .for_each(|(x, y)| x.append(y)),
            (None, base) if before == 0 => self.base = base,
            // a base on one side only: NaN rows, which `check` names
            (Some(b), None) => b.pad(added),
            (None, Some(mut more)) => {
                let mut b = BaseMotion::new();
                b.pad(before);
                b.series()
                    .into_iter()
                    .zip(more.series())
                    .for_each(|(x, y)| x.append(y));
                self.base = Some(b);
            }
            (None, None) => {}
        }
        let mut seen = vec![false; self.contacts.len()];
        for c in contacts {
            match (self.contacts.iter())
                .position(|d| d.frame == c.frame && d.expressed == c.expressed)
            {
                Some(i) => {
                    self.contacts[i].wrench.extend(c.wrench);
                    seen[i] = true;
                }
                None => {
                    let mut wrench = vec![f64::NAN; 6 * before];
                    wrench.extend(c.wrench);
                    self.contacts.push(ContactChannel { wrench, ..c });
                }
            }
        }
        for (d, _) in self.contacts.iter_mut().zip(&seen).filter(|(_, s)| !**s) {
            d.wrench.extend(vec![f64::NAN; 6 * added]);
        }
    }

    /// Keeps the base's and the contacts' samples in `range` (beside
    /// [`keep`](Self::keep)'s joints).
    fn keep_beyond_joints(&mut self, range: &std::ops::Range<usize>) {
        if let Some(b) = &mut self.base {
            b.series().into_iter().for_each(|x| x.keep(range.clone()));
        }
        for c in &mut self.contacts {
            let end = (6 * range.end).min(c.wrench.len());
            c.wrench.truncate(end);
            c.wrench.drain(..(6 * range.start).min(end));
        }
    }

    /// The base's and the contacts' samples in `range`.
    fn slice_beyond_joints(
        &self,
        range: &std::ops::Range<usize>,
    ) -> (Option<BaseMotion>, Vec<ContactChannel>) {
        let base = self.base.as_ref().map(|b| BaseMotion {
            pose: b.pose.slice(range.clone()),
            twist: b.twist.slice(range.clone()),
            accel: b.accel.slice(range.clone()),
        });
        let contacts = (self.contacts.iter())
            .map(|c| ContactChannel {
                wrench: (c.wrench.get(6 * range.start..6 * range.end))
                    .map_or_else(Vec::new, <[f64]>::to_vec),
                ..c.clone()
            })
            .collect();
        (base, contacts)
    }
}
