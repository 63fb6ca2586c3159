//! Errors of the moments layer.

/// What can go wrong in the moments layer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MomentsError {
    /// An ellipsoid that is empty, degenerate or not finite.
    #[error("invalid ellipsoid: {0}")]
    InvalidEllipsoid(String),
    /// Parameters that do not allow the requested construction.
    #[error("{0}")]
    NotConsistent(String),
    /// Non-finite parameters.
    #[error("non-finite inertial parameters in {0}")]
    NonFinite(String),
    /// The conic layer failed.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
    /// The solver ended without a usable answer.
    #[error("solver ended with status {status} while {task}")]
    Solver {
        /// The status.
        status: crate::conic::Status,
        /// What it was solving.
        task: String,
    },
}
