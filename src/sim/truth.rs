//! The simulated "true robot": the robot description's model with its own
//! parameters as the truth, to which effects add what a real robot has and
//! a nominal model may lack.
//!
//! `sim` provides the mechanisms and knows no effect by name: a [`Truth`]
//! starts as the description's links with no rotor, no friction and an
//! ideal sensor, and an effect (a [`crate::effects::Effect`], which says
//! how it is applied) changes it through the methods below: the rotors,
//! an inertia added to a body, the friction law's coefficients, an
//! additive per-joint torque term, a torque gain, a delay between state and
//! torque, an encoder offset, a compliant transmission. [`Truth::build`]
//! gives the [`TrueRobot`] that [`super::simulate_with`] samples.

use super::compliance::Compliance;
use super::effects::Effects;
use super::error::SimError;
use super::warning::SimWarning;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Friction, Joint, Model, RobotDescription, Samples};
use crate::moments::InertialParams;
use std::sync::Arc;

/// One joint's state as an additive torque term sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointState {
    /// The joint's index (model order).
    pub joint: usize,
    /// Its true position (rad or m; after an encoder offset).
    pub q: f64,
    /// Its velocity (rad/s or m/s).
    pub qd: f64,
    /// The time since the record began (s).
    pub t: f64,
    /// The gear ratio N of its rotor (1 without one).
    pub gear: f64,
}

/// An additive torque (N·m, or N) on one joint, from its state.
pub type TorqueTerm = Arc<dyn Fn(&JointState) -> f64 + Send + Sync>;

/// What effects set on a true robot besides its bodies.
#[derive(Clone)]
struct Parts {
    friction: Friction,
    terms: Vec<TorqueTerm>,
    gain: f64,
    delay: f64,
    position_offset: Vec<f64>,
    compliance: Option<Compliance>,
    warnings: Vec<SimWarning>,
}

/// The true robot being built ([`Truth::build`]).
pub struct Truth<'r> {
    robot: &'r RobotDescription,
    joints: Vec<Joint>,
    rotors: bool,
    parts: Parts,
}

impl<'r> Truth<'r> {
    /// The description's links with their own parameters; no rotor, no
    /// friction, no other effect.
    pub fn new(robot: &'r RobotDescription) -> Self {
        let n = robot.model.dof();
        Self {
            robot,
            joints: robot.model.joints.clone(),
            rotors: false,
            parts: Parts {
                friction: Friction::zeros(n),
                terms: vec![],
                gain: 1.0,
                delay: 0.0,
                position_offset: vec![0.0; n],
                compliance: None,
                warnings: vec![],
            },
        }
    }

    /// The robot description (nominal friction, tool point, rotors, …).
    pub fn robot(&self) -> &'r RobotDescription {
        self.robot
    }

    /// The description's rotors are part of the true robot.
    pub fn include_rotors(&mut self) {
        self.rotors = true;
    }

    /// Adds `p` to link `body`'s inertia (its body frame; a joint index).
    pub fn add_inertia(&mut self, body: usize, p: &InertialParams) -> Result<(), SimError> {
        let n = self.joints.len();
        let j = self
            .joints
            .get_mut(body)
            .ok_or(SimError::Body { body, bodies: n })?;
        j.inertia = j.inertia.plus(p);
        Ok(())
    }

    /// Scales every link's 10 parameters by `factor` (> 0 keeps them
    /// physically consistent).
    pub fn scale_link_inertias(&mut self, factor: f64) {
        for j in &mut self.joints {
            j.inertia = InertialParams(j.inertia.0.map(|v| v * factor));
        }
    }

    /// The friction law's coefficients of the true robot (zero until an
    /// effect sets them).
    pub fn friction_mut(&mut self) -> &mut Friction {
        &mut self.parts.friction
    }

    /// Adds a torque term to every joint's torque (applied in the order
    /// added, after the rigid-body torque and the friction).
    pub fn add_torque(&mut self, term: impl Fn(&JointState) -> f64 + Send + Sync + 'static) {
        self.parts.terms.push(Arc::new(term));
    }

    /// The measured torque is `gain` × the true one (ideal: 1).
    pub fn set_gain(&mut self, gain: f64) {
        self.parts.gain = gain;
    }

    /// The torque is measured at the state `delay` seconds earlier.
    pub fn set_delay(&mut self, delay: f64) {
        self.parts.delay = delay;
    }

    /// Every encoder reads its joint `delta` short of the true position
    /// (true q = measured q + δ; rad or m).
    pub fn offset_positions(&mut self, delta: f64) {
        self.parts
            .position_offset
            .iter_mut()
            .for_each(|d| *d = delta);
    }

    /// The links are driven through this compliant transmission.
    pub fn set_compliance(&mut self, c: Compliance) {
        self.parts.compliance = Some(c);
    }

    /// Records a warning about the true robot (an effect that changes
    /// nothing, …).
    pub fn warn(&mut self, w: SimWarning) {
        self.parts.warnings.push(w);
    }

    /// The true robot; `effects` is the record of what built it (the
    /// simulation checks it is its configuration's).
    pub fn build(self, effects: Effects) -> Result<TrueRobot, SimError> {
        let model = &self.robot.model;
        let gear = (0..model.dof())
            .map(|i| model.rotor_of(i).map_or(1.0, |r| r.gear_ratio))
            .collect();
        let rotors = if self.rotors {
            model.rotors.clone()
        } else {
            vec![]
        };
        let mut m = Model::new(&model.name, self.joints, rotors, model.gravity)?;
        m.frames = model.frames.clone();
        m.tool = model.tool;
        Ok(TrueRobot {
            model: m,
            effects,
            parts: self.parts,
            gear,
        })
    }
}

