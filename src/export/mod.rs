//! # `export`: an identified model back into the simulators' formats
//!
//! - [`urdf_with_params`]: the robot's own URDF text with each body's
//!   `<inertial>` replaced by the identified one and each joint's
//!   `<dynamics damping friction>` by the identified viscous and Coulomb
//!   friction, every other byte kept; [`sidecar_with_params`]: the sidecar
//!   beside it (rotors' parameters, joints' friction, the CAD prior kept as
//!   the prior), which the URDF reader takes back;
//! - [`MujocoView`]: the model as MuJoCo holds it (a rotor's spin as joint
//!   `armature`, its mass on the parent body), and what that drops;
//! - [`mjcf`]: a MuJoCo model (MJCF) of it.
//!
//! Frames: a body's parameters are in its body frame, which is its URDF
//! link's frame (`docs/export.md`).

mod checks;
mod error;
mod generate;
pub mod mjcf;
mod mujoco;
mod sidecar;
mod urdf;

pub use error::ExportError;
pub use generate::urdf_of_model;
pub use mujoco::{Dropped, MujocoView};
pub use sidecar::sidecar_with_params;
pub use urdf::{UrdfSource, urdf_with_params};
