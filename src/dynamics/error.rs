//! Errors of the dynamics layer.

/// What can go wrong building or evaluating a model.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// A model that is not a valid tree or has bad numbers.
    #[error("model '{model}': {message}")]
    InvalidModel {
        /// The model.
        model: String,
        /// What is wrong.
        message: String,
    },
    /// Wrong vector length.
    #[error("{what}: expected length {expected}, found {found}")]
    Dimension {
        /// Which vector.
        what: String,
        /// Expected length.
        expected: usize,
        /// Found length.
        found: usize,
    },
    /// A URDF or sidecar file problem, naming the element.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: String,
        /// What is wrong, naming the element.
        message: String,
    },
    /// The mass matrix is not positive definite (forward dynamics).
    #[error("the mass matrix is not positive definite at this state")]
    SingularMassMatrix,
}
