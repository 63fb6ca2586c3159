//! The constant description of a kinematic tree with geared rotors, fixed
//! to the world or hanging from a free-flying base ([`RootJoint`]).

use super::error::DynamicsError;
use super::fault::{MAX_ABS_LIMIT, ModelFault};
use super::spatial::Transform;
use crate::moments::InertialParams;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// The kind of a moving joint (fixed joints are merged at import).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// Rotation about the axis (rad).
    Revolute,
    /// Translation along the axis (m).
    Prismatic,
}

/// A joint and the body it moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Joint name (also names CSV columns: `q_<name>`, …).
    pub name: String,
    /// Name of the body it moves.
    pub body: String,
    /// Index of the parent joint's body, `None` for the fixed base.
    pub parent: Option<usize>,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Unit axis in the joint frame.
    pub axis: Vector3<f64>,
    /// Joint frame (before the joint's own motion) in the parent body frame.
    pub x_tree: Transform,
    /// Lower and upper position limits (rad or m); ±∞ when unlimited.
    pub limits: (f64, f64),
    /// The moved body's inertial parameters in its own (joint) frame.
    pub inertia: InertialParams,
}

/// A joint limit pair: increasing, each end ±∞ or finite within
/// ±[`MAX_ABS_LIMIT`].
pub fn check_limits(joint: &str, (lower, upper): (f64, f64)) -> Result<(), ModelFault> {
    let ok = |x: f64| x.is_infinite() || x.abs() <= MAX_ABS_LIMIT;
    let joint = joint.to_string();
    if !(lower < upper) {
        return Err(ModelFault::LimitsOrder {
            joint,
            lower,
            upper,
        });
    }
    if !(ok(lower) && ok(upper)) {
        return Err(ModelFault::LimitsRange {
            joint,
            lower,
            upper,
        });
    }
    Ok(())
}

/// A joint name is also a CSV column name (`q_<name>`): not empty, and no
/// comma, quote, space or control character.
pub fn check_joint_name(name: &str) -> Result<(), ModelFault> {
    if name.is_empty() {
        return Err(ModelFault::UnnamedJoint);
    }
    if let Some(c) = name
        .chars()
        .find(|c| matches!(c, ',' | '"' | '\'') || c.is_whitespace() || c.is_control())
    {
        return Err(ModelFault::JointName {
            joint: name.to_string(),
            bad: c,
        });
    }
    Ok(())
}

/// A rotor geared to a joint: a rigid body mounted on the joint's parent
/// body, spinning about its own axis at `gear_ratio × q̇` (so its angle is
/// `gear_ratio × q`). Its gyroscopic coupling with the parent is modelled.
#[derive(Clone, Debug, PartialEq)]
pub struct Rotor {
    /// Name (reports, parameter files).
    pub name: String,
    /// Index of the joint that drives it.
    pub joint: usize,
    /// Rotor frame (before its spin) in the frame of the joint's parent body.
    pub x_tree: Transform,
    /// Spin axis, unit, in the rotor frame.
    pub axis: Vector3<f64>,
    /// Gear ratio N (rotor turns per joint turn).
    pub gear_ratio: f64,
    /// Inertial parameters in the rotor frame.
    pub inertia: InertialParams,
}

/// A named frame rigidly attached to a body (Pinocchio's operational
/// frames): every URDF link is one, including the links merged into a body
/// by fixed joints and those on the base.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Name (the URDF link name).
    pub name: String,
    /// The body it is attached to (joint index), `None` for the fixed base.
    pub body: Option<usize>,
    /// `bXf`: the frame's placement in the body (or base) frame; it maps
    /// body coordinates to frame coordinates (`x_f = E (x_b − r)`).
    pub placement: Transform,
}

/// The tool point: where a payload sits (a point of one body, in its frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolPoint {
    /// The body (joint index).
    pub body: usize,
    /// The point in the body frame (m).
    pub point: Vector3<f64>,
}

