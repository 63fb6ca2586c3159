//! Errors of the experiment design.

/// What can stop a design.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExciteError {
    /// A pool that cannot be designed over.
    #[error("experiment design pool: {problem}")]
    Pool {
        /// What is wrong.
        problem: &'static str,
    },
    /// A setting out of its range.
    #[error("experiment design setting '{setting}' = {}: {requirement}", crate::numfmt::short(*value))]
    Setting {
        /// The setting.
        setting: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        requirement: &'static str,
    },
    /// A joint with no room to move.
    #[error("joint '{joint}' has no room to move: {why}")]
    NoRoom {
        /// The joint.
        joint: String,
        /// Why.
        why: String,
    },
    /// A written sample beyond a limit (a bug: the design keeps a margin).
    #[error(
        "the designed trajectory leaves joint '{joint}''s {what} limit at t = {t} s ({value} against {limit})"
    )]
    Limit {
        /// The joint.
        joint: String,
        /// position, velocity or acceleration.
        what: &'static str,
        /// Time (s).
        t: f64,
        /// The value.
        value: f64,
        /// The limit.
        limit: f64,
    },
    /// A motion whose information is singular: some base parameter is not
    /// excited at all (a joint that cannot move, a rate too coarse).
    #[error(
        "the designed motion leaves the information of the {parameters} base parameters singular (a joint with no room to move, or settings that sample it too coarsely)"
    )]
    Singular {
        /// Base parameters.
        parameters: usize,
    },
    /// A pool design too large to solve in memory.
    #[error(
        "the convex pool design over {parameters} base parameters and {candidates} candidates would need about {gib:.1} GiB (a dense PSD block in the solver, and each candidate's information matrix): use fewer candidates, the E criterion (a block half the size), or no pool"
    )]
    TooLarge {
        /// Base parameters.
        parameters: usize,
        /// Candidate motions.
        candidates: usize,
        /// The memory it would need (GiB).
        gib: f64,
    },
    /// The design's conic problem did not solve.
    #[error("the design's conic problem ended with status {}", .0.as_str())]
    Solver(crate::conic::Status),
    /// Two effects that cannot be separated as asked.
    #[error("separating two effects: {why}")]
    Separate {
        /// What is wrong (naming the effect).
        why: String,
    },
    /// From `effects` (an unknown effect's name, a hypothesis that cannot
    /// be built).
    #[error(transparent)]
    Effect(#[from] crate::effects::EffectError),
    /// From `conic`.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
    /// From `dynamics`.
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
    /// From `identify`.
    #[error(transparent)]
    Identify(#[from] crate::identify::IdentifyError),
}
