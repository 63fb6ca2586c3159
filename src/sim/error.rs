//! Errors of the simulator.

use crate::data::DataError;
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
    /// A standing robot's contacts cannot follow the motion: a foot out of
    /// reach, a singular posture, or forces outside the friction cones.
    #[error("standing on force plates, at t = {time} s: {problem}")]
    Stance {
        /// The sample's time (s).
        time: f64,
        /// What failed, naming the foot.
        problem: String,
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
    /// An effect name a floating-base simulation does not know.
    #[error("floating-base effect '{name}': not one of {known}")]
    UnknownEffect {
        /// The name given.
        name: String,
        /// The known names.
        known: String,
    },
    /// A duration that gives too few or too many samples at the rate.
    #[error(
        "simulation setting 'seconds' = {}: {} samples at this rate; a data set needs at least 2 and at most {most}",
        crate::numfmt::short(*seconds),
        crate::numfmt::sig4(*samples)
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
    /// A trajectory file that cannot be read (the reader's error names the
    /// file, row and column).
    #[error(transparent)]
    Data(#[from] DataError),
    /// A trajectory file (or data set) that cannot drive the simulation.
    #[error("trajectory file {path}: {problem}")]
    TrajectoryFile {
        /// The file.
        path: String,
        /// What is wrong with it.
        problem: TrajectoryProblem,
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

/// What is wrong with a trajectory file ([`super::sampled::SampledTrajectory`]).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum TrajectoryProblem {
    /// No `qdd_<joint>` columns (q̈ is needed for every joint).
    NoAccelerations,
    /// Fewer than two samples.
    TooFewSamples {
        /// The samples found.
        samples: usize,
    },
    /// A column for a joint the robot does not have.
    UnknownJoint {
        /// The column.
        column: String,
        /// The robot's joints.
        joints: Vec<String>,
    },
    /// A joint of the robot without samples.
    MissingJoint {
        /// The joint.
        joint: String,
    },
    /// Time stamps not uniform (or not increasing).
    NotUniform {
        /// 1-based data row (the header is row 0).
        row: usize,
        /// Its time (s).
        t: f64,
        /// The time a uniform grid puts there (s).
        expected: f64,
        /// The grid's step (s).
        step: f64,
    },
    /// Not periodic, and shorter than the simulation needs.
    TooShort {
        /// The file's first time (s).
        first_s: f64,
        /// Its last time (s).
        last_s: f64,
        /// The time needed before the data's start (s): the dropped edge,
        /// and any delay or compliance pre-roll.
        before_s: f64,
        /// The time needed from the data's start (s): the data and the
        /// dropped edge after them.
        after_s: f64,
    },
}

impl std::fmt::Display for TrajectoryProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // seconds to the microsecond
        let short = |x: f64| crate::numfmt::short((x * 1e6).round() / 1e6);
        match self {
            Self::NoAccelerations => {
                f.write_str("no qdd_<joint> columns: a trajectory gives q, q̇ and q̈ of every joint")
            }
            Self::TooFewSamples { samples } => {
                write!(f, "{samples} sample(s); a trajectory needs at least 2")
            }
            Self::UnknownJoint { column, joints } => write!(
                f,
                "column '{column}' is for a joint the robot does not have (its joints: {})",
                joints.join(", ")
            ),
            Self::MissingJoint { joint } => write!(f, "no samples of joint '{joint}'"),
            Self::NotUniform {
                row,
                t,
                expected,
                step,
            } => write!(
                f,
                "row {row}, column 't': time {t} s is not on the uniform grid of step {} s \
                 (expected {} s, to 1 % of a step): a trajectory is sampled at one rate",
                short(*step),
                short(*expected)
            ),
            Self::TooShort {
                first_s,
                last_s,
                before_s,
                after_s,
            } => write!(
                f,
                "not periodic (its last sample does not continue into its first), and it spans \
                 t = {} … {} s ({} s); the simulation needs {} s of it ({} s before the data's \
                 start: the dropped edge, and any delay or compliance pre-roll; {} s from it: \
                 the data and the edge after them)",
                short(*first_s),
                short(*last_s),
                short(last_s - first_s),
                short(before_s + after_s),
                short(*before_s),
                short(*after_s)
            ),
        }
    }
}