/// The joint that attaches the tree to the world (Pinocchio's root joint).
#[derive(Clone, Debug, PartialEq)]
pub enum RootJoint {
    /// Welded to the world: the base does not move and has no parameters.
    Fixed,
    /// Pinocchio's free flyer: the base is a body with six degrees of
    /// freedom (conventions in [`super::free_flyer`]).
    FreeFlyer(BaseBody),
}

/// The free-flying base body.
#[derive(Clone, Debug, PartialEq)]
pub struct BaseBody {
    /// The base's name (the URDF root link).
    pub name: String,
    /// Its inertial parameters in the base frame (paper order), every link
    /// fixed to the root merged in.
    pub inertia: InertialParams,
}

/// A kinematic tree: joints in topological order (parents first), one body
/// per joint, optional rotors, gravity, and the root joint that attaches
/// it to the world. With a free-flying root the base is body 0 of the
/// parameter vector and the generalized velocity has its 6 entries first
/// ([`Model::nv`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// Model name.
    pub name: String,
    /// How the tree is attached to the world.
    pub root: RootJoint,
    /// Joints, parents before children.
    pub joints: Vec<Joint>,
    /// Rotors.
    pub rotors: Vec<Rotor>,
    /// Gravity in the world frame (m/s²), e.g. (0, 0, −9.81) (the fixed
    /// base's frame is the world's).
    pub gravity: Vector3<f64>,
    /// Named frames (by default one per body, at the body frame).
    pub frames: Vec<Frame>,
    /// The tool point (default: the last body's origin; `None` without joints).
    pub tool: Option<ToolPoint>,
    /// Rotor index per joint (at most one rotor per joint), derived.
    pub(crate) rotor_of: Vec<Option<usize>>,
    /// The friction terms the regressor has columns for, in
    /// [`FrictionTerm::ALL`](super::FrictionTerm::ALL)'s order.
    pub(crate) friction_terms: Vec<super::FrictionTerm>,
    /// The Stribeck velocity (rad/s) of the regressor's Stribeck column.
    pub(crate) stribeck_velocity: f64,
}

impl Model {
    /// Builds and validates a model: parents before children, unit axes,
    /// finite numbers, at most one rotor per joint, unique joint and body
    /// names.
    pub fn new(
        name: &str,
        joints: Vec<Joint>,
        rotors: Vec<Rotor>,
        gravity: Vector3<f64>,
    ) -> Result<Self, DynamicsError> {
        let invalid = |fault| DynamicsError::InvalidModel {
            model: name.to_string(),
            fault,
        };
        if joints.is_empty() {
            return Err(invalid(ModelFault::NoJoint));
        }
        if !gravity.iter().all(|g| g.is_finite() && g.abs() <= 1e3) {
            return Err(invalid(ModelFault::Gravity(gravity.into())));
        }
        check_joints(&joints).map_err(invalid)?;
        let rotor_of = check_rotors(&joints, &rotors).map_err(invalid)?;
        check_body_names(&joints, &rotors).map_err(invalid)?;
        let frames = joints
            .iter()
            .enumerate()
            .map(|(i, j)| Frame {
                name: j.body.clone(),
                body: Some(i),
                placement: Transform::identity(),
            })
            .collect();
        let tool = joints.len().checked_sub(1).map(|last| ToolPoint {
            body: last,
            point: Vector3::zeros(),
        });
        Ok(Self {
            name: name.to_string(),
            root: RootJoint::Fixed,
            joints,
            rotors,
            gravity,
            frames,
            tool,
            rotor_of,
            friction_terms: super::FrictionTerm::DEFAULT.to_vec(),
            stribeck_velocity: super::friction::DEFAULT_STRIBECK_VELOCITY,
        })
    }

