//! The limits a designed trajectory keeps: each joint's position range
//! (the model's, less a margin), its velocity and acceleration limits (the
//! description's: the sidecar's `max_velocity`, `max_acceleration`, else
//! the URDF's `<limit velocity>`) and, where none is given, the peaks of
//! the robot's default excitation — so that a designed motion is never
//! more violent than the one the robot is simulated with by default.

use crate::dynamics::RobotDescription;
use crate::sim::trajectory::Trajectory;
use serde::Serialize;

/// The fraction of a finite position range kept free at each end.
pub const POSITION_MARGIN: f64 = 0.05;

/// One joint's limits.
#[derive(Clone, Debug, Serialize)]
pub struct JointLimits {
    /// The joint.
    pub joint: String,
    /// Lowest and highest position (rad or m).
    pub position: (f64, f64),
    /// Largest |q̇| (rad/s or m/s).
    pub velocity: f64,
    /// Largest |q̈| (rad/s² or m/s²).
    pub acceleration: f64,
    /// Where the velocity limit comes from: `description` (the sidecar's
    /// `max_velocity`, else the URDF's `<limit velocity>`) or `default
    /// excitation`.
    pub velocity_from: &'static str,
    /// Where the acceleration limit comes from: `description` (the
    /// sidecar's `max_acceleration`) or `default excitation`.
    pub acceleration_from: &'static str,
    /// The URDF's effort limit (N·m or N), where given: checked, not
    /// enforced ([`super::Designed::torque_margins`]).
    pub effort: Option<f64>,
}

/// The peaks of the default excitation per joint: (min q, max q, max |q̇|,
/// max |q̈|) over `seconds` at 200 Hz.
fn default_peaks(robot: &RobotDescription, seconds: f64) -> Vec<[f64; 4]> {
    let traj = Trajectory::for_excitation(&robot.excitation, &robot.model, 1);
    let n = robot.model.dof();
    let mut peaks = vec![[f64::INFINITY, f64::NEG_INFINITY, 0.0, 0.0]; n];
    let steps = (seconds * 200.0) as usize;
    for k in 0..steps {
        if let Some((q, qd, qdd)) = traj.state(k as f64 / 200.0) {
            for j in 0..n {
                let p = &mut peaks[j];
                p[0] = p[0].min(q[j]);
                p[1] = p[1].max(q[j]);
                p[2] = p[2].max(qd[j].abs());
                p[3] = p[3].max(qdd[j].abs());
            }
        }
    }
    peaks
}

/// Every joint's limits for `robot`.
pub fn joint_limits(robot: &RobotDescription) -> Vec<JointLimits> {
    let peaks = default_peaks(robot, 20.0);
    let source = |v: Option<f64>| {
        if v.is_some() {
            "description"
        } else {
            "default excitation"
        }
    };
    (robot.model.joints.iter().zip(peaks))
        .enumerate()
        .map(|(k, (j, p))| {
            let (lo, hi) = j.limits;
            let position = if lo.is_finite() && hi.is_finite() {
                let m = POSITION_MARGIN * (hi - lo);
                (lo + m, hi - m)
            } else {
                (p[0], p[1])
            };
            let rates = robot.rates(k);
            JointLimits {
                joint: j.name.clone(),
                position,
                velocity: rates.velocity.unwrap_or(p[2]),
                acceleration: rates.acceleration.unwrap_or(p[3]),
                velocity_from: source(rates.velocity),
                acceleration_from: source(rates.acceleration),
                effort: rates.effort,
            }
        })
        .collect()
}
