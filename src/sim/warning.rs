//! What a simulation reports without failing.

use serde::Serialize;
use std::fmt;

/// A warning about the simulated robot.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum SimWarning {
    /// An effect is on but changes nothing: the robot's nominal friction
    /// it scales is zero on every joint.
    NominalFrictionZero {
        /// The effect.
        effect: String,
    },
    /// An effect is on but the robot has nothing it acts on.
    Inert {
        /// The effect.
        effect: String,
        /// Why (what the robot lacks).
        why: &'static str,
    },
}

impl fmt::Display for SimWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimWarning::NominalFrictionZero { effect } => write!(
                f,
                "effect '{effect}' is on but the robot's nominal friction it scales is zero on every joint"
            ),
            SimWarning::Inert { effect, why } => {
                write!(f, "effect '{effect}' is on but changes nothing: {why}")
            }
        }
    }
}
