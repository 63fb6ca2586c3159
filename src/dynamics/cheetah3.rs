//! The built-in `cheetah3-leg`: one MIT Cheetah 3 leg on a fixed base,
//! 3 links + 3 geared rotors (gear ratio 10.6), from public data
//! (Cheetah-Software's identified parameters, the public MATLAB example's box
//! prior, and enlarged bounding ellipsoids; see `docs/robots.md`).
//!
//! The kinematics, the identified inertias, the foot's inverse kinematics
//! and the shell excitation are here; everything else known about the leg
//! (prior, bounding ellipsoids, friction, tool point, excitation) is its
//! sidecar [`SIDECAR`], read by the same function as a URDF robot's
//! ([`RobotDescription::new`]). This is the only file that knows the leg.

use super::description::RobotDescription;
use super::error::DynamicsError;
use super::model::{Joint, JointKind, Model, Rotor};
use super::spatial::Transform;
use crate::moments::{Ellipsoid, InertialParams};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// The built-in name.
pub const NAME: &str = "cheetah3-leg";

/// The leg's sidecar (TOML): prior, bounding ellipsoids, friction, tool
/// point and excitation.
pub const SIDECAR: &str = include_str!("cheetah3-leg.toml");

/// Gear ratio of all three actuators (the paper's 10.6:1).
pub const GEAR_RATIO: f64 = 10.6;

/// Joint names.
pub const JOINTS: [&str; 3] = ["abad", "hip", "knee"];

/// Body names in parameter order.
pub const BODIES: [&str; 6] = [
    "abad",
    "hip",
    "knee",
    "abad_rotor",
    "hip_rotor",
    "knee_rotor",
];

/// Identified ("true") parameters, Cheetah-Software order
/// `[m, hx, hy, hz, Ixx, Iyy, Izz, Iyz, Ixz, Ixy]`, bodies as [`BODIES`].
const TRUE_SPATIAL_V2: [[f64; 10]; 6] = [
    [
        1.645278752937798,
        3.987e-24,
        1.050694793045323e-01,
        -7.248117018543008e-03,
        6.871761154771191e-03,
        2.715028710162546e-04,
        6.820782113449669e-03,
        4.545198314447007e-04,
        1.0e-25,
        -2.2e-25,
    ],
    [
        1.071200401412615,
        -7.564034441661159e-04,
        -3.180527291037499e-02,
        -1.047496808654130e-01,
        2.020976253260794e-02,
        1.856851411013688e-02,
        3.115448656660994e-03,
        1.294666102054298e-04,
        1.217274116646696e-03,
        -4.116533457993085e-04,
    ],
    [
        9.019384095786234e-01,
        2.215928611851693e-02,
        3.623331361414656e-03,
        -4.411934868569409e-02,
        2.269554734974269e-02,
        2.714252268535285e-02,
        5.566745484613744e-03,
        -3.238036214456428e-04,
        -2.194717054345885e-03,
        1.274627163554897e-03,
    ],
    [
        4.999939189070923e-01,
        1.18e-24,
        1.976769699734076e-03,
        -3.681440077402916e-04,
        9.908339941420835e-04,
        4.955917167197880e-04,
        4.956200895280653e-04,
        3.533262919985919e-08,
        5.8e-27,
        1.3e-27,
    ],
    [
        5.405045213157799e-01,
        -3.164547557293410e-03,
        -6.776800604201722e-03,
        7.158586831736347e-04,
        4.352341568156850e-04,
        1.015373256571613e-03,
        9.126776037286181e-04,
        -3.097121515937353e-05,
        -2.154046949222089e-04,
        1.306997274233568e-04,
    ],
    [
        5.398676189202086e-01,
        -2.571556872957194e-04,
        -7.550002224983261e-03,
        1.125959428120149e-03,
        7.035267590972641e-04,
        8.693209041255046e-04,
        4.122075637011218e-04,
        -3.986925582339967e-05,
        -2.295396403157565e-04,
        2.324567952553503e-05,
    ],
];

/// The identified ("true") parameters, paper order, bodies as [`BODIES`].
pub fn true_params() -> [InertialParams; 6] {
    TRUE_SPATIAL_V2.map(InertialParams::from_spatial_v2)
}

/// The leg's description: its kinematics with its sidecar [`SIDECAR`],
/// loaded like any robot ([`super::robots::load_robot`]) once per process.
pub fn description() -> RobotDescription {
    static LEG: std::sync::OnceLock<RobotDescription> = std::sync::OnceLock::new();
    LEG.get_or_init(|| {
        super::robots::load_robot(NAME, None).expect("the built-in leg and its sidecar are valid")
    })
    .clone()
}

/// The box "CAD prior" of the sidecar, bodies as [`BODIES`].
pub fn cad_params() -> [InertialParams; 6] {
    let p = description().prior;
    std::array::from_fn(|k| p[k])
}

/// The sidecar's bounding ellipsoids in each body's frame, bodies as
/// [`BODIES`]. Every identified body is density realizable in its ellipsoid.
pub fn ellipsoids() -> [Ellipsoid; 6] {
    let b = description().bounding;
    std::array::from_fn(|k| b[k][0])
}

/// Identified Coulomb friction (N·m), ab/ad, hip, knee (the paper's B_c, as
/// the sidecar states it).
pub const COULOMB: [f64; 3] = [3.12, 1.25, 0.95];

/// Viscous friction used for the simulated robot (N·m·s/rad), as the sidecar
/// states it; the paper does not give one, Cheetah-Software's actuator
/// model uses 0.1.
pub const VISCOUS: [f64; 3] = [0.1, 0.1, 0.1];

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

/// The leg's kinematics with the given link and rotor parameters (bodies as
/// [`BODIES`]), before its sidecar (tool point) is applied.
fn kinematics_with(params: &[InertialParams; 6]) -> Result<Model, DynamicsError> {
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

/// The leg's kinematics with its identified parameters (the registry's
/// entry; [`model`] adds the sidecar).
pub(crate) fn kinematics() -> Model {
    kinematics_with(&true_params()).expect("the built-in model is valid")
}

/// Whether `model` has the leg's kinematics (joint axes and placements), so
/// that the leg's inverse kinematics and shell excitation apply to it.
pub fn has_leg_kinematics(model: &Model) -> bool {
    let leg = kinematics();
    model.dof() == leg.dof()
        && model.joints.iter().zip(&leg.joints).all(|(a, b)| {
            a.parent == b.parent
                && a.kind == b.kind
                && (a.axis - b.axis).norm() < 1e-9
                && (a.x_tree.r - b.x_tree.r).norm() < 1e-9
                && (a.x_tree.e - b.x_tree.e).norm() < 1e-9
        })
}

/// The leg with the given link and rotor parameters (bodies as [`BODIES`]).
pub fn model_with(params: &[InertialParams; 6]) -> Result<Model, DynamicsError> {
    let mut m = model();
    m.set_params(&params.iter().flat_map(|p| p.0).collect::<Vec<_>>())?;
    Ok(m)
}

/// The leg with its identified ("true") parameters (the description's model).
pub fn model() -> Model {
    description().model
}

/// Foot position in the base frame for joint angles q (forward kinematics).
pub fn foot_position(q: [f64; 3]) -> Vector3<f64> {
    let m = model();
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
