//! # `urdf`: the one URDF reader
//!
//! [`read_str`] / [`read_file`] parse URDF text once (with `roxmltree`) into
//! a [`Robot`]: links with their inertials, collision and visual shapes;
//! joints with origin, axis, limits, mimic and friction; transmissions with
//! their reductions. The checker ([`crate::moments::urdf_check`]) and the
//! model builder ([`crate::dynamics::urdf`]) both read through it, and both
//! apply the same rules through [`validate`], which also gives the
//! kinematic [`Tree`].
//!
//! It is strict about what it reads (a bad number is an error naming the
//! file, the link or joint, the element and the attribute) and lenient about
//! everything else: elements it does not use (materials and their textures,
//! `<gazebo>`, `<ros2_control>`, …) are ignored, and a shape whose origin or
//! geometry cannot be read or is out of range is kept as
//! [`Geometry::Invalid`] (reported by [`geometry_warnings`]). No mesh file is
//! opened while reading; [`mesh`] finds and reads the mesh files a URDF
//! names, for the checker's bounding volumes.
//!
//! Hostile input is bounded before it is parsed ([`Limits`]: 256 MiB,
//! 16 Mi nodes, nesting depth 1,000, 64 attributes per element, 1,000
//! namespace declarations); reading, [`validate`] and the tree take time
//! and memory linear in the size of the file (about ten times its size). The rules and limits are listed in `docs/inputs.md`.

mod error;
mod limits;
pub mod mesh;
mod read;
mod robot;
mod rules;
mod tree;
pub mod write;

pub use error::UrdfError;
pub use limits::{Limits, MAX_ATTRIBUTES, MAX_BYTES, MAX_DEPTH, MAX_NAMESPACES, MAX_NODES};
pub use mesh::MeshError;
pub use read::{read_file, read_file_with, read_str, read_str_with};
pub use robot::{
    Geometry, Inertial, Joint, JointDynamics, JointType, Limit, Link, Mimic, Pose, Reduction,
    Robot, Shape, Transmission,
};
pub use rules::{
    GeometryWarning, MAX_ABS_INERTIAL, axis_ok, geometry_warnings, validate, validate_masses,
};
pub use tree::Tree;
