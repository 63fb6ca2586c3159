//! The limits a designed trajectory keeps: each joint's position range
//! (the model's, less a margin), its velocity limit (the URDF's
//! `<limit velocity>`, where given) and, where none is given, the peaks of
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
    /// Where the velocity limit comes from: `urdf` or `default excitation`.
    pub velocity_from: &'static str,
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

/// The URDF's velocity and effort limits by joint name (none for a
/// built-in robot or a joint without one; 0 or absent: not given).
fn urdf_limits(robot: &RobotDescription) -> Vec<(String, Option<f64>, Option<f64>)> {
    let path = std::path::Path::new(&robot.source);
    let Ok((_, urdf)) = crate::urdf::read_file(path) else {
        return vec![];
    };
    let given = |v: f64| (v > 0.0 && v.is_finite()).then_some(v);
    (urdf.joints.iter())
        .filter_map(|j| {
            j.limit
                .map(|l| (j.name.clone(), given(l.velocity), given(l.effort)))
        })
        .collect()
}

/// Every joint's limits for `robot`.
pub fn joint_limits(robot: &RobotDescription) -> Vec<JointLimits> {
    let peaks = default_peaks(robot, 20.0);
    let urdf = urdf_limits(robot);
    (robot.model.joints.iter().zip(peaks))
        .map(|(j, p)| {
            let (lo, hi) = j.limits;
            let position = if lo.is_finite() && hi.is_finite() {
                let m = POSITION_MARGIN * (hi - lo);
                (lo + m, hi - m)
            } else {
                (p[0], p[1])
            };
            let own = urdf.iter().find(|(n, ..)| *n == j.name);
            let from_urdf = own.and_then(|u| u.1);
            JointLimits {
                joint: j.name.clone(),
                position,
                velocity: from_urdf.unwrap_or(p[2]),
                acceleration: p[3],
                velocity_from: if from_urdf.is_some() {
                    "urdf"
                } else {
                    "default excitation"
                },
                effort: own.and_then(|u| u.2),
            }
        })
        .collect()
}
