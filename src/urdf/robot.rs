//! What a URDF says, as plain data (lengths in m, angles in rad, masses in
//! kg, inertias in kg·m²). Frames as in the URDF specification: an
//! `<origin xyz rpy>` places a child frame in its parent frame with
//! R = Rz(yaw)·Ry(pitch)·Rx(roll).

use std::ops::Range;

/// A pose `<origin xyz rpy>`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// Translation (m).
    pub xyz: [f64; 3],
    /// Roll, pitch, yaw (rad).
    pub rpy: [f64; 3],
}

/// An `<inertial>` block, as written: mass, CoM frame, inertia about the CoM
/// in that frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Inertial {
    /// The CoM frame in the link frame.
    pub origin: Pose,
    /// Mass (kg); negative values are kept for the checker to report.
    pub mass: f64,
    /// `[ixx, ixy, ixz, iyy, iyz, izz]` about the CoM, CoM frame (kg·m²).
    pub inertia: [f64; 6],
    /// Byte range of the `<inertial>` element in the text (for repairs).
    pub range: Range<usize>,
}

/// A `<geometry>`.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// `<box size="x y z">` (full side lengths, m).
    Box {
        /// Side lengths (m).
        size: [f64; 3],
    },
    /// `<cylinder radius length>` about the z axis.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length (m).
        length: f64,
    },
    /// `<sphere radius>`.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// `<capsule radius length>` about the z axis (length of the cylinder part).
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Length of the cylindrical part (m).
        length: f64,
    },
    /// `<mesh filename scale>`.
    Mesh {
        /// The file name as written (`package://…`, `file://…` or a path).
        filename: String,
        /// Scale per axis.
        scale: [f64; 3],
    },
    /// A shape whose origin or geometry could not be read or is out of range
    /// (kept so that a reader that needs geometry can say why; see
    /// [`super::geometry_warnings`]).
    Invalid {
        /// Why, naming the element and attribute (`<box size="-1 1 1">:
        /// every value must be positive`).
        message: String,
    },
}

/// A `<visual>` or `<collision>` shape.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// The shape's frame in the link frame.
    pub origin: Pose,
    /// The geometry.
    pub geometry: Geometry,
}

/// A `<link>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Link {
    /// Name.
    pub name: String,
    /// The inertial block, if any.
    pub inertial: Option<Inertial>,
    /// Collision shapes.
    pub collisions: Vec<Shape>,
    /// Visual shapes.
    pub visuals: Vec<Shape>,
    /// Byte range of the `<link>` element in the text (for writing a copy).
    pub range: Range<usize>,
}

/// A joint's `type`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointType {
    /// `revolute` (limited rotation).
    Revolute,
    /// `continuous` (unlimited rotation).
    Continuous,
    /// `prismatic` (translation).
    Prismatic,
    /// `fixed`.
    Fixed,
    /// `floating` (6 DoF).
    Floating,
    /// `planar` (3 DoF).
    Planar,
    /// `spherical` (3 DoF).
    Spherical,
}

/// `<limit lower upper effort velocity>` (absent values: 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Limit {
    /// Lower position limit (rad or m).
    pub lower: f64,
    /// Upper position limit (rad or m).
    pub upper: f64,
    /// Effort limit (N·m or N).
    pub effort: f64,
    /// Velocity limit (rad/s or m/s).
    pub velocity: f64,
}

/// `<mimic joint multiplier offset>`: q = multiplier · q_joint + offset.
#[derive(Clone, Debug, PartialEq)]
pub struct Mimic {
    /// The joint followed.
    pub joint: String,
    /// Multiplier (default 1).
    pub multiplier: f64,
    /// Offset (default 0).
    pub offset: f64,
}

/// `<dynamics damping friction>`: viscous (N·m·s/rad) and Coulomb (N·m)
/// friction of the joint, each as written (absent: `None`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointDynamics {
    /// Viscous damping.
    pub damping: Option<f64>,
    /// Coulomb friction.
    pub friction: Option<f64>,
}

/// A `<joint>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Name.
    pub name: String,
    /// Type.
    pub kind: JointType,
    /// The parent link.
    pub parent: String,
    /// The child link.
    pub child: String,
    /// The joint frame in the parent link frame.
    pub origin: Pose,
    /// Axis in the joint frame (default (1, 0, 0)), as written (not normalised).
    pub axis: [f64; 3],
    /// Limits, if given.
    pub limit: Option<Limit>,
    /// Mimic, if given.
    pub mimic: Option<Mimic>,
    /// Friction, if given.
    pub dynamics: Option<JointDynamics>,
    /// Byte ranges in the text of the `<joint>` element and of its
    /// `<dynamics>` child, if any (for writing a copy).
    pub ranges: (Range<usize>, Option<Range<usize>>),
}

/// A `<transmission>`: the joint it drives and its reduction.
#[derive(Clone, Debug, PartialEq)]
pub struct Transmission {
    /// Name.
    pub name: String,
    /// The joint (`<joint name>`), if given.
    pub joint: Option<String>,
    /// `<mechanicalReduction>`, if given.
    pub reduction: Option<Reduction>,
}

/// A `<mechanicalReduction>`: the number, or the text that is not one.
#[derive(Clone, Debug, PartialEq)]
pub enum Reduction {
    /// A finite ratio.
    Ratio(f64),
    /// Text that is not a finite number.
    NotANumber(String),
}

/// A whole URDF: the elements a robot description needs, in file order.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Robot {
    /// `<robot name>`.
    pub name: String,
    /// Links.
    pub links: Vec<Link>,
    /// Joints.
    pub joints: Vec<Joint>,
    /// Transmissions.
    pub transmissions: Vec<Transmission>,
}

impl Robot {
    /// The link named `name` (a linear search; for many look-ups use
    /// [`super::Tree::link_index`]).
    pub fn link(&self, name: &str) -> Option<&Link> {
        self.links.iter().find(|l| l.name == name)
    }
}
