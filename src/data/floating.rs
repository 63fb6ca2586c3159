//! A floating-base log: the base's pose and motion (motion capture or an
//! estimator and an IMU), the joints' encoders and torques, and the
//! wrenches measured at contact frames (force plates, a harness load cell,
//! foot sensors). Conventions: [`Model`]'s (`q` 7 + n with the
//! quaternion `x, y, z, w`; `v`, `a` 6 + n, base part linear then angular
//! in base coordinates).

use super::error::DataError;
use super::raw::{limit, not_after, refusal};
use crate::dynamics::{ContactWrench, DynamicsError, Model, WrenchFrame};

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

/// Samples of a floating-base robot, sample-major.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatingLog {
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Configurations, `samples × (7 + n)`.
    pub q: Vec<f64>,
    /// Velocities, `samples × (6 + n)`.
    pub v: Vec<f64>,
    /// Accelerations, `samples × (6 + n)`.
    pub a: Vec<f64>,
    /// Joint torques, `samples × n` (N·m or N); `None` when not measured
    /// (only the base rows can be used).
    pub tau: Option<Vec<f64>>,
    /// The contact wrenches (every external wrench on the robot).
    pub contacts: Vec<ContactChannel>,
}

impl FloatingLog {
    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.t.len()
    }

    /// Checks the log against the robot: every array's length, every value
    /// finite and within the readers' limits (times too, and increasing), every quaternion of unit norm, every contact frame one of
    /// the robot's; the error names the array, sample or frame.
    pub fn check(&self, ff: &Model) -> Result<(), DataError> {
        ff.need_free_flyer("a floating-base log")
            .map_err(|e| DataError::Log {
                message: e.to_string(),
            })?;
        let s = self.samples();
        let n = ff.dof();
        let arrays = [
            ("q", Some(&self.q), 7 + n),
            ("v", Some(&self.v), 6 + n),
            ("a", Some(&self.a), 6 + n),
            ("tau", self.tau.as_ref(), n),
        ];
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
        for (name, x, width) in arrays {
            if let Some(x) = x {
                check_array((name, false), x, s, width)?;
            }
        }
        for c in &self.contacts {
            ff.frame_index(&c.frame).map_err(|e| DataError::Log {
                message: e.to_string(),
            })?;
            check_array(
                (&format!("wrench of '{}'", c.frame), false),
                &c.wrench,
                s,
                6,
            )?;
        }
        let (nq, nv) = (ff.nq(), ff.nv());
        for k in 0..s {
            let q = &self.q[k * nq..(k + 1) * nq];
            let v = &self.v[k * nv..(k + 1) * nv];
            ff.base_state(q, v, &self.a[k * nv..(k + 1) * nv])
                .map_err(|e| bad(k, e))?;
        }
        Ok(())
    }

    /// Whether sample `k` exists in every array (their lengths as `ff`
    /// needs them), for the per-sample readers that run without [`check`](Self::check).
    pub fn sample_fits(&self, ff: &Model, k: usize) -> Result<(), DynamicsError> {
        let n = ff.dof();
        let need = |what: &str, x: &[f64], w: usize| {
            if x.len() < (k + 1) * w {
                return Err(DynamicsError::Dimension {
                    what: format!("floating-base log, sample {k}: {what}"),
                    expected: (k + 1) * w,
                    found: x.len(),
                });
            }
            Ok(())
        };
        need("q", &self.q, ff.nq())?;
        need("v", &self.v, ff.nv())?;
        need("a", &self.a, ff.nv())?;
        if let Some(t) = &self.tau {
            need("tau", t, n)?;
        }
        for c in &self.contacts {
            need(&format!("wrench of '{}'", c.frame), &c.wrench, 6)?;
        }
        Ok(())
    }

    /// Sample `k`'s contact wrenches, for [`Model::contact_force`].
    pub fn contacts_at(&self, ff: &Model, k: usize) -> Result<Vec<ContactWrench>, DynamicsError> {
        self.sample_fits(ff, k)?;
        self.contacts
            .iter()
            .map(|c| {
                Ok(ContactWrench {
                    frame: ff.frame_index(&c.frame)?,
                    wrench: std::array::from_fn(|i| c.wrench[6 * k + i]),
                    expressed: c.expressed,
                })
            })
            .collect()
    }
}

/// Lays logs end to end as fixed-base files are
/// ([`Dataset::append_segment`](super::Dataset::append_segment)): a log
/// whose times do not start after the previous one's last is shifted to
/// start one of its own steps after it.
pub fn lay_end_to_end(logs: &mut [FloatingLog]) {
    for i in 1..logs.len() {
        let (before, rest) = logs.split_at_mut(i);
        if let Some(&last) = before[i - 1].t.last() {
            super::dataset::follow(last, &mut rest[0].t);
        }
    }
}

fn bad(sample: usize, source: DynamicsError) -> DataError {
    DataError::Sample { sample, source }
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