    /// The same model with these named frames (each on an existing body, with
    /// finite placements and unique names).
    pub fn with_frames(mut self, frames: Vec<Frame>) -> Result<Self, DynamicsError> {
        let mut names = std::collections::HashSet::with_capacity(frames.len());
        for f in &frames {
            let bad = |fault| DynamicsError::InvalidModel {
                model: self.name.clone(),
                fault,
            };
            if f.body.is_some_and(|b| b >= self.joints.len()) {
                return Err(bad(ModelFault::FrameBody(f.name.clone())));
            }
            if !f
                .placement
                .r
                .iter()
                .chain(f.placement.e.iter())
                .all(|x| x.is_finite())
            {
                return Err(bad(ModelFault::FramePlacement(f.name.clone())));
            }
            if !names.insert(f.name.as_str()) {
                return Err(bad(ModelFault::DuplicateFrame(f.name.clone())));
            }
        }
        self.frames = frames;
        Ok(self)
    }

    /// The frame named `name`.
    pub fn frame(&self, name: &str) -> Option<&Frame> {
        self.frames.iter().find(|f| f.name == name)
    }

    /// The same model with its tool point at `xyz` (m) in frame `frame`,
    /// which must be on a moving body.
    pub fn with_tool(mut self, frame: &str, xyz: [f64; 3]) -> Result<Self, DynamicsError> {
        let bad = |fault| DynamicsError::InvalidModel {
            model: self.name.clone(),
            fault,
        };
        let f = self.frame(frame).ok_or_else(|| {
            bad(ModelFault::ToolFrame {
                frame: frame.to_string(),
                frames: self.frames.iter().map(|f| f.name.clone()).collect(),
            })
        })?;
        let body = f
            .body
            .ok_or_else(|| bad(ModelFault::ToolOnBase(frame.to_string())))?;
        let x = Vector3::from(xyz);
        if !x.iter().all(|v| v.is_finite()) {
            return Err(bad(ModelFault::ToolPoint));
        }
        // x_body = Eᵀ x_frame + r
        let point = f.placement.e.transpose() * x + f.placement.r;
        self.tool = Some(ToolPoint { body, point });
        Ok(self)
    }

    /// The same tree hanging from a free-flying base `name` with parameters
    /// `inertia` (checked: finite, physically consistent).
    pub fn with_free_flyer(
        mut self,
        name: &str,
        inertia: InertialParams,
    ) -> Result<Self, DynamicsError> {
        inertia.validate().map_err(|e| DynamicsError::Description {
            source_name: self.name.clone(),
            message: format!("base '{name}': {e}"),
        })?;
        if self.body_names().iter().any(|b| b == name) {
            return Err(DynamicsError::InvalidModel {
                model: self.name.clone(),
                fault: ModelFault::DuplicateBody(name.to_string()),
            });
        }
        self.root = RootJoint::FreeFlyer(BaseBody {
            name: name.to_string(),
            inertia,
        });
        Ok(self)
    }

    /// The free-flying base, `None` for a fixed base.
    pub fn base(&self) -> Option<&BaseBody> {
        match &self.root {
            RootJoint::Fixed => None,
            RootJoint::FreeFlyer(b) => Some(b),
        }
    }

    /// Whether the root is a free flyer.
    pub fn is_floating(&self) -> bool {
        self.base().is_some()
    }

    /// The same tree welded to the world (the base body dropped).
    pub fn fixed_tree(&self) -> Model {
        Model {
            root: RootJoint::Fixed,
            ..self.clone()
        }
    }

    /// Degrees of freedom of the joints, n (the free flyer's 6 not counted).
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The root joint's velocity size: 0 fixed, 6 free flyer.
    pub fn root_nv(&self) -> usize {
        6 * usize::from(self.is_floating())
    }

    /// Configuration size: n, or `7 + n` with a free flyer.
    pub fn nq(&self) -> usize {
        self.dof() + 7 * usize::from(self.is_floating())
    }

