//! One log file as read, before preparation ([`super::prepare`]): time
//! stamps and the joints' values, in SI units and the robot's joint order.

use super::error::DataError;
use super::warning::ReadWarning;
use crate::dynamics::Samples;

/// The most data rows a file may have (10 million: about 3 hours at 1 kHz).
pub const MAX_ROWS: usize = 10_000_000;
/// The largest magnitude of a q, q̇, q̈ or τ value (rad, rad/s, rad/s², N·m):
/// no robot moves or pushes like that, and beyond it products in the
/// regressor lose all precision long before they overflow.
pub const MAX_ABS_VALUE: f64 = 1e8;
/// The largest magnitude of a time stamp (s): room for Unix time.
pub const MAX_ABS_TIME: f64 = 1e12;

/// A log file's samples as recorded: `t` (s), and per sample one value
/// per joint of the robot (its order) of q, and of q̇, q̈, τ where the
/// file has them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RawLog {
    /// The file (for errors and the report).
    pub path: String,
    /// Time stamps (s), as recorded (absolute or not, possibly irregular).
    pub t: Vec<f64>,
    /// Positions (rad or m).
    pub q: Samples,
    /// Velocities, if recorded.
    pub qd: Option<Samples>,
    /// Accelerations, if recorded.
    pub qdd: Option<Samples>,
    /// Torques, if recorded.
    pub tau: Option<Samples>,
    /// What reading it skipped or substituted (carried into the report).
    pub warnings: Vec<ReadWarning>,
}

impl RawLog {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Appends `other`'s samples (a later part of the same file: the same
    /// series recorded) and warnings.
    pub(crate) fn append(&mut self, mut other: RawLog) {
        self.t.append(&mut other.t);
        self.q.append(&mut other.q);
        for (mine, theirs) in [
            (&mut self.qd, &mut other.qd),
            (&mut self.qdd, &mut other.qdd),
            (&mut self.tau, &mut other.tau),
        ] {
            debug_assert!(
                self.t.is_empty() || other.t.is_empty() || mine.is_some() == theirs.is_some(),
                "parts of one file record the same series"
            );
            match (mine.as_mut(), theirs.as_mut()) {
                (Some(m), Some(t)) => m.append(t),
                (None, Some(_)) => *mine = theirs.take(),
                _ => {}
            }
        }
        self.warnings.append(&mut other.warnings);
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

/// Checks one value read from `path`'s `array` at 1-based `row`: finite
/// and within `limit`.
pub(crate) fn check_value(
    v: f64,
    limit: f64,
    path: &str,
    array: &str,
    row: usize,
) -> Result<f64, DataError> {
    let bad = |message: String| DataError::Array {
        path: path.into(),
        array: array.into(),
        message: format!("row {row}: {message}"),
    };
    match refusal(v, limit) {
        Some(why) => Err(bad(why)),
        None => Ok(v),
    }
}

/// The limit of a value read from a log: [`MAX_ABS_TIME`] for a time
/// stamp, else [`MAX_ABS_VALUE`].
pub(crate) fn limit(is_time: bool) -> f64 {
    if is_time { MAX_ABS_TIME } else { MAX_ABS_VALUE }
}

/// What every reader says of a time `t` that does not follow `before`
/// (the previous `what`: row or sample).
pub(crate) fn not_after(t: f64, before: f64, what: &str) -> String {
    format!(
        "time {} is not after the previous {what}'s {}",
        crate::numfmt::short(t),
        crate::numfmt::short(before)
    )
}

/// Why a value read from a log is refused, if it is: not finite, or
/// beyond `limit` in magnitude ([`MAX_ABS_VALUE`], [`MAX_ABS_TIME`]). One
/// rule for every reader; the number is written short (`1e300`).
pub(crate) fn refusal(v: f64, limit: f64) -> Option<String> {
    if !v.is_finite() {
        Some(format!("non-finite value {v}"))
    } else if v.abs() > limit {
        Some(format!(
            "{} is beyond ±{}",
            crate::numfmt::short(v),
            crate::numfmt::short(limit)
        ))
    } else {
        None
    }
}

/// Where each robot joint is among the `order` of a file's columns
/// (`""` entries are columns to skip): every robot joint must be there,
/// and every named column must be a robot joint.
pub(crate) fn joint_positions(
    robot: &[&str],
    order: &[&str],
    path: &str,
    array: &str,
) -> Result<Vec<usize>, DataError> {
    let bad = |message: String| DataError::Array {
        path: path.into(),
        array: array.into(),
        message,
    };
    if let Some(j) = order.iter().find(|j| !j.is_empty() && !robot.contains(j)) {
        return Err(bad(format!(
            "the mapping names joint '{j}', which the robot lacks (its joints: {}; \"\" skips a column)",
            robot.join(", ")
        )));
    }
    robot
        .iter()
        .map(|j| {
            order.iter().position(|o| o == j).ok_or_else(|| {
                bad(format!(
                    "no column for the robot's joint '{j}' in the mapping's joints"
                ))
            })
        })
        .collect()
}
