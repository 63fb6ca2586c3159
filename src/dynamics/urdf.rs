//! URDF import (via `urdf-rs`) into a fixed-base [`Model`], with an optional
//! TOML sidecar for what URDF cannot say (rotors, gear ratios, locked
//! joints); the format is in `docs/robots.md`.
//!
//! - the root link (and everything fixed to it) is the fixed base;
//! - revolute, continuous and prismatic joints become model joints
//!   (continuous: unlimited revolute); floating / planar / spherical are
//!   rejected (fixed-base trees only);
//! - fixed joints, and joints named in the sidecar's `lock`, are merged: the
//!   child link's inertia is moved into the parent body with the combined
//!   inertia, and its descendants hang from the parent body;
//! - `<transmission>` `mechanicalReduction` gives a joint's gear ratio when a
//!   sidecar rotor does not.

use super::error::DynamicsError;
use super::model::{Joint, JointKind, Model, Rotor};
use super::spatial::Transform;
use crate::moments::{InertialParams, rpy_rotation};
use nalgebra::Vector3;
use serde::Deserialize;
use std::collections::HashMap;
use std::path::Path;

/// The sidecar file (TOML).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    /// Gravity in the base frame (m/s²); default (0, 0, −9.81).
    pub gravity: Option<[f64; 3]>,
    /// Movable joints to lock at 0 and merge like fixed joints.
    #[serde(default)]
    pub lock: Vec<String>,
    /// Rotors.
    #[serde(default, rename = "rotor")]
    pub rotors: Vec<SidecarRotor>,
}

/// One rotor in the sidecar.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarRotor {
    /// The driven joint.
    pub joint: String,
    /// Rotor name (default `<joint>_rotor`).
    pub name: Option<String>,
    /// Gear ratio N (default: the joint's `<transmission>` reduction).
    pub gear_ratio: Option<f64>,
    /// Rotor frame origin in the joint's parent body frame (default: the joint frame's).
    pub xyz: Option<[f64; 3]>,
    /// Rotor frame orientation, roll-pitch-yaw (default: the joint frame's).
    pub rpy: Option<[f64; 3]>,
    /// Spin axis in the rotor frame (default: the joint axis).
    pub axis: Option<[f64; 3]>,
    /// Inertial parameters in the paper's order, rotor frame.
    pub params: Option<[f64; 10]>,
    /// Or: mass (kg) …
    pub mass: Option<f64>,
    /// … CoM in the rotor frame (m) …
    pub com: Option<[f64; 3]>,
    /// … and inertia about the CoM `[ixx, ixy, ixz, iyy, iyz, izz]` (kg·m²).
    pub inertia: Option<[f64; 6]>,
}

fn ferr(path: &str, message: String) -> DynamicsError {
    DynamicsError::File {
        path: path.to_string(),
        message,
    }
}

impl Sidecar {
    /// Parses sidecar text; `path` names it in errors.
    pub fn parse(text: &str, path: &str) -> Result<Self, DynamicsError> {
        toml::from_str(text).map_err(|e| ferr(path, format!("invalid sidecar: {e}")))
    }

    /// Reads a sidecar file.
    pub fn read(path: &Path) -> Result<Self, DynamicsError> {
        let p = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ferr(&p, e.to_string()))?;
        Self::parse(&text, &p)
    }
}

fn pose(p: &urdf_rs::Pose) -> Transform {
    Transform::from_pose(&rpy_rotation(p.rpy.0), &Vector3::from(p.xyz.0))
}

fn inertial_of(l: &urdf_rs::Link) -> InertialParams {
    let i = &l.inertial;
    InertialParams::from_urdf(
        i.mass.value,
        i.origin.xyz.0,
        i.origin.rpy.0,
        [
            i.inertia.ixx,
            i.inertia.ixy,
            i.inertia.ixz,
            i.inertia.iyy,
            i.inertia.iyz,
            i.inertia.izz,
        ],
    )
}

