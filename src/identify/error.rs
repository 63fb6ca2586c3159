//! Errors of the identification.

use crate::conic::Status;
use crate::dynamics::DynamicsError;

/// What can stop an identification.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// An option out of range.
    #[error("identification option '{option}': {message}")]
    Option {
        /// The option.
        option: &'static str,
        /// What is wrong.
        message: String,
    },
    /// An unknown body or joint name.
    #[error("unknown {what} '{name}' (known: {valid})")]
    UnknownName {
        /// A body or a joint.
        what: &'static str,
        /// The name given.
        name: String,
        /// The valid names.
        valid: String,
    },
    /// The training data have no samples or no torques.
    #[error(
        "the training data need torques (tau_* columns) and at least one sample ({samples} samples, {torques} with torques)"
    )]
    NoTrainingData {
        /// Samples.
        samples: usize,
        /// Samples with torques.
        torques: usize,
    },
    /// Sample vectors of different lengths (q, q̇, q̈, τ).
    #[error("{what} has {found} samples, q has {expected}")]
    SampleCount {
        /// Which vector.
        what: &'static str,
        /// q's samples.
        expected: usize,
        /// Its samples.
        found: usize,
    },
    /// A sample with the wrong number of values.
    #[error("sample {sample}: {what} has {found} values, the model has {expected} joints")]
    SampleLength {
        /// The sample (0-based).
        sample: usize,
        /// Which vector.
        what: &'static str,
        /// Joints.
        expected: usize,
        /// Values found.
        found: usize,
    },
    /// Reduced data of another model.
    #[error("reduced data have {found} columns, the model needs {expected}")]
    Columns {
        /// The model's regressor columns.
        expected: usize,
        /// The reduced data's.
        found: usize,
    },
    /// The regressor failed at a sample.
    #[error("the regressor at sample {sample}: {source}")]
    Regressor {
        /// The sample (0-based).
        sample: usize,
        /// Why.
        #[source]
        source: DynamicsError,
    },
    /// A sample with a non-finite regressor row or torque.
    #[error("sample {sample}: {what}")]
    NonFinite {
        /// The sample (0-based).
        sample: usize,
        /// What is not finite.
        what: &'static str,
    },
    /// A sum or product that left the floating-point range.
    #[error("{what} overflowed")]
    Overflow {
        /// What.
        what: &'static str,
    },
    /// The identification would need more memory than it may use.
    #[error(
        "identifying this robot would need about {needed_gib:.2} GiB, beyond the {limit_gib:.2} GiB limit: lock joints in the sidecar or raise the limit (identify --max-memory-gib)"
    )]
    TooLarge {
        /// Estimated need (GiB).
        needed_gib: f64,
        /// The limit (GiB).
        limit_gib: f64,
    },
    /// A dense factorisation did not converge.
    #[error("the {what} did not converge")]
    Factorisation {
        /// Which (the eigen-decomposition of the Gram matrix, the SVD, …).
        what: &'static str,
    },
    /// A body whose constraint set is empty.
    #[error("the constraint set of body '{body}' is infeasible")]
    InfeasibleBody {
        /// The body.
        body: String,
    },
    /// The solver ended without a solution.
    #[error("the solver ended with status {0}")]
    Solver(Status),
    /// The conic layer failed.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
    /// Data problems.
    #[error(transparent)]
    Data(#[from] crate::data::DataError),
    /// Model problems.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
}
