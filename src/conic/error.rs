//! Errors of the conic layer.

/// What can go wrong while building, compiling or solving a conic problem.
/// A solver that ends without a solution is a [`Status`](super::status::Status), not
/// an error.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum ConicError {
    /// Two operands or an operand and a constraint do not fit.
    #[error("dimension mismatch in {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// The operation or constraint.
        what: String,
        /// The size it needed.
        expected: String,
        /// The size it got.
        found: String,
    },
    /// An index outside a matrix or vector.
    #[error("{what} is out of range for shape {shape}")]
    IndexOutOfRange {
        /// The index.
        what: String,
        /// The shape indexed.
        shape: String,
    },
    /// A NaN or infinite coefficient.
    #[error("non-finite coefficient in {what}")]
    NonFinite {
        /// Where it was found.
        what: String,
    },
    /// A PSD constraint on a matrix expression that is not symmetric.
    #[error(
        "matrix in {constraint} is not symmetric: entry ({row}, {col}) differs from ({col}, {row})"
    )]
    NotSymmetric {
        /// The constraint.
        constraint: String,
        /// Row of the first offending entry.
        row: usize,
        /// Column of the first offending entry.
        col: usize,
    },
    /// A variable, expression or constraint handle of another problem (or
    /// an expression that mixes two problems' variables).
    #[error("{what} belongs to another problem")]
    ForeignHandle {
        /// What was used.
        what: String,
    },
    /// A handle of the solved problem created after the solve.
    #[error("{what} was added to the problem after this solve; solve again to read it")]
    Stale {
        /// What was used.
        what: String,
    },
    /// A solution without values: its status is not solved.
    #[error("the solver ended with status {status}: there is no {what} to read")]
    NotSolved {
        /// The status.
        status: super::status::Status,
        /// What was asked for (values, duals).
        what: &'static str,
    },
    /// A decomposed result failed its check against the original problem
    /// and [`Settings::forbid_decomposition_fallback`](super::Settings::forbid_decomposition_fallback)
    /// forbade solving it again without decomposition.
    #[error(
        "the chordally decomposed solve's result failed its check against the original problem \
         ({reason}); solving again without decomposition was not allowed: {why}"
    )]
    DecompositionRejected {
        /// What the check found.
        reason: String,
        /// Why no fall-back was allowed, as the caller said.
        why: String,
    },
    /// A negative weight of a least-squares term.
    #[error("weight of square #{square} is {weight}: it must be finite and ≥ 0")]
    NegativeWeight {
        /// The square's index.
        square: usize,
        /// The weight.
        weight: f64,
    },
    /// A dual asked for as the wrong kind (a matrix of a scalar constraint, …).
    #[error("{constraint}: its dual is {found}, not {asked}")]
    DualKind {
        /// The constraint's name.
        constraint: String,
        /// What was asked for.
        asked: &'static str,
        /// What it is.
        found: String,
    },
    /// A problem with no variables.
    #[error("the problem is empty: it has no variables")]
    EmptyProblem,
    /// An invalid setting.
    #[error("invalid setting {name}: {reason}")]
    InvalidSetting {
        /// The setting.
        name: &'static str,
        /// Why it is invalid.
        reason: String,
    },
    /// A problem shape the solver cannot take (e.g. Clarabel rejected the data).
    #[error("solver rejected the problem: {0}")]
    Solver(String),
    /// A feature a conversion does not support (e.g. writing a second-order
    /// cone to SDPA).
    #[error("unsupported: {0}")]
    Unsupported(String),
}
