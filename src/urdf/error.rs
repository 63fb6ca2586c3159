//! Errors of the URDF reader and of the rules every reader of a URDF
//! applies ([`super::validate`]).

/// What can make a URDF unreadable or invalid; each names the file and the
/// element (the link, the joint, the line).
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
    /// The file is larger than [`super::Limits::max_bytes`].
    #[error("{path}: the file is {bytes} bytes, more than the limit of {limit} bytes ({} MiB)", .limit >> 20)]
    TooLarge {
        /// The file.
        path: String,
        /// Its size (bytes; at least `limit + 1` when it was read to find out).
        bytes: u64,
        /// The limit (bytes).
        limit: usize,
    },
    /// More nodes than [`super::Limits::max_nodes`].
    #[error("{path}: line {line}: more than {limit} elements, comments and other nodes")]
    TooManyNodes {
        /// The file.
        path: String,
        /// The line of the first node beyond the limit.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// Elements nested deeper than [`super::Limits::max_depth`].
    #[error("{path}: line {line}: elements nested more than {limit} deep")]
    TooDeep {
        /// The file.
        path: String,
        /// The line of the first element beyond the limit.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// An element with more than [`super::Limits::max_attributes`] attributes.
    #[error("{path}: line {line}: an element with more than {limit} attributes")]
    TooManyAttributes {
        /// The file.
        path: String,
        /// The line of the element.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// More than [`super::Limits::max_namespaces`] namespace declarations.
    #[error("{path}: line {line}: more than {limit} namespace declarations (xmlns) in the file")]
    TooManyNamespaces {
        /// The file.
        path: String,
        /// The line of the declaration beyond the limit.
        line: usize,
        /// The limit.
        limit: usize,
    },
    /// Two links with the same name.
    #[error("{path}: two links are named '{name}' (URDF names are unique)")]
    DuplicateLink {
        /// The file.
        path: String,
        /// The name.
        name: String,
    },
    /// Two joints with the same name.
    #[error("{path}: two joints are named '{name}' (URDF names are unique)")]
    DuplicateJoint {
        /// The file.
        path: String,
        /// The name.
        name: String,
    },
    /// A `<robot>` without links.
    #[error("{path}: the <robot> has no <link>: nothing to check, no model to build")]
    NoLinks {
        /// The file.
        path: String,
    },
    /// A joint whose parent or child link does not exist.
    #[error("{path}: <joint name=\"{joint}\">: {role} link '{link}' does not exist")]
    MissingLink {
        /// The file.
        path: String,
        /// The joint.
        joint: String,
        /// `parent` or `child`.
        role: &'static str,
        /// The link named.
        link: String,
    },
    /// A link that is the child of two joints (a kinematic loop).
    #[error(
        "{path}: link '{link}' is the child of two joints ('{first}' and '{second}'): a kinematic loop, not a tree"
    )]
    TwoParents {
        /// The file.
        path: String,
        /// The link.
        link: String,
        /// The first joint (file order).
        first: String,
        /// The second joint.
        second: String,
    },
    /// Joints that form a cycle.
    #[error(
        "{path}: <joint name=\"{joint}\"> closes a cycle of {length} joint(s) through link '{link}': a kinematic loop, not a tree"
    )]
    Cycle {
        /// The file.
        path: String,
        /// A joint on the cycle.
        joint: String,
        /// Its child link.
        link: String,
        /// The number of joints on the cycle.
        length: usize,
    },
    /// Not exactly one root link (a link that is no joint's child).
    #[error("{path}: expected one root link, found {count}{}", names(.roots, *.count))]
    Roots {
        /// The file.
        path: String,
        /// How many there are.
        count: usize,
        /// The first of them (at most ten).
        roots: Vec<String>,
    },
    /// A negative link mass.
    #[error("{path}: link '{link}': negative mass {mass} kg")]
    NegativeMass {
        /// The file.
        path: String,
        /// The link.
        link: String,
        /// The mass (kg).
        mass: f64,
    },
    /// A moving joint without a direction.
    #[error(
        "{path}: <joint name=\"{joint}\">: axis must be a non-zero vector (of positive, finite length)"
    )]
    ZeroAxis {
        /// The file.
        path: String,
        /// The joint.
        joint: String,
    },
}

/// `: a, b, c` (with `, …` when some are left out); empty without names.
fn names(shown: &[String], count: usize) -> String {
    if shown.is_empty() {
        return String::new();
    }
    let more = if count > shown.len() { ", …" } else { "" };
    format!(": {}{more}", shown.join(", "))
}
