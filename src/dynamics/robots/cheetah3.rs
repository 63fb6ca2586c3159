//! The built-in `cheetah3-leg`: one MIT Cheetah 3 leg on a fixed base,
//! 3 links + 3 geared rotors (gear ratio 10.6), from public data
//! (Cheetah-Software's identified parameters, the public MATLAB example's box
//! prior, and enlarged bounding ellipsoids; see `docs/robots.md`).
//!
//! The identified inertias and the registry entry are here, the kinematics
//! and the shell excitation in [`crate::dynamics::leg_kinematics`]
//! (re-exported); everything else known about the leg (prior, bounding
//! ellipsoids, friction, tool point, excitation) is its sidecar [`SIDECAR`],
//! read by the same function as a URDF robot's ([`RobotDescription::new`]).

use super::entry::BuiltIn;
use crate::dynamics::description::RobotDescription;
use crate::dynamics::error::DynamicsError;
use crate::dynamics::leg_kinematics::kinematics_with;
pub use crate::dynamics::leg_kinematics::{
    FOOT, GEAR_RATIO, HIP_OFFSET, LIMITS, NAME, SHANK, Shell, THIGH, cheetah_ik, foot_position,
    has_leg_kinematics,
};
use crate::dynamics::model::Model;
use crate::dynamics::sidecar::Sidecar;
use crate::moments::{Ellipsoid, InertialParams};

/// The leg's sidecar (TOML): prior, bounding ellipsoids, friction, tool
/// point and excitation.
pub const SIDECAR: &str = include_str!("cheetah3-leg.toml");

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

/// The registry's entry.
pub const ENTRY: BuiltIn = BuiltIn {
    name: NAME,
    describe,
    sidecar: SIDECAR,
};

/// The leg's kinematics with its identified parameters, described by its
/// sidecar [`SIDECAR`] through [`RobotDescription::new`] (as a URDF robot's).
fn describe() -> Result<RobotDescription, DynamicsError> {
    let model = kinematics_with(&true_params())?;
    RobotDescription::new(NAME, model, &Sidecar::parse(SIDECAR, NAME)?, None)
}

/// The leg's description ([`ENTRY`]'s), built once per process.
pub fn description() -> RobotDescription {
    static LEG: std::sync::OnceLock<RobotDescription> = std::sync::OnceLock::new();
    LEG.get_or_init(|| describe().expect("the built-in leg and its sidecar are valid"))
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
    let b = description().bounding().to_vec();
    std::array::from_fn(|k| b[k][0])
}

/// Identified Coulomb friction (N·m), ab/ad, hip, knee (the paper's B_c, as
/// the sidecar states it).
pub const COULOMB: [f64; 3] = [3.12, 1.25, 0.95];

/// Viscous friction used for the simulated robot (N·m·s/rad), as the sidecar
/// states it; the paper does not give one, Cheetah-Software's actuator
/// model uses 0.1.
pub const VISCOUS: [f64; 3] = [0.1, 0.1, 0.1];

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
