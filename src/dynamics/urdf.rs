//! A fixed-base [`Model`] from a URDF (read by [`crate::urdf`], held to the
//! checker's rules by [`crate::urdf::validate`]: one tree, unique names,
//! non-negative masses, non-zero axes) and the
//! kinematic entries of its sidecar ([`Sidecar`]: gravity, locked joints,
//! rotors); the format is in `docs/robots.md`.
//!
//! - the root link (and everything fixed to it) is the fixed base;
//! - revolute, continuous and prismatic joints become model joints
//!   (continuous: unlimited revolute); floating / planar / spherical are
//!   rejected (fixed-base trees only);
//! - fixed joints, and joints named in the sidecar's `lock`, are merged: the
//!   child link's inertia is moved into the parent body with the combined
//!   inertia, and its descendants hang from the parent body;
//! - every link becomes a named [`Frame`] of the body it is merged into;
//! - `<transmission>` `mechanicalReduction` gives a joint's gear ratio when a
//!   sidecar rotor does not.

pub use super::sidecar::{Sidecar, SidecarRotor};

use super::error::DynamicsError;
use super::model::{Frame, Joint, JointKind, Model, Rotor};
use super::spatial::Transform;
use crate::moments::{InertialParams, rpy_rotation};
use crate::urdf::{self as format, JointType, Pose, Reduction, Robot, Tree};
use nalgebra::Vector3;
use std::collections::{HashMap, HashSet};
use std::path::Path;

fn ferr(path: &str, message: String) -> DynamicsError {
    DynamicsError::File {
        path: path.to_string(),
        message,
    }
}

fn pose(p: &Pose) -> Transform {
    Transform::from_pose(&rpy_rotation(p.rpy), &Vector3::from(p.xyz))
}

fn inertial_of(l: &format::Link) -> InertialParams {
    match &l.inertial {
        Some(i) => InertialParams::from_urdf(i.mass, i.origin.xyz, i.origin.rpy, i.inertia),
        None => InertialParams([0.0; 10]),
    }
}

/// The sidecar's locked joints, each checked to be a joint of the robot.
fn locks<'s>(tree: &Tree, sc: &'s Sidecar, path: &str) -> Result<HashSet<&'s str>, DynamicsError> {
    let joints: HashSet<&str> = tree
        .robot()
        .joints
        .iter()
        .map(|j| j.name.as_str())
        .collect();
    let mut locked = HashSet::with_capacity(sc.lock.len());
    for name in &sc.lock {
        if !joints.contains(name.as_str()) {
            return Err(ferr(path, format!("sidecar lock: no joint named '{name}'")));
        }
        if !locked.insert(name.as_str()) {
            return Err(ferr(
                path,
                format!("sidecar lock: '{name}' is listed twice"),
            ));
        }
    }
    Ok(locked)
}

/// The model joint a URDF joint becomes (`None`: merged into its parent).
fn joint_kind(
    j: &format::Joint,
    locked: bool,
    path: &str,
) -> Result<Option<JointKind>, DynamicsError> {
    Ok(match j.kind {
        JointType::Fixed => None,
        _ if locked => None,
        JointType::Revolute | JointType::Continuous => Some(JointKind::Revolute),
        JointType::Prismatic => Some(JointKind::Prismatic),
        other => {
            return Err(ferr(
                path,
                format!(
                    "<joint name=\"{}\">: type {other:?} is not supported (fixed-base trees with revolute, continuous, prismatic and fixed joints)",
                    j.name
                ),
            ));
        }
    })
}

fn model_joint(
    j: &format::Joint,
    kind: JointKind,
    parent: Option<usize>,
    x_tree: Transform,
    path: &str,
) -> Result<Joint, DynamicsError> {
    let a = Vector3::from(j.axis);
    if !format::axis_ok(j.axis) {
        return Err(crate::urdf::UrdfError::ZeroAxis {
            path: path.into(),
            joint: j.name.clone(),
        }
        .into());
    }
    let limits = match j.limit {
        Some(l) if j.kind != JointType::Continuous && !(l.lower == 0.0 && l.upper == 0.0) => {
            (l.lower, l.upper)
        }
        _ => (f64::NEG_INFINITY, f64::INFINITY),
    };
    Ok(Joint {
        name: j.name.clone(),
        body: j.child.clone(),
        parent,
        kind,
        axis: a.normalize(),
        x_tree,
        limits,
        inertia: InertialParams([0.0; 10]),
    })
}

/// What a walk of the URDF tree makes: the joints, the frames, and the
/// inertia of everything fixed to the root (in the root frame).
type Walked = (Vec<Joint>, Vec<Frame>, InertialParams);

