//! Errors of the dynamics layer.

/// What can go wrong building or evaluating a model.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// A model that is not a valid tree or has bad numbers.
    #[error("model '{model}': {fault}")]
    InvalidModel {
        /// The model.
        model: String,
        /// What is wrong.
        fault: super::fault::ModelFault,
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
    /// A file that could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// A URDF or sidecar file problem, naming the element.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: String,
        /// What is wrong, naming the element.
        message: String,
    },
    /// A computed torque (or state) that left the floating-point range.
    #[error("sample {sample}: {what} is not finite (an overflow in the model's arithmetic)")]
    NonFinite {
        /// The sample (0-based).
        sample: usize,
        /// What.
        what: String,
    },
    /// A base orientation quaternion that is not of unit norm.
    #[error("base quaternion (x, y, z, w) = {values:?} has norm {norm}, not 1 (within 1e-5)")]
    Quaternion {
        /// The quaternion as given.
        values: [f64; 4],
        /// Its norm.
        norm: f64,
    },
    /// A free flyer's algorithm asked of a fixed-base model.
    #[error(
        "model '{model}' has a fixed base; {what} needs a free-flying root (sidecar [floating_base] or --floating-base)"
    )]
    FixedBase {
        /// The model.
        model: String,
        /// What needed the free flyer.
        what: &'static str,
    },
    /// The mass matrix is not positive definite (forward dynamics).
    #[error("the mass matrix is not positive definite at this state")]
    SingularMassMatrix,
    /// A URDF that cannot be read.
    #[error(transparent)]
    Urdf(#[from] crate::urdf::UrdfError),
    /// An unknown name (a built-in robot, a joint, …).
    #[error("unknown {what} '{name}' (known: {valid})")]
    UnknownName {
        /// What kind of name.
        what: &'static str,
        /// The name given.
        name: String,
        /// The valid names.
        valid: String,
    },
    /// A name given twice in a list that takes each once.
    #[error("{what} '{name}' is listed twice")]
    Repeated {
        /// What kind of name.
        what: &'static str,
        /// The name given twice.
        name: String,
    },
    /// A sidecar body's bounding ellipsoid that is not one.
    #[error("[[body]] '{body}': bounding: {source}")]
    Bounding {
        /// The body.
        body: String,
        /// Why.
        #[source]
        source: crate::moments::MomentsError,
    },
    /// A robot description (sidecar) entry that does not fit the model.
    #[error("{source_name}: {message}")]
    Description {
        /// The sidecar or built-in robot.
        source_name: String,
        /// What is wrong, naming the entry.
        message: String,
    },
}

/// The text of a file, or an error naming it (with the OS error as source).
pub(crate) fn read_text(path: &std::path::Path) -> Result<String, DynamicsError> {
    let io = |source| DynamicsError::Io {
        path: path.display().to_string(),
        source,
    };
    let bytes = crate::io::read_capped(path, MAX_TEXT_BYTES).map_err(|e| match e {
        crate::io::Capped::Io(source) => io(source),
        crate::io::Capped::TooLarge(_) => DynamicsError::File {
            path: path.display().to_string(),
            message: format!(
                "larger than {} MiB; not a sidecar or parameter file",
                MAX_TEXT_BYTES >> 20
            ),
        },
    })?;
    String::from_utf8(bytes)
        .map_err(|e| io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// The largest sidecar or parameter file read (64 MiB): a description of
/// thousands of bodies is a few MiB.
pub const MAX_TEXT_BYTES: u64 = 64 << 20;