/// The true robot: a model (with or without rotors) and its effects.
#[derive(Clone)]
pub struct TrueRobot {
    model: Model,
    effects: Effects,
    parts: Parts,
    gear: Vec<f64>,
}

impl std::fmt::Debug for TrueRobot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TrueRobot")
            .field("model", &self.model.name)
            .field("effects", &self.effects)
            .field("terms", &self.parts.terms.len())
            .finish_non_exhaustive()
    }
}

impl TrueRobot {
    /// The record of the effects it was built with.
    pub fn effects(&self) -> &Effects {
        &self.effects
    }

    /// What the effects reported while it was built.
    pub fn warnings(&self) -> &[SimWarning] {
        &self.parts.warnings
    }

    /// The compliance of the transmission, if any.
    pub fn compliance(&self) -> Option<Compliance> {
        self.parts.compliance
    }

    /// The measured-torque gain (1: ideal).
    pub fn gain(&self) -> f64 {
        self.parts.gain
    }

    /// The delay (s) the trajectory must be sampled with for the torques.
    pub fn delay(&self) -> f64 {
        self.parts.delay
    }

    /// The link side of the true robot driven through a compliant
    /// transmission (payload included; rotor housings welded to the links
    /// they are mounted on, rotor spin on the motor side): [`Model::link_side`].
    pub fn links_model(&self) -> Model {
        self.model.link_side()
    }

    /// Torques at the given states (already shifted by the delay if any),
    /// all at the record's start (a term that drifts with time at its
    /// initial value): [`Self::torques_at`].
    pub fn torques(&self, q: &Samples, qd: &Samples, qdd: &Samples) -> Result<Samples, SimError> {
        self.torques_at(&vec![0.0; q.len()], q, qd, qdd)
    }

    /// Torques at the given states (already shifted by the delay if any)
    /// and times `t` (s since the record began, one per sample): the
    /// rigid-body torque at the true positions plus the friction, then
    /// every torque term in order, times the gain.
    pub fn torques_at(
        &self,
        t: &[f64],
        q: &Samples,
        qd: &Samples,
        qdd: &Samples,
    ) -> Result<Samples, SimError> {
        let (n, p) = (self.model.dof(), &self.parts);
        if t.len() != q.len() {
            return Err(SimError::Times {
                times: t.len(),
                samples: q.len(),
            });
        }
        let shifted: Samples;
        let q = if p.position_offset.iter().any(|d| *d != 0.0) {
            // the encoders read q − δ: the robot is really at q + δ
            let mut s = q.clone();
            for r in s.iter_mut() {
                r.iter_mut()
                    .zip(&p.position_offset)
                    .for_each(|(x, d)| *x += d);
            }
            shifted = s;
            &shifted
        } else {
            q
        };
        let mut tau = predict_torques(&self.model, &p.friction, q, qd, qdd)?;
        for (k, row) in tau.iter_mut().enumerate() {
            for i in 0..n {
                let s = JointState {
                    joint: i,
                    q: q[k][i],
                    qd: qd[k][i],
                    t: t[k],
                    gear: self.gear[i],
                };
                for term in &p.terms {
                    row[i] += term(&s);
                }
                row[i] *= p.gain;
            }
        }
        Ok(tau)
    }
}