/// Joints and frames from a depth-first walk from the root (children in name
/// order, joints numbered as reached): each link is attached to a model body (`None`: the base) through
/// a fixed transform (body frame → link frame) and its inertia is merged
/// into that body.
fn walk(tree: &Tree, locked: &HashSet<&str>, path: &str) -> Result<Walked, DynamicsError> {
    let n = tree.robot().links.len();
    let mut joints: Vec<Joint> = Vec::new();
    let mut frames: Vec<Frame> = Vec::with_capacity(n);
    let mut base = InertialParams([0.0; 10]);
    // a joint is numbered when its child is reached: depth first, so that
    // every branch's joints are consecutive (Pinocchio's order)
    let mut stack = vec![(tree.root(), None::<usize>, Transform::identity(), None)];
    while let Some((li, mut body, x, joint)) = stack.pop() {
        if let Some(j) = joint {
            joints.push(j);
            body = Some(joints.len() - 1);
        }
        let link = tree.link(li);
        // x maps body → link: x_body = Eᵀ x_link + r
        let moved = inertial_of(link).transformed(&x.e.transpose(), &x.r);
        match body {
            Some(b) => joints[b].inertia = joints[b].inertia.plus(&moved),
            None => base = base.plus(&moved),
        }
        frames.push(Frame {
            name: link.name.clone(),
            body,
            placement: x,
        });
        let mut kids = tree.child_joints(li).to_vec();
        // the stack pops in name order
        kids.sort_by(|&a, &b| tree.joint(b).name.cmp(&tree.joint(a).name));
        for ji in kids {
            let j = tree.joint(ji);
            let origin = pose(&j.origin).compose(&x); // body → joint frame
            let child = tree.child_link(ji);
            match joint_kind(j, locked.contains(j.name.as_str()), path)? {
                None => stack.push((child, body, origin, None)),
                Some(kind) => {
                    let joint = model_joint(j, kind, body, origin, path)?;
                    stack.push((child, None, Transform::identity(), Some(joint)));
                }
            }
        }
    }
    Ok((joints, frames, base))
}

/// One sidecar rotor on the model's joints.
fn rotor(
    r: &SidecarRotor,
    joints: &[Joint],
    index: &HashMap<&str, usize>,
    reductions: &HashMap<&str, &Reduction>,
    path: &str,
) -> Result<Rotor, DynamicsError> {
    let Some(&ji) = index.get(r.joint.as_str()) else {
        return Err(ferr(
            path,
            format!(
                "sidecar rotor: '{}' is not a movable joint of the model",
                r.joint
            ),
        ));
    };
    let name = r
        .name
        .clone()
        .unwrap_or_else(|| format!("{}_rotor", r.joint));
    let n = match (r.gear_ratio, reductions.get(r.joint.as_str())) {
        (Some(n), _) => n,
        (None, Some(Reduction::Ratio(n))) => *n,
        (None, Some(Reduction::NotANumber(text))) => {
            return Err(ferr(
                path,
                format!(
                    "sidecar rotor '{name}': the <transmission> mechanicalReduction '{text}' of joint '{}' is not a number",
                    r.joint
                ),
            ));
        }
        (None, None) => {
            return Err(ferr(
                path,
                format!(
                    "sidecar rotor '{name}': no gear_ratio and no <transmission> mechanicalReduction for joint '{}'",
                    r.joint
                ),
            ));
        }
    };
    let inertia = match (r.params, r.mass, r.inertia) {
        (Some(p), None, None) => InertialParams(p),
        (None, Some(m), Some(i)) => {
            InertialParams::from_urdf(m, r.com.unwrap_or([0.0; 3]), [0.0; 3], i)
        }
        _ => {
            return Err(ferr(
                path,
                format!("sidecar rotor '{name}': give either params or mass + inertia (+ com)"),
            ));
        }
    };
    let x_tree = match (r.xyz, r.rpy) {
        (None, None) => joints[ji].x_tree,
        (xyz, rpy) => Transform::from_pose(
            &rpy_rotation(rpy.unwrap_or([0.0; 3])),
            &Vector3::from(xyz.unwrap_or([0.0; 3])),
        ),
    };
    let axis = r.axis.map(Vector3::from).unwrap_or(joints[ji].axis);
    check_rotor(&name, n, &inertia, &axis, &x_tree).map_err(|m| ferr(path, m))?;
    Ok(Rotor {
        name,
        joint: ji,
        x_tree,
        axis: axis.normalize(),
        gear_ratio: n,
        inertia,
    })
}

