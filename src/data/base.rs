//! What a log holds beyond the joints: the base's motion when the robot's
//! root is free (motion capture or an estimator and an IMU) and the
//! wrenches measured at contact frames (force plates, a harness load
//! cell, foot or wrist sensors), with the checks of a [`Dataset`] against
//! the robot ([`Model`]'s conventions: the generalized `q` is 7 + n with
//! the quaternion `x, y, z, w`; `v`, `a` are 6 + n, the base part linear
//! then angular in base coordinates).

use super::Dataset;
pub use super::dataset::{BaseMotion, ContactChannel};
use super::error::DataError;
use super::raw::{limit, not_after, refusal};
use crate::dynamics::{ContactWrench, DynamicsError, Model, Samples, WrenchFrame};

/// One sample's generalized state: `q` (nq), `v` and `a` (nv).
pub type State = (Vec<f64>, Vec<f64>, Vec<f64>);

impl Dataset {
    /// A log of the robot `model` with no samples: its joints, the base's
    /// motion when its root is free, torques, and the contact channels
    /// `contacts` (frame, axes).
    pub fn for_model(model: &Model, contacts: &[(String, WrenchFrame)]) -> Self {
        let mut d = Dataset::empty(&model.joint_names());
        d.base = model.is_floating().then(BaseMotion::new);
        d.contacts = (contacts.iter())
            .map(|(frame, expressed)| ContactChannel {
                frame: frame.clone(),
                expressed: *expressed,
                wrench: vec![],
            })
            .collect();
        d
    }

    /// Whether torques were measured (a log without them fits only the
    /// base rows of a floating base).
    pub fn has_torques(&self) -> bool {
        !self.tau.is_empty() || self.is_empty()
    }

    /// Sample `k`'s generalized `q`, `v`, `a` (the base's, when there is
    /// one, before the joints').
    pub fn state(&self, k: usize) -> State {
        let joined = |b: Option<&Samples>, j: &Samples| match b {
            Some(b) => [&b[k], &j[k]].concat(),
            None => j[k].to_vec(),
        };
        let base = self.base.as_ref();
        (
            joined(base.map(|b| &b.pose), &self.q),
            joined(base.map(|b| &b.twist), &self.qd),
            joined(base.map(|b| &b.accel), &self.qdd),
        )
    }

    /// Appends one sample given as the generalized `q`, `v`, `a` (the
    /// base's part first when the log has a base) and its torques (none:
    /// not measured); the contact wrenches are pushed to
    /// [`contacts`](Self::contacts) by the caller.
    ///
    /// # Panics
    /// If a vector's length is not the log's width (a simulator's
    /// programming error; readers check their rows first).
    pub fn push_state(&mut self, t: f64, (q, v, a): (&[f64], &[f64], &[f64]), tau: Option<&[f64]>) {
        let (qb, vb) = if self.base.is_some() { (7, 6) } else { (0, 0) };
        if let Some(b) = &mut self.base {
            b.pose.push(&q[..qb]);
            b.twist.push(&v[..vb]);
            b.accel.push(&a[..vb]);
        }
        self.t.push(t);
        self.q.push(&q[qb..]);
        self.qd.push(&v[vb..]);
        self.qdd.push(&a[vb..]);
        if let Some(tau) = tau {
            self.tau.push(tau);
        }
    }

    /// Checks the log against the robot: the base's motion there exactly
    /// when the root is free, every series's length and width, every value
    /// finite and within the readers' limits (times too, and increasing),
    /// every quaternion of unit norm, every contact frame one of the
    /// robot's; the error names the series, sample or frame.
    pub fn check(&self, model: &Model) -> Result<(), DataError> {
        let log = |message: String| DataError::Log { message };
        match &self.base {
            Some(_) => model
                .need_free_flyer("a floating-base log")
                .map_err(|e| log(e.to_string()))?,
            None if model.is_floating() => {
                return Err(log(format!(
                    "the log has no base motion (base_* columns) and '{}' has a free-flying base",
                    model.name
                )));
            }
            None => {}
        }
        if self.joints != model.joint_names() {
            return Err(log(format!(
                "its joints {:?} are not the robot's {:?} (in order)",
                self.joints,
                model.joint_names()
            )));
        }
        self.check_series(model.dof())?;
        for c in &self.contacts {
            model
                .frame_index(&c.frame)
                .map_err(|e| log(e.to_string()))?;
            check_array(
                (&format!("wrench of '{}'", c.frame), false),
                &c.wrench,
                self.len(),
                6,
            )?;
        }
        if model.is_floating() {
            for k in 0..self.len() {
                let (q, v, a) = self.state(k);
                (model.base_state(&q, &v, &a))
                    .map_err(|source| DataError::Sample { sample: k, source })?;
            }
        }
        Ok(())
    }