    /// Velocity size (rows of the dynamics): n, or `6 + n` with a free flyer.
    pub fn nv(&self) -> usize {
        self.dof() + self.root_nv()
    }

    /// Bodies with parameters before link 0 (1 with a free-flying base).
    pub(crate) fn first_link_body(&self) -> usize {
        usize::from(self.is_floating())
    }

    /// The parameter-order index of the body frame `f` is on: link i's is
    /// `i` (after a free-flying base's 0); a frame on the base is on body 0
    /// with a free flyer, on no body (`None`) with a fixed base.
    pub fn body_of_frame(&self, f: &Frame) -> Option<usize> {
        match f.body {
            Some(i) => Some(self.first_link_body() + i),
            None => self.is_floating().then_some(0),
        }
    }

    /// Number of bodies with parameters: the free-flying base (if any),
    /// links, then rotors.
    pub fn num_bodies(&self) -> usize {
        self.first_link_body() + self.joints.len() + self.rotors.len()
    }

    /// Joint names in order.
    pub fn joint_names(&self) -> Vec<&str> {
        self.joints.iter().map(|j| j.name.as_str()).collect()
    }

    /// Body names in parameter order: the free-flying base (if any), links
    /// (by their body names), then rotors.
    pub fn body_names(&self) -> Vec<String> {
        (self.base().map(|b| b.name.clone()).into_iter())
            .chain(self.joints.iter().map(|j| j.body.clone()))
            .chain(self.rotors.iter().map(|r| r.name.clone()))
            .collect()
    }

    /// All inertial parameters stacked: the free-flying base (if any),
    /// links, then rotors (10 per body).
    pub fn params(&self) -> Vec<f64> {
        (self.base().map(|b| b.inertia).into_iter())
            .chain(self.joints.iter().map(|j| j.inertia))
            .chain(self.rotors.iter().map(|r| r.inertia))
            .flat_map(|p| p.0)
            .collect()
    }

    /// Replaces all inertial parameters (the free-flying base, links, then
    /// rotors; 10 per body).
    pub fn set_params(&mut self, p: &[f64]) -> Result<(), DynamicsError> {
        if p.len() != 10 * self.num_bodies() {
            return Err(DynamicsError::Dimension {
                what: "parameter vector".into(),
                expected: 10 * self.num_bodies(),
                found: p.len(),
            });
        }
        if let Some(k) = p.iter().position(|x| !x.is_finite()) {
            return Err(DynamicsError::InvalidModel {
                model: self.name.clone(),
                fault: ModelFault::BodyParameter {
                    body: self.body_names()[k / 10].clone(),
                    value: p[k],
                },
            });
        }
        let (b0, nj) = (self.first_link_body(), self.joints.len());
        for (k, chunk) in p.chunks(10).enumerate() {
            let v = InertialParams(std::array::from_fn(|i| chunk[i]));
            if let (true, RootJoint::FreeFlyer(b)) = (k < b0, &mut self.root) {
                b.inertia = v;
                continue;
            }
            let k = k - b0;
            if k < nj {
                self.joints[k].inertia = v;
            } else {
                self.rotors[k - nj].inertia = v;
            }
        }
        Ok(())
    }

    /// The links as a compliant transmission drives them: each rotor's body
    /// welded to the link it is mounted on at zero spin angle (its housing
    /// moves with that link; a rotor on a fixed base drops out, one on a
    /// free-flying base rides on it), and no
    /// rotor spin (exact for rotors symmetric about their spin axes). The
    /// spin terms (the rotors' motion relative to their mounts) stay with
    /// the motor side: `full(θ) − link_side(θ)` at a rigid state.
    pub fn link_side(&self) -> Model {
        let mut joints = self.joints.clone();
        let mut root = self.root.clone();
        for r in &self.rotors {
            let moved = r.inertia.transformed(&r.x_tree.e.transpose(), &r.x_tree.r);
            match (self.joints[r.joint].parent, &mut root) {
                (Some(p), _) => joints[p].inertia = joints[p].inertia.plus(&moved),
                (None, RootJoint::FreeFlyer(base)) => base.inertia = base.inertia.plus(&moved),
                (None, RootJoint::Fixed) => {}
            }
        }
        Model {
            name: self.name.clone(),
            root,
            joints,
            rotors: vec![],
            gravity: self.gravity,
            frames: self.frames.clone(),
            tool: self.tool,
            rotor_of: vec![None; self.joints.len()],
            friction_terms: self.friction_terms.clone(),
            stribeck_velocity: self.stribeck_velocity,
        }
    }