/// A rotor's numbers: a gear ratio in (0, 10⁶], parameters passing
/// [`InertialParams::validate`], a finite non-zero axis and a finite pose.
fn check_rotor(
    name: &str,
    n: f64,
    inertia: &InertialParams,
    axis: &Vector3<f64>,
    x_tree: &Transform,
) -> Result<(), String> {
    if !(n > 0.0 && n <= 1e6) {
        return Err(format!(
            "sidecar rotor '{name}': gear ratio {n} must be in (0, 1e6] (reverse a motor with its axis)"
        ));
    }
    inertia
        .validate()
        .map_err(|m| format!("sidecar rotor '{name}': {m}"))?;
    if !(axis.iter().all(|x| x.is_finite()) && axis.norm() > 0.0) {
        return Err(format!(
            "sidecar rotor '{name}': axis {:?} must be finite and non-zero",
            axis.as_slice()
        ));
    }
    if !(x_tree
        .e
        .iter()
        .chain(x_tree.r.iter())
        .all(|x| x.is_finite()))
    {
        return Err(format!("sidecar rotor '{name}': non-finite xyz or rpy"));
    }
    Ok(())
}

/// Builds the model of a URDF read by [`crate::urdf`] (with an optional
/// sidecar); `path` names it in errors.
pub fn model_from_robot(
    robot: &Robot,
    path: &str,
    sidecar: Option<&Sidecar>,
) -> Result<Model, DynamicsError> {
    tree_from_robot(robot, path, sidecar).map(|(model, _)| model)
}

/// The URDF as a floating-base robot: its root link (and every link fixed
/// to it) is the base of a free-flyer root joint
/// ([`RootJoint::FreeFlyer`](super::RootJoint::FreeFlyer)), the rest as
/// [`model_from_robot`] makes it.
pub fn free_flyer_from_robot(
    robot: &Robot,
    path: &str,
    sidecar: Option<&Sidecar>,
) -> Result<Model, DynamicsError> {
    let (tree, base) = tree_from_robot(robot, path, sidecar)?;
    let t = format::validate(robot, path)?;
    let name = t.link(t.root()).name.clone();
    (tree.with_free_flyer(&name, base)).map_err(|e| ferr(path, e.to_string()))
}

/// Reads a URDF file (and an optional sidecar) as a floating-base robot.
pub fn free_flyer_from_urdf_file(
    path: &Path,
    sidecar: Option<&Path>,
) -> Result<Model, DynamicsError> {
    let (_, robot) = crate::urdf::read_file(path)?;
    let sc = sidecar.map(Sidecar::read).transpose()?;
    free_flyer_from_robot(&robot, &path.display().to_string(), sc.as_ref())
}

fn tree_from_robot(
    robot: &Robot,
    path: &str,
    sidecar: Option<&Sidecar>,
) -> Result<(Model, InertialParams), DynamicsError> {
    let empty = Sidecar::default();
    let sc = sidecar.unwrap_or(&empty);
    let tree = format::validate(robot, path)?;
    format::validate_masses(robot, path)?;
    let locked = locks(&tree, sc, path)?;
    let (joints, frames, base) = walk(&tree, &locked, path)?;
    let index: HashMap<&str, usize> = joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.name.as_str(), i))
        .collect();
    // `<transmission>` reductions by joint name (the last one wins)
    let reductions: HashMap<&str, &Reduction> = robot
        .transmissions
        .iter()
        .filter_map(|t| Some((t.joint.as_deref()?, t.reduction.as_ref()?)))
        .collect();
    let rotors = sc
        .rotors
        .iter()
        .map(|r| rotor(r, &joints, &index, &reductions, path))
        .collect::<Result<_, _>>()?;
    let g = sc
        .gravity
        .map(Vector3::from)
        .unwrap_or(Vector3::new(0.0, 0.0, -9.81));
    let name = if robot.name.is_empty() {
        "robot"
    } else {
        robot.name.as_str()
    };
    Model::new(name, joints, rotors, g)
        .and_then(|m| m.with_frames(frames))
        .map(|m| (m, base))
        .map_err(|e| ferr(path, e.to_string()))
}

/// Imports URDF text (with an optional sidecar); `path` names it in errors.
pub fn model_from_urdf_str(
    text: &str,
    path: &str,
    sidecar: Option<&Sidecar>,
) -> Result<Model, DynamicsError> {
    model_from_robot(&crate::urdf::read_str(text, path)?, path, sidecar)
}

/// Reads a URDF file and an optional sidecar file.
pub fn model_from_urdf_file(path: &Path, sidecar: Option<&Path>) -> Result<Model, DynamicsError> {
    let (_, robot) = crate::urdf::read_file(path)?;
    let sc = sidecar.map(Sidecar::read).transpose()?;
    model_from_robot(&robot, &path.display().to_string(), sc.as_ref())
}
