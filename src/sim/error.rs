//! Errors of the simulator.

use crate::dynamics::DynamicsError;

/// What can stop a simulation; nothing is written when one happens.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The model or an effect is invalid.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    /// Torques asked at a number of times other than of states.
    #[error("torques asked at {times} times for {samples} states")]
    Times {
        /// Times given.
        times: usize,
        /// States given.
        samples: usize,
    },
    /// A setting out of range.
    #[error("simulation setting '{setting}' = {}: {requirement}", crate::numfmt::short(*value))]
    Setting {
        /// The setting (`seconds`, `rate_hz`, …).
        setting: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        requirement: &'static str,
    },
    /// A duration that gives too few or too many samples at the rate.
    #[error(
        "simulation setting 'seconds' = {}: {samples} samples at this rate; a data set needs at least 2 and at most {most}",
        crate::numfmt::short(*seconds)
    )]
    Samples {
        /// The duration (s).
        seconds: f64,
        /// The samples it gives.
        samples: f64,
        /// The most a simulation makes.
        most: usize,
    },
    /// A simulation beyond the memory it may plan for.
    #[error(
        "{joints} joints × {samples} samples need about {needed_gib:.1} GiB, beyond {limit_gib} GiB (fewer joints, lock some in the sidecar, or a shorter run)"
    )]
    TooLarge {
        /// Joints.
        joints: usize,
        /// Samples (with the dropped edges).
        samples: usize,
        /// The estimate (GiB).
        needed_gib: f64,
        /// The limit (GiB).
        limit_gib: f64,
    },
    /// The excitation cannot be evaluated (the leg's foot target out of reach).
    #[error("the excitation leaves the workspace at t = {t} s")]
    Workspace {
        /// Time (s).
        t: f64,
    },
    /// A simulated value beyond what the data readers accept.
    #[error(
        "the simulated {what} at t = {t} s is {value:e}, beyond ±1e8: the description (gravity, poses, effects) is out of scale"
    )]
    OutOfRange {
        /// The column.
        what: String,
        /// Time (s).
        t: f64,
        /// The value.
        value: f64,
    },
    /// The excitation gives a non-finite state.
    #[error("the excitation gives a non-finite state at t = {t} s")]
    NonFinite {
        /// Time (s).
        t: f64,
    },
    /// The excitation does not fit the model.
    #[error("the excitation moves {found} joints, the model has {expected}")]
    Excitation {
        /// The model's joints.
        expected: usize,
        /// The excitation's joints.
        found: usize,
    },
    /// A joint leaves its limits.
    #[error("joint '{joint}' leaves its limits at t = {t} s (q = {q})")]
    Limits {
        /// The joint.
        joint: String,
        /// Time (s).
        t: f64,
        /// Its position (rad or m).
        q: f64,
    },
    /// A `NAME=VALUE` effect-parameter override that cannot be read.
    #[error("effect parameter override '{text}': {problem}")]
    Override {
        /// The text given.
        text: String,
        /// What is wrong with it.
        problem: OverrideProblem,
    },
    /// An effect named a body the model does not have.
    #[error("body {body} does not exist (the model has {bodies} links)")]
    Body {
        /// The body (a link's joint index).
        body: usize,
        /// The model's links.
        bodies: usize,
    },
    /// The true robot was built with other effects than the configuration
    /// records.
    #[error(
        "the true robot was built with effects [{}], the simulation's configuration records [{}] (or other magnitudes)",
        truth.join(", "),
        config.join(", ")
    )]
    EffectsRecord {
        /// The true robot's effects.
        truth: Vec<String>,
        /// The configuration's.
        config: Vec<String>,
    },
    /// The compliant link-side simulation diverged.
    #[error("the compliant link simulation diverged at t = {t} s")]
    Diverged {
        /// Time (s).
        t: f64,
    },
}

/// What is wrong with a `NAME=VALUE` override.
#[derive(Clone, Debug, PartialEq)]
pub enum OverrideProblem {
    /// No `=`.
    NoEquals,
    /// Nothing before the `=`.
    NoName,
    /// The value is not a number.
    NotANumber(String),
}

impl std::fmt::Display for OverrideProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OverrideProblem::NoEquals => f.write_str("expected NAME=VALUE"),
            OverrideProblem::NoName => f.write_str("no parameter name before '='"),
            OverrideProblem::NotANumber(v) => write!(f, "'{v}' is not a number"),
        }
    }
}