    /// The friction terms the regressor has columns for (default
    /// [`FrictionTerm::DEFAULT`](super::FrictionTerm::DEFAULT)).
    pub fn friction_terms(&self) -> &[super::FrictionTerm] {
        &self.friction_terms
    }

    /// The model with regressor columns for the friction `terms` instead
    /// (none: links and rotors only), kept in
    /// [`FrictionTerm::ALL`](super::FrictionTerm::ALL)'s order, each once.
    pub fn with_friction_terms(mut self, terms: &[super::FrictionTerm]) -> Self {
        let mut t = terms.to_vec();
        t.sort();
        t.dedup();
        self.friction_terms = t;
        self
    }

    /// The Stribeck velocity v_s (rad/s) of the regressor's Stribeck
    /// column (default
    /// [`DEFAULT_STRIBECK_VELOCITY`](super::friction::DEFAULT_STRIBECK_VELOCITY)).
    pub fn stribeck_velocity(&self) -> f64 {
        self.stribeck_velocity
    }

    /// The model with Stribeck velocity `v` (rad/s; positive and at most
    /// 1e6, as a model file allows; else an error naming it).
    pub fn with_stribeck_velocity(mut self, v: f64) -> Result<Self, super::DynamicsError> {
        if !(v.is_finite() && v > 0.0 && v <= crate::moments::MAX_ABS_PARAM) {
            return Err(super::DynamicsError::InvalidModel {
                model: self.name.clone(),
                fault: super::fault::ModelFault::StribeckVelocity(v),
            });
        }
        self.stribeck_velocity = v;
        Ok(self)
    }

    /// Index of the joint named `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The regressor's column layout by name (rows: one per velocity
    /// coordinate, [`nv`](Self::nv)).
    pub fn layout(&self) -> super::ParamLayout {
        self.layout_of_rows(0..self.nv())
    }

    /// The column layout fitting the `rows` of each sample (a free flyer's
    /// base rows `0..6`, joint rows `6..6 + n`, or both).
    pub fn layout_of_rows(&self, rows: std::ops::Range<usize>) -> super::ParamLayout {
        super::ParamLayout {
            bodies: self.body_names(),
            joints: self.joint_names().iter().map(|j| j.to_string()).collect(),
            terms: self.friction_terms().to_vec(),
            rows: rows.len(),
            first_row: rows.start,
        }
    }

    /// The regressor's column count ([`crate::dynamics::regressor`]): 10 per
    /// body, then one per joint and friction term.
    pub fn regressor_columns(&self) -> usize {
        10 * self.num_bodies() + self.friction_terms.len() * self.dof()
    }

    /// The rotor driven by joint i, if any.
    pub fn rotor_of(&self, i: usize) -> Option<&Rotor> {
        self.rotor_of
            .get(i)
            .copied()
            .flatten()
            .map(|k| &self.rotors[k])
    }

    /// Motion subspace of joint i in its body frame (6-vector).
    pub(crate) fn subspace(&self, i: usize) -> nalgebra::Vector6<f64> {
        let a = self.joints[i].axis;
        match self.joints[i].kind {
            JointKind::Revolute => nalgebra::Vector6::new(a.x, a.y, a.z, 0.0, 0.0, 0.0),
            JointKind::Prismatic => nalgebra::Vector6::new(0.0, 0.0, 0.0, a.x, a.y, a.z),
        }
    }

