//! What a built-in robot gives the registry.

use crate::dynamics::description::RobotDescription;
use crate::dynamics::error::DynamicsError;

/// A built-in robot: its name and how it is described (its model and its
/// own sidecar, through [`RobotDescription::new`]).
#[derive(Clone, Copy, Debug)]
pub struct BuiltIn {
    /// The name `--robot` takes.
    pub name: &'static str,
    /// Its description.
    pub describe: fn() -> Result<RobotDescription, DynamicsError>,
    /// Its own sidecar's text (what [`Self::describe`] reads besides its
    /// kinematics; the base of the sidecar an export writes).
    pub sidecar: &'static str,
}