/// `<transmission>` reductions by joint name.
fn reductions(text: &str) -> HashMap<String, f64> {
    let mut out = HashMap::new();
    let Ok(doc) = roxmltree::Document::parse(text) else {
        return out;
    };
    for t in doc.descendants().filter(|n| n.has_tag_name("transmission")) {
        let joint = t
            .children()
            .find(|c| c.has_tag_name("joint"))
            .and_then(|j| j.attribute("name"));
        let red = t
            .descendants()
            .find(|c| c.has_tag_name("mechanicalReduction"))
            .and_then(|r| r.text())
            .and_then(|s| s.trim().parse::<f64>().ok());
        if let (Some(j), Some(r)) = (joint, red) {
            out.insert(j.to_string(), r);
        }
    }
    out
}

/// Imports URDF text (with an optional sidecar); `path` names it in errors.
pub fn model_from_urdf_str(
    text: &str,
    path: &str,
    sidecar: Option<&Sidecar>,
) -> Result<Model, DynamicsError> {
    if let Err(e) = roxmltree::Document::parse(text) {
        return Err(ferr(path, format!("malformed XML: {e}")));
    }
    let robot =
        urdf_rs::read_from_string(text).map_err(|e| ferr(path, format!("invalid URDF: {e}")))?;
    let empty = Sidecar::default();
    let sc = sidecar.unwrap_or(&empty);
    let link_idx: HashMap<&str, usize> = robot
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| (l.name.as_str(), i))
        .collect();
    for j in &robot.joints {
        for (role, l) in [("parent", &j.parent.link), ("child", &j.child.link)] {
            if !link_idx.contains_key(l.as_str()) {
                return Err(ferr(
                    path,
                    format!(
                        "<joint name=\"{}\">: {role} link '{l}' does not exist",
                        j.name
                    ),
                ));
            }
        }
    }
    for name in &sc.lock {
        if !robot.joints.iter().any(|j| &j.name == name) {
            return Err(ferr(path, format!("sidecar lock: no joint named '{name}'")));
        }
    }
    let mut children: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
    let mut has_parent: HashMap<&str, &str> = HashMap::new();
    for j in &robot.joints {
        if let Some(prev) = has_parent.insert(j.child.link.as_str(), j.name.as_str()) {
            return Err(ferr(
                path,
                format!(
                    "link '{}' is the child of two joints ('{prev}' and '{}')",
                    j.child.link, j.name
                ),
            ));
        }
        children.entry(j.parent.link.as_str()).or_default().push(j);
    }
    let roots: Vec<&str> = robot
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|l| !has_parent.contains_key(l))
        .collect();
    if roots.len() != 1 {
        return Err(ferr(
            path,
            format!("expected one root link, found {}: {:?}", roots.len(), roots),
        ));
    }
    // Walk the tree: each link is attached to a model body (None = base)
    // through a fixed transform `x` (body frame → link frame).
    struct Item<'a> {
        link: &'a str,
        body: Option<usize>,
        x: Transform,
    }
    let mut joints: Vec<Joint> = Vec::new();
    let mut stack = vec![Item {
        link: roots[0],
        body: None,
        x: Transform::identity(),
    }];
    let mut visited = 0usize;
    while let Some(it) = stack.pop() {
        visited += 1;
        if visited > robot.links.len() {
            return Err(ferr(path, "the joints form a cycle".into()));
        }
        let link = &robot.links[link_idx[it.link]];
        // merge this link's inertia into its body (links on the base are ignored)
        if let Some(b) = it.body {
            let pi = inertial_of(link);
            if !pi.is_finite() {
                return Err(ferr(
                    path,
                    format!("<link name=\"{}\">: non-finite inertial values", link.name),
                ));
            }
            // it.x maps body → link: x_body = Eᵀ x_link + r
            let moved2 = pi.transformed(&it.x.e.transpose(), &it.x.r);
            joints[b].inertia = joints[b].inertia.plus(&moved2);
        }
        let mut kids = children.get(it.link).cloned().unwrap_or_default();
        kids.sort_by(|a, b| b.name.cmp(&a.name)); // stack pops in name order
        for j in kids {
            let origin = pose(&j.origin).compose(&it.x); // body → joint frame
            let locked = sc.lock.iter().any(|n| n == &j.name);
            let kind = match &j.joint_type {
                urdf_rs::JointType::Fixed => None,
                _ if locked => None,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    Some(JointKind::Revolute)
                }
                urdf_rs::JointType::Prismatic => Some(JointKind::Prismatic),
                other => {
                    return Err(ferr(
                        path,
                        format!(
                            "<joint name=\"{}\">: type {other:?} is not supported (fixed-base trees with revolute, continuous, prismatic and fixed joints)",
                            j.name
                        ),
                    ));
                }
            };
            match kind {
                None => stack.push(Item {
                    link: &j.child.link,
                    body: it.body,
                    x: origin,
                }),
                Some(kind) => {
                    let a = Vector3::from(j.axis.xyz.0);
                    if !(a.norm() > 0.0 && a.iter().all(|v| v.is_finite())) {
                        return Err(ferr(
                            path,
                            format!(
                                "<joint name=\"{}\">: axis must be a non-zero vector",
                                j.name
                            ),
                        ));
                    }
                    let limits = if matches!(j.joint_type, urdf_rs::JointType::Continuous)
                        || (j.limit.lower == 0.0 && j.limit.upper == 0.0)
                    {
                        (f64::NEG_INFINITY, f64::INFINITY)
                    } else {
                        (j.limit.lower, j.limit.upper)
                    };
                    joints.push(Joint {
                        name: j.name.clone(),
                        body: j.child.link.clone(),
                        parent: it.body,
                        kind,
                        axis: a.normalize(),
                        x_tree: origin,
                        limits,
                        inertia: InertialParams([0.0; 10]),
                    });
                    stack.push(Item {
                        link: &j.child.link,
                        body: Some(joints.len() - 1),
                        x: Transform::identity(),
                    });
                }
            }
        }
    }
    if visited != robot.links.len() {
        return Err(ferr(
            path,
            format!(
                "{} link(s) are not connected to the root '{}'",
                robot.links.len() - visited,
                roots[0]
            ),
        ));
    }
    // rotors from the sidecar
    let red = reductions(text);
    let mut rotors = Vec::new();
    for r in &sc.rotors {
        let Some(ji) = joints.iter().position(|j| j.name == r.joint) else {
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
        let n = r.gear_ratio.or_else(|| red.get(&r.joint).copied()).ok_or_else(|| {
            ferr(path, format!("sidecar rotor '{name}': no gear_ratio and no <transmission> mechanicalReduction for joint '{}'", r.joint))
        })?;
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
        if !(axis.norm() > 0.0) {
            return Err(ferr(path, format!("sidecar rotor '{name}': zero axis")));
        }
        rotors.push(Rotor {
            name,
            joint: ji,
            x_tree,
            axis: axis.normalize(),
            gear_ratio: n,
            inertia,
        });
    }
    let g = sc
        .gravity
        .map(Vector3::from)
        .unwrap_or(Vector3::new(0.0, 0.0, -9.81));
    let name = if robot.name.is_empty() {
        "robot".to_string()
    } else {
        robot.name.clone()
    };
    Model::new(&name, joints, rotors, g).map_err(|e| ferr(path, e.to_string()))
}

/// Reads a URDF file and an optional sidecar file.
pub fn model_from_urdf_file(path: &Path, sidecar: Option<&Path>) -> Result<Model, DynamicsError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| ferr(&p, e.to_string()))?;
    let sc = sidecar.map(Sidecar::read).transpose()?;
    model_from_urdf_str(&text, &p, sc.as_ref())
}