    /// Transform from the parent body frame to body i at position q_i.
    #[inline]
    pub(crate) fn joint_transform(&self, i: usize, q: f64) -> Transform {
        let j = &self.joints[i];
        let motion = match j.kind {
            JointKind::Revolute => Transform::from_pose(
                &super::spatial::axis_rotation(&j.axis, q),
                &Vector3::zeros(),
            ),
            JointKind::Prismatic => Transform::from_pose(&Matrix3::identity(), &(j.axis * q)),
        };
        motion.compose(&j.x_tree)
    }

    /// Transform from the parent body frame of rotor k to the spun rotor frame.
    #[inline]
    pub(crate) fn rotor_transform(&self, k: usize, q: f64) -> Transform {
        let r = &self.rotors[k];
        let spin = Transform::from_pose(
            &super::spatial::axis_rotation(&r.axis, r.gear_ratio * q),
            &Vector3::zeros(),
        );
        spin.compose(&r.x_tree)
    }
}

/// Every joint's name, limits, parent order, axis and numbers, and unique
/// names.
fn check_joints(joints: &[Joint]) -> Result<(), ModelFault> {
    let mut names = std::collections::HashSet::with_capacity(joints.len());
    for (i, j) in joints.iter().enumerate() {
        check_joint_name(&j.name)?;
        check_limits(&j.name, j.limits)?;
        let joint = || j.name.clone();
        if let Some(parent) = j.parent.filter(|&p| p >= i) {
            return Err(ModelFault::ParentOrder {
                joint: joint(),
                parent,
            });
        }
        if !((j.axis.norm() - 1.0).abs() < 1e-9) {
            return Err(ModelFault::Axis {
                joint: joint(),
                axis: j.axis.into(),
            });
        }
        let placement = j.x_tree.r.iter().chain(j.x_tree.e.iter());
        if !j.inertia.is_finite() || !placement.into_iter().all(|x| x.is_finite()) {
            return Err(ModelFault::JointNumbers { joint: joint() });
        }
        if !names.insert(j.name.as_str()) {
            return Err(ModelFault::DuplicateJoint(joint()));
        }
    }
    Ok(())
}

/// Every rotor drives an existing joint, one per joint, with a unit axis
/// and finite numbers; returns each joint's rotor.
fn check_rotors(joints: &[Joint], rotors: &[Rotor]) -> Result<Vec<Option<usize>>, ModelFault> {
    let mut rotor_of = vec![None; joints.len()];
    for (k, r) in rotors.iter().enumerate() {
        if r.joint >= joints.len() {
            return Err(ModelFault::RotorJoint {
                rotor: r.name.clone(),
                joint: r.joint,
                joints: joints.len(),
            });
        }
        if rotor_of[r.joint].is_some() {
            return Err(ModelFault::TwoRotors(joints[r.joint].name.clone()));
        }
        if !((r.axis.norm() - 1.0).abs() < 1e-9)
            || !r.gear_ratio.is_finite()
            || !r.inertia.is_finite()
        {
            return Err(ModelFault::RotorNumbers(r.name.clone()));
        }
        rotor_of[r.joint] = Some(k);
    }
    Ok(rotor_of)
}

/// Link and rotor bodies have distinct names (parameter files name them).
fn check_body_names(joints: &[Joint], rotors: &[Rotor]) -> Result<(), ModelFault> {
    let mut bodies = std::collections::HashSet::with_capacity(joints.len() + rotors.len());
    let names = joints
        .iter()
        .map(|j| &j.body)
        .chain(rotors.iter().map(|r| &r.name));
    for b in names {
        if !bodies.insert(b.as_str()) {
            return Err(ModelFault::DuplicateBody(b.clone()));
        }
    }
    Ok(())
}
