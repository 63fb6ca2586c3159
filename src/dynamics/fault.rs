//! [`ModelFault`]: what makes a kinematic tree invalid, with the values a
//! caller can act on (the joint, the limits, the frame, …).

use std::fmt;

/// The largest finite joint limit (rad or m): a larger one is a typo or an
/// "unlimited" that should be written as no limit.
pub const MAX_ABS_LIMIT: f64 = 1e4;

/// What is wrong with a model.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ModelFault {
    /// No movable joint.
    NoJoint,
    /// Gravity not finite or beyond ±1000 m/s².
    Gravity([f64; 3]),
    /// A Stribeck velocity (rad/s) that is not positive and ≤ 1e6.
    StribeckVelocity(f64),
    /// A movable joint without a name.
    UnnamedJoint,
    /// A joint name with a character a CSV column cannot hold.
    JointName {
        /// The name.
        joint: String,
        /// The character.
        bad: char,
    },
    /// Joint limits that are not increasing.
    LimitsOrder {
        /// The joint.
        joint: String,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A finite joint limit beyond ±1e4 (rad or m).
    LimitsRange {
        /// The joint.
        joint: String,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A joint listed before its parent.
    ParentOrder {
        /// The joint.
        joint: String,
        /// Its parent's index.
        parent: usize,
    },
    /// A joint axis that is not a unit vector.
    Axis {
        /// The joint.
        joint: String,
        /// The axis.
        axis: [f64; 3],
    },
    /// A joint with non-finite inertia or placement.
    JointNumbers {
        /// The joint.
        joint: String,
    },
    /// Two joints of one name.
    DuplicateJoint(String),
    /// A rotor driving a joint the model does not have.
    RotorJoint {
        /// The rotor.
        rotor: String,
        /// The joint index.
        joint: usize,
        /// The model's joints.
        joints: usize,
    },
    /// A joint with two rotors.
    TwoRotors(String),
    /// A rotor whose axis is not unit or whose numbers are not finite.
    RotorNumbers(String),
    /// Two bodies of one name.
    DuplicateBody(String),
    /// A body's inertial parameter that is not finite.
    BodyParameter {
        /// The body.
        body: String,
        /// The value.
        value: f64,
    },
    /// A named frame on a body the model does not have.
    FrameBody(String),
    /// A named frame with a non-finite placement.
    FramePlacement(String),
    /// Two frames of one name.
    DuplicateFrame(String),
    /// A tool frame the model does not have.
    ToolFrame {
        /// The frame asked for.
        frame: String,
        /// The model's frames.
        frames: Vec<String>,
    },
    /// A tool frame on the fixed base.
    ToolOnBase(String),
    /// A non-finite tool point.
    ToolPoint,
}

impl fmt::Display for ModelFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ModelFault::*;
        match self {
            NoJoint => f.write_str("no movable joint: nothing to simulate, identify or diagnose"),
            Gravity(g) => write!(f, "gravity {g:?} must be finite and within ±1000 m/s²"),
            StribeckVelocity(v) => {
                write!(
                    f,
                    "the Stribeck velocity {} rad/s must be positive and ≤ 1e6",
                    crate::numfmt::short(*v)
                )
            }
            UnnamedJoint => f.write_str("a movable joint without a name"),
            JointName { joint, bad } => write!(
                f,
                "joint '{}': its name becomes a CSV column and cannot hold {bad:?}",
                joint.escape_debug()
            ),
            LimitsOrder {
                joint,
                lower,
                upper,
            } => write!(
                f,
                "joint '{joint}': limits [{lower}, {upper}] must be increasing"
            ),
            LimitsRange {
                joint,
                lower,
                upper,
            } => write!(
                f,
                "joint '{joint}': limits [{lower:e}, {upper:e}] beyond ±{:e} (leave an unlimited joint without limits)",
                MAX_ABS_LIMIT
            ),
            ParentOrder { joint, parent } => {
                write!(
                    f,
                    "joint '{joint}' comes before its parent (index {parent})"
                )
            }
            Axis { joint, axis } => {
                write!(f, "joint '{joint}': axis {axis:?} is not a unit vector")
            }
            JointNumbers { joint } => write!(f, "joint '{joint}': non-finite numbers"),
            DuplicateJoint(j) => write!(f, "duplicate joint name '{j}'"),
            RotorJoint {
                rotor,
                joint,
                joints,
            } => write!(f, "rotor '{rotor}' drives joint {joint} of {joints}"),
            TwoRotors(j) => write!(f, "joint '{j}' has two rotors"),
            RotorNumbers(r) => write!(f, "rotor '{r}': axis not unit or non-finite numbers"),
            DuplicateBody(b) => write!(
                f,
                "two bodies are named '{b}' (a rotor named like a link?): parameter files name bodies"
            ),
            BodyParameter { body, value } => {
                write!(f, "body '{body}': non-finite parameter {value}")
            }
            FrameBody(fr) => write!(
                f,
                "frame '{fr}': attached to a body the model does not have"
            ),
            FramePlacement(fr) => write!(f, "frame '{fr}': non-finite placement"),
            DuplicateFrame(fr) => write!(f, "frame '{fr}': defined twice"),
            ToolFrame { frame, frames } => write!(
                f,
                "tool frame '{frame}' is not a frame of the model (frames: {})",
                frames.join(", ")
            ),
            ToolOnBase(fr) => write!(
                f,
                "tool frame '{fr}' is on the fixed base; a payload there does not move"
            ),
            ToolPoint => f.write_str("non-finite tool point"),
        }
    }
}
