//! The rules every reader of a URDF applies, in one place: the checker
//! ([`crate::moments::urdf_check`]) and the model loader
//! ([`crate::dynamics::urdf`]) both call [`validate`], so that a file one of
//! them refuses the other refuses too, with the same message.
//!
//! Errors (the file is invalid): no links; joints that do not make one tree
//! ([`Tree::new`]); an `<inertial>` number beyond ±[`MAX_ABS_INERTIAL`]; a
//! moving joint with a zero axis. The model loader also refuses a negative
//! link mass ([`validate_masses`]), which the checker reports as a finding.
//! The reader already refused duplicate names, unreadable or non-finite
//! numbers and an `<inertial>` without `<mass>` or `<inertia>`.
//!
//! Warnings (the file is usable; the element is not): a `<collision>` or
//! `<visual>` whose origin or geometry cannot be read or is out of range
//! ([`geometry_warnings`]).

use super::error::UrdfError;
use super::robot::{Geometry, JointType, Robot};
use super::tree::Tree;

/// Checks `robot` against the rules above; returns its tree. `path` names
/// the file in errors.
pub fn validate<'r>(robot: &'r Robot, path: &str) -> Result<Tree<'r>, UrdfError> {
    if robot.links.is_empty() {
        return Err(UrdfError::NoLinks { path: path.into() });
    }
    let tree = Tree::new(robot, path)?;
    for l in &robot.links {
        let Some(i) = &l.inertial else { continue };
        let numbers = [("mass", i.mass)].into_iter().chain(
            ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]
                .into_iter()
                .zip(i.inertia),
        );
        let origin = ["origin x", "origin y", "origin z"]
            .into_iter()
            .zip(i.origin.xyz);
        if let Some((name, x)) = numbers
            .chain(origin)
            .find(|(_, x)| x.abs() > MAX_ABS_INERTIAL)
        {
            return Err(UrdfError::Link {
                path: path.into(),
                link: l.name.clone(),
                message: format!(
                    "<inertial> {name} = {x:e} is beyond ±{MAX_ABS_INERTIAL:e} (kg, kg·m², m)"
                ),
            });
        }
    }
    for j in &robot.joints {
        let moves = matches!(
            j.kind,
            JointType::Revolute | JointType::Continuous | JointType::Prismatic | JointType::Planar
        );
        if moves && !axis_ok(j.axis) {
            return Err(UrdfError::ZeroAxis {
                path: path.into(),
                joint: j.name.clone(),
            });
        }
    }
    Ok(tree)
}

/// What a model needs beyond [`validate`]: no negative link mass. (The
/// checker reports a negative mass as the finding `nonpositive_mass` and
/// goes on; a model cannot be built with one.)
pub fn validate_masses(robot: &Robot, path: &str) -> Result<(), UrdfError> {
    for l in &robot.links {
        if let Some(i) = &l.inertial
            && i.mass < 0.0
        {
            return Err(UrdfError::NegativeMass {
                path: path.into(),
                link: l.name.clone(),
                mass: i.mass,
            });
        }
    }
    Ok(())
}

/// The largest magnitude of an `<inertial>` number (mass, inertia entry,
/// CoM coordinate): the same bound as the other readers of inertial
/// parameters (`moments::MAX_ABS_PARAM`); beyond it the checker's and the
/// identification's solvers leave the range where they are reliable.
pub const MAX_ABS_INERTIAL: f64 = 1e6;

/// Whether an axis can be normalised: its length, as computed, is positive
/// and finite (so 1e-200 and 1e200 components are refused too).
pub fn axis_ok(axis: [f64; 3]) -> bool {
    let n = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
    n > 0.0 && n.is_finite()
}

/// One warning per shape kept as [`Geometry::Invalid`], naming the link,
/// the element (`<collision>` or `<visual>` and its 1-based position among
/// the link's elements of that kind) and why: `link 'arm': <collision> 2:
/// <box size="-1 1 1">: every value must be positive`.
pub fn geometry_warnings(robot: &Robot) -> Vec<GeometryWarning> {
    let mut out = Vec::new();
    for l in &robot.links {
        for (element, shapes) in [("collision", &l.collisions), ("visual", &l.visuals)] {
            for (k, s) in shapes.iter().enumerate() {
                if let Geometry::Invalid { message } = &s.geometry {
                    out.push(GeometryWarning {
                        link: l.name.clone(),
                        element,
                        position: k + 1,
                        why: message.clone(),
                    });
                }
            }
        }
    }
    out
}

/// A link's shape that cannot be used ([`geometry_warnings`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GeometryWarning {
    /// The link.
    pub link: String,
    /// `collision` or `visual`.
    pub element: &'static str,
    /// Its 1-based position among the link's elements of that kind.
    pub position: usize,
    /// Why (the element as written and what is wrong with it).
    pub why: String,
}

impl std::fmt::Display for GeometryWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "link '{}': <{}> {}: {}",
            self.link, self.element, self.position, self.why
        )
    }
}
