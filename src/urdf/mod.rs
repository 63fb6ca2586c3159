//! # `urdf`: the one URDF reader
//!
//! [`read_str`] / [`read_file`] parse URDF text once (with `roxmltree`) into
//! a [`Robot`]: links with their inertials, collision and visual shapes;
//! joints with origin, axis, limits, mimic and friction; transmissions with
//! their reductions. The checker ([`crate::moments::urdf_check`]) and the
//! model builder ([`crate::dynamics::urdf`]) both read through it.
//!
//! It is strict about what it reads (a bad number is an error naming the
//! file, the link or joint, the element and the attribute) and lenient about
//! everything else: elements it does not use (materials and their textures,
//! `<gazebo>`, `<ros2_control>`, …) are ignored, and a shape whose geometry
//! cannot be read is kept as [`Geometry::Invalid`] for the readers that need
//! geometry to report. No mesh file is opened here.

mod error;
mod read;
mod robot;

pub use error::UrdfError;
pub use read::{read_file, read_str};
pub use robot::{
    Geometry, Inertial, Joint, JointDynamics, JointType, Limit, Link, Mimic, Pose, Robot, Shape,
    Transmission,
};
