//! The Cheetah 3 leg's kinematics (joint frames, axes, limits, rotor
//! placements and gear ratio), its foot's forward and inverse kinematics,
//! and the paper's excitation: the foot on an ellipsoidal shell ([`Shell`]).
//! The sidecar's `leg_shell` excitation and the built-in `cheetah3-leg`
//! ([`super::robots::cheetah3`], its parameters and sidecar) both use it.

use super::error::DynamicsError;
use super::model::{Joint, JointKind, Model, Rotor};
use super::spatial::Transform;
use crate::moments::InertialParams;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// The built-in name.
pub const NAME: &str = "cheetah3-leg";

/// Gear ratio of all three actuators (the paper's 10.6:1).
pub const GEAR_RATIO: f64 = 10.6;

/// Thigh and shank lengths (m).
pub const THIGH: f64 = 0.342;
/// Shank length (m).
pub const SHANK: f64 = 0.345;
/// Foot position in the knee frame (m).
pub const FOOT: [f64; 3] = [0.0, 0.0, -0.345];
/// Hip joint offset in the ab/ad frame (m).
pub const HIP_OFFSET: [f64; 3] = [0.0, 0.045, 0.0];

/// Joint limits chosen for the simulated leg (rad): they bound the
/// excitation, they are not hardware values.
pub const LIMITS: [(f64, f64); 3] = [(-1.6, 1.6), (-4.0, 4.0), (-2.9, 2.9)];

fn rz_pi() -> Matrix3<f64> {
    Matrix3::new(-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0)
}

/// The leg's kinematics with the given link and rotor parameters (bodies
/// abad, hip, knee, then their rotors), before its sidecar (tool point) is
/// applied.
pub fn kinematics_with(params: &[InertialParams; 6]) -> Result<Model, DynamicsError> {
    let x = Vector3::x();
    let y = Vector3::y();
    let hip_tree = Transform::from_pose(&rz_pi(), &Vector3::from(HIP_OFFSET));
    let knee_tree = Transform::from_pose(&Matrix3::identity(), &Vector3::new(0.0, 0.0, -THIGH));
    let joint = |name: &str, parent, axis, x_tree, k: usize| Joint {
        name: name.into(),
        body: name.into(),
        parent,
        kind: JointKind::Revolute,
        axis,
        x_tree,
        limits: LIMITS[k],
        inertia: params[k],
    };
    let joints = vec![
        joint("abad", None, x, Transform::identity(), 0),
        joint("hip", Some(0), y, hip_tree, 1),
        joint("knee", Some(1), y, knee_tree, 2),
    ];
    let rotor = |name: &str, j: usize, axis, x_tree| Rotor {
        name: name.into(),
        joint: j,
        x_tree,
        axis,
        gear_ratio: GEAR_RATIO,
        inertia: params[3 + j],
    };
    let rotors = vec![
        rotor("abad_rotor", 0, x, Transform::identity()),
        rotor("hip_rotor", 1, y, hip_tree),
        rotor("knee_rotor", 2, y, Transform::identity()),
    ];
    Model::new(NAME, joints, rotors, Vector3::new(0.0, 0.0, -9.81))
}

/// Whether `model` has the leg's kinematics (joint axes and placements), so
/// that the leg's inverse kinematics and shell excitation apply to it.
pub fn has_leg_kinematics(model: &Model) -> bool {
    let zero = [InertialParams([0.0; 10]); 6];
    let Ok(leg) = kinematics_with(&zero) else {
        return false;
    };
    model.dof() == leg.dof()
        && model.joints.iter().zip(&leg.joints).all(|(a, b)| {
            a.parent == b.parent
                && a.kind == b.kind
                && (a.axis - b.axis).norm() < 1e-9
                && (a.x_tree.r - b.x_tree.r).norm() < 1e-9
                && (a.x_tree.e - b.x_tree.e).norm() < 1e-9
        })
}

/// Foot position in the base frame for joint angles q (forward kinematics).
pub fn foot_position(q: [f64; 3]) -> Vector3<f64> {
    let zero = [InertialParams([0.0; 10]); 6];
    let m = kinematics_with(&zero).expect("the leg's kinematics are valid");
    let mut x = Transform::identity();
    for (i, qi) in q.iter().enumerate() {
        x = m.joint_transform(i, *qi).compose(&x);
    }
    // x maps base → knee frame; the foot point in base coordinates:
    x.inverse().apply_point(&Vector3::from(FOOT))
}

/// The ellipsoidal shell the foot follows (base frame, m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Shell {
    /// Centre (m).
    pub center: [f64; 3],
    /// Semi-axes (m).
    pub semi_axes: [f64; 3],
    /// φ̇ = a_φ sin(ω_φ t): amplitude (rad/s) and frequency (rad/s).
    pub phi_rate: (f64, f64),
    /// θ̇ = a_θ sin(ω_θ t).
    pub theta_rate: (f64, f64),
}

impl Default for Shell {
    /// Our choice (the paper gives neither centre nor radii): centred under
    /// the hip, 0.45 m below the ab/ad axis, semi-axes 0.12 × 0.10 × 0.12 m;
    /// the paper's rates φ̇ = 12 sin(1.63 t), θ̇ = 3.4 sin(0.265 t).
    fn default() -> Self {
        Self {
            center: [0.0, 0.045, -0.45],
            semi_axes: [0.12, 0.10, 0.12],
            phi_rate: (12.0, 1.63),
            theta_rate: (3.4, 0.265),
        }
    }
}

impl Shell {
    /// Spherical angles at time t: φ = (a/ω)(1 − cos ωt), θ = π/2 + (a/ω)(1 − cos ωt).
    pub fn angles(&self, t: f64) -> (f64, f64) {
        let (ap, wp) = self.phi_rate;
        let (at, wt) = self.theta_rate;
        (
            ap / wp * (1.0 - (wp * t).cos()),
            std::f64::consts::FRAC_PI_2 + at / wt * (1.0 - (wt * t).cos()),
        )
    }

    /// Foot target at time t (base frame).
    pub fn foot(&self, t: f64) -> Vector3<f64> {
        let (phi, theta) = self.angles(t);
        let [a, b, c] = self.semi_axes;
        Vector3::from(self.center)
            + Vector3::new(
                a * theta.sin() * phi.cos(),
                b * theta.sin() * phi.sin(),
                c * theta.cos(),
            )
    }
}

/// Inverse kinematics of the Cheetah 3 leg, on the branch with the foot
/// below the hip (in the ab/ad frame) and the knee bent to positive angles.
/// Returns `None` when the point is out of reach.
pub fn cheetah_ik(p: &Vector3<f64>) -> Option<[f64; 3]> {
    let d = HIP_OFFSET[1];
    let r2 = p.y * p.y + p.z * p.z - d * d;
    if r2 < 0.0 {
        return None;
    }
    let zp = -r2.sqrt(); // foot below the hip in the ab/ad frame
    let qa = p.z.atan2(p.y) - zp.atan2(d);
    let xp = p.x;
    let (l1, l2) = (THIGH, SHANK);
    let c = (xp * xp + zp * zp - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if !(-1.0..=1.0).contains(&c) {
        return None;
    }
    let qk = c.acos();
    let qh = xp.atan2(-zp) - (l2 * qk.sin()).atan2(l1 + l2 * qk.cos());
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
    };
    Some([wrap(qa), wrap(qh), qk])
}
