//! Errors of the URDF reader.

/// What can make a URDF unreadable; each names the file and the element.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UrdfError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// Not well-formed XML.
    #[error("{path}: malformed XML: {message}")]
    Xml {
        /// The file.
        path: String,
        /// The parser's message (with line and column).
        message: String,
    },
    /// Well-formed XML that is not a URDF at the top level.
    #[error("{path}: invalid URDF: {message}")]
    Robot {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// A bad element inside a link (its inertial, say).
    #[error("{path}: link '{link}': {message}")]
    Link {
        /// The file.
        path: String,
        /// The link.
        link: String,
        /// What is wrong, naming the element and attribute.
        message: String,
    },
    /// A bad element inside a joint.
    #[error("{path}: <joint name=\"{joint}\">: {message}")]
    Joint {
        /// The file.
        path: String,
        /// The joint.
        joint: String,
        /// What is wrong, naming the element and attribute.
        message: String,
    },
}
