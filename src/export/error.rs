//! Errors of the export layer.

/// What can keep a model from being written for a simulator.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// The model's parameters or robot could not be read or built.
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
    /// The URDF could not be read.
    #[error(transparent)]
    Urdf(#[from] crate::urdf::UrdfError),
    /// The model is not the one this URDF gives (a body or joint the URDF
    /// does not have), or the URDF text is not the one read.
    #[error("{path}: {message}")]
    NotThisUrdf {
        /// The URDF.
        path: String,
        /// What does not match.
        message: String,
    },
    /// A body the target format cannot hold.
    #[error("body '{body}': {message}")]
    Body {
        /// The body (a link by its URDF name, or a rotor).
        body: String,
        /// Why, and what the format needs.
        message: String,
    },
    /// The sidecar given could not be edited into the one written.
    #[error("{path}: {message}")]
    Sidecar {
        /// The sidecar read.
        path: String,
        /// What is wrong.
        message: String,
    },
}
