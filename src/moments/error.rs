//! Errors of the moments layer.

/// What can go wrong in the moments layer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MomentsError {
    /// An ellipsoid that is empty, degenerate or not finite.
    #[error("invalid ellipsoid: {0}")]
    InvalidEllipsoid(String),
    /// The pseudo-inertia is not positive semidefinite (not a physical body).
    #[error("the pseudo-inertia is not positive semidefinite (smallest eigenvalue {min_eig:.3e})")]
    NotPositiveSemidefinite {
        /// Its smallest eigenvalue.
        min_eig: f64,
    },
    /// A body without mass has no point-mass decomposition.
    #[error("zero mass: no point masses reproduce it")]
    ZeroMass,
    /// A rank-deficient pseudo-inertia whose decomposition would put a point
    /// at infinity.
    #[error("a point of the decomposition would lie at infinity")]
    PointAtInfinity,
    /// Not density realizable in the ellipsoid (Theorem 4): `tr(J Q) < 0`.
    #[error("not realizable in the ellipsoid: tr(J Q) = {trace_jq:.3e} < 0")]
    OutsideEllipsoid {
        /// `tr(J Q)`.
        trace_jq: f64,
    },
    /// Not density realizable in the union of ellipsoids (Corollary 2).
    #[error("not density realizable in the union of {parts} ellipsoids")]
    OutsideUnion {
        /// The number of ellipsoids.
        parts: usize,
    },
    /// An option out of range.
    #[error("invalid option {option} = {}", crate::numfmt::short(*value))]
    InvalidOption {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f64,
    },
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