    /// Every series's shape (`n` joints) and values, and the times increasing.
    fn check_series(&self, n: usize) -> Result<(), DataError> {
        let s = self.len();
        check_array(("t", true), &self.t, s, 1)?;
        if let Some(k) = self.t.windows(2).position(|w| w[1] <= w[0]) {
            return Err(DataError::Log {
                message: format!(
                    "t: sample {}: {}",
                    k + 1,
                    not_after(self.t[k + 1], self.t[k], "sample")
                ),
            });
        }
        for (x, width, (name, offset), column) in self.series(n) {
            if x.len() != s || (s > 0 && x.width() != width) {
                return Err(DataError::Log {
                    message: format!(
                        "{column}…: {} samples of {} values, expected {s} of {width}",
                        x.len(),
                        x.width()
                    ),
                });
            }
            for (i, &v) in x.as_flat().iter().enumerate() {
                if let Some(why) = refusal(v, limit(false)) {
                    let (k, e) = (i / width, i % width);
                    return Err(DataError::Log {
                        message: format!(
                            "{name}: sample {k}, entry {} (column {}): {why}",
                            offset + e,
                            column_name(column, e, &self.joints)
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Every series of samples beside the times: (values, width, (its
    /// name in the generalized vectors, its first entry there), its
    /// columns' prefix).
    fn series(&self, n: usize) -> Vec<(&Samples, usize, (&'static str, usize), &'static str)> {
        let mut v = vec![];
        let (qb, vb) = match &self.base {
            Some(b) => {
                v.push((&b.pose, 7, ("q", 0), "base_pose"));
                v.push((&b.twist, 6, ("v", 0), "base_twist"));
                v.push((&b.accel, 6, ("a", 0), "base_accel"));
                (7, 6)
            }
            None => (0, 0),
        };
        v.push((&self.q, n, ("q", qb), "q"));
        v.push((&self.qd, n, ("v", vb), "qd"));
        v.push((&self.qdd, n, ("a", vb), "qdd"));
        if self.has_torques() {
            v.push((&self.tau, n, ("tau", 0), "tau"));
        }
        v
    }

    /// Whether sample `k` of every series exists, for the
    /// per-sample readers that run without [`check`](Self::check).
    pub fn sample_fits(&self, k: usize) -> Result<(), DynamicsError> {
        let need = |what: &str, len: usize, w: usize| {
            if len < (k + 1) * w {
                return Err(DynamicsError::Dimension {
                    what: format!("log, sample {k}: {what}"),
                    expected: (k + 1) * w,
                    found: len,
                });
            }
            Ok(())
        };
        need("t", self.t.len(), 1)?;
        let base = self.base.as_ref();
        let series = [
            base.map(|b| ("base pose", &b.pose)),
            base.map(|b| ("base twist", &b.twist)),
            base.map(|b| ("base acceleration", &b.accel)),
            Some(("q", &self.q)),
            Some(("qd", &self.qd)),
            Some(("qdd", &self.qdd)),
            (!self.tau.is_empty()).then_some(("tau", &self.tau)),
        ];
        for (name, x) in series.into_iter().flatten() {
            need(name, x.len(), 1)?;
        }
        for c in &self.contacts {
            need(&format!("wrench of '{}'", c.frame), c.wrench.len(), 6)?;
        }
        Ok(())
    }

    /// Sample `k`'s contact wrenches, for [`Model::contact_force`].
    pub fn contacts_at(
        &self,
        model: &Model,
        k: usize,
    ) -> Result<Vec<ContactWrench>, DynamicsError> {
        self.sample_fits(k)?;
        self.contacts
            .iter()
            .map(|c| {
                Ok(ContactWrench {
                    frame: model.frame_index(&c.frame)?,
                    wrench: std::array::from_fn(|i| c.wrench[6 * k + i]),
                    expressed: c.expressed,
                })
            })
            .collect()
    }
}

/// The base pose's column suffixes (`base_x` …).
pub(super) const BASE_Q: [&str; 7] = ["x", "y", "z", "qx", "qy", "qz", "qw"];
/// The base twist's column suffixes (`base_vx` …; its derivative's `base_dvx` …).
pub(super) const BASE_V: [&str; 6] = ["vx", "vy", "vz", "wx", "wy", "wz"];
/// A contact column's axes.
pub(super) const AXES: [&str; 3] = ["x", "y", "z"];

/// A contact column's prefix for the axes it is expressed in.
pub(super) fn prefix_of(expressed: WrenchFrame) -> &'static str {
    match expressed {
        WrenchFrame::Local => "",
        WrenchFrame::WorldAligned => "world_",
    }
}

/// The base's columns: pose, twist, the twist's derivative.
pub(super) fn base_columns() -> impl Iterator<Item = String> {
    let pose = BASE_Q.iter().map(|c| format!("base_{c}"));
    let twist = BASE_V.iter().map(|c| format!("base_{c}"));
    pose.chain(twist)
        .chain(BASE_V.iter().map(|c| format!("base_d{c}")))
}

/// A contact's columns: force, then moment, each x, y, z.
pub(super) fn contact_columns(c: &ContactChannel) -> Vec<String> {
    let w = prefix_of(c.expressed);
    let kinds = ["force", "moment"].into_iter();
    kinds
        .flat_map(|kind| {
            AXES.iter()
                .map(move |a| format!("{w}{kind}_{}_{a}", c.frame))
        })
        .collect()
}

/// Lays logs end to end as [`Dataset::append_segment`] does: a log whose
/// times do not start after the previous one's last is shifted to start
/// one of its own steps after it.
pub fn lay_end_to_end(logs: &mut [Dataset]) {
    for i in 1..logs.len() {
        let (before, rest) = logs.split_at_mut(i);
        if let Some(&last) = before[i - 1].t.last() {
            super::dataset::follow(last, &mut rest[0].t);
        }
    }
}

/// The CSV column of entry `e` of a series (its prefix as
/// [`Dataset::series`] names it).
fn column_name(prefix: &str, e: usize, joints: &[String]) -> String {
    let base: Vec<String> = base_columns().collect();
    match prefix {
        "base_pose" => base[e].clone(),
        "base_twist" => base[7 + e].clone(),
        "base_accel" => base[13 + e].clone(),
        _ => format!("{prefix}_{}", joints.get(e).map_or("?", String::as_str)),
    }
}

/// Checks one array of `samples × width` values; `name` names it, and
/// `is_time` picks its limit ([`limit`]).
fn check_array(
    (name, is_time): (&str, bool),
    x: &[f64],
    samples: usize,
    width: usize,
) -> Result<(), DataError> {
    if x.len() != samples * width {
        return Err(DataError::Log {
            message: format!(
                "{name}: {} values, expected {samples} samples × {width}",
                x.len()
            ),
        });
    }
    for (i, &v) in x.iter().enumerate() {
        if let Some(why) = refusal(v, limit(is_time)) {
            return Err(DataError::Log {
                message: format!("{name}: sample {}, entry {}: {why}", i / width, i % width),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-joint log of `k` samples with a base and one contact, every
    /// value its sample index plus the entry / 100.
    fn log(k: usize) -> Dataset {
        let mut d = Dataset::empty(&["a", "b"]);
        d.base = Some(BaseMotion::new());
        d.contacts = vec![ContactChannel {
            frame: "foot".into(),
            expressed: WrenchFrame::Local,
            wrench: vec![],
        }];
        for s in 0..k {
            let x = |n: usize, off: usize| -> Vec<f64> {
                (0..n)
                    .map(|i| s as f64 + (off + i) as f64 / 100.0)
                    .collect()
            };
            d.push_state(s as f64, (&x(9, 0), &x(8, 10), &x(8, 20)), Some(&x(2, 30)));
            d.contacts[0].wrench.extend(x(6, 40));
        }
        d
    }

    #[test]
    fn the_state_joins_the_base_and_the_joints() {
        let d = log(3);
        let (q, v, a) = d.state(2);
        assert_eq!(q.len(), 9);
        assert_eq!((q[6], q[7]), (2.06, 2.07));
        assert_eq!((v[5], v[6]), (2.15, 2.16));
        assert_eq!(a[7], 2.27);
        assert_eq!(&d.tau[2], &[2.30, 2.31]);
        assert!(d.sample_fits(2).is_ok() && d.sample_fits(3).is_err());
    }

    #[test]
    fn keep_slice_and_append_carry_the_base_and_the_contacts() {
        let mut d = log(5);
        let s = d.slice(1..3);
        assert_eq!(s.state(0), d.state(1));
        assert_eq!(s.contacts[0].wrench, d.contacts[0].wrench[6..18].to_vec());
        d.append_segment(log(2));
        assert_eq!((d.len(), d.segments.clone()), (7, vec![0, 5]));
        assert_eq!(d.state(6).1[0], 1.10); // the second log's sample 1
        assert_eq!(d.contacts[0].wrench.len(), 42);
        d.keep(4..7);
        assert_eq!(d.base.as_ref().unwrap().pose.len(), 3);
        assert_eq!(d.state(0).0[0], 4.0);
        assert_eq!(d.contacts[0].wrench[0], 4.40);
        let mut empty = Dataset::empty(&["a", "b"]);
        empty.append_segment(log(2));
        assert!(empty.base.is_some() && empty.contacts.len() == 1);
    }

    #[test]
    fn what_one_segment_lacks_is_nan_not_lost() {
        // a segment without base or contact after one with them, and the reverse
        let mut joints_only = log(2);
        (joints_only.base, joints_only.contacts) = (None, vec![]);
        let mut d = log(3);
        d.append_segment(joints_only.clone());
        assert_eq!(d.base.as_ref().unwrap().pose.len(), 5);
        assert!(d.state(4).0[0].is_nan() && d.contacts[0].wrench[6 * 4].is_nan());
        assert_eq!(d.contacts[0].wrench.len(), 30);
        let mut d = joints_only;
        d.append_segment(log(3));
        assert!(d.state(0).0[0].is_nan() && d.state(2).0[0] == 0.0);
        assert_eq!(d.contacts[0].wrench.len(), 30);
        assert!(d.contacts[0].wrench[0].is_nan() && d.contacts[0].wrench[12] == 0.40);
    }
}
