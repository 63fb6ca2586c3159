//! The simulated "true robot": the description's model with its own
//! parameters as the truth, plus switchable effects the nominal model may
//! lack (their terms and parameters: [`crate::dynamics::effect`]). Every
//! effect is off by default. Friction magnitudes come from the robot
//! description's nominal friction, the payload sits at the model's tool
//! point, and every other magnitude is the description's default unless
//! overridden.

use super::compliance::Compliance;
use super::error::SimError;
use crate::dynamics::effect::parse_override;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{
    DynamicsError, Effect, EffectParams, Model, Param, RobotDescription, params_file::Friction,
    sign,
};
use crate::moments::InertialParams;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Which effects are on, and the magnitudes the user set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Effects {
    /// Effects switched on, in the order given.
    pub on: Vec<Effect>,
    /// Overrides of the robot's default magnitudes.
    pub overrides: BTreeMap<Param, f64>,
}

impl Effects {
    /// These effects, with the robot's default magnitudes.
    pub fn new(on: impl IntoIterator<Item = Effect>) -> Self {
        let mut e = Self::default();
        for x in on {
            if !e.on.contains(&x) {
                e.on.push(x);
            }
        }
        e
    }

    /// Parses `a,b,c` and `NAME=VALUE` overrides. An unknown effect or
    /// parameter name is an error listing the valid ones; so is a parameter
    /// of an effect that is not on, and a value outside its range.
    pub fn parse(list: &str, overrides: &[String]) -> Result<Self, DynamicsError> {
        let on = list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(str::parse)
            .collect::<Result<Vec<Effect>, _>>()?;
        let mut e = Self::new(on);
        for o in overrides {
            let (p, v) = parse_override(o)?;
            e = e.with(p, v)?;
        }
        Ok(e)
    }

    /// Overrides one magnitude (checked: in range, and its effect is on).
    pub fn with(mut self, p: Param, v: f64) -> Result<Self, DynamicsError> {
        if !p.effects().iter().any(|x| self.has(*x)) {
            return Err(DynamicsError::Override {
                text: format!("{p}={v}"),
                message: format!(
                    "belongs to {}, which is not switched on",
                    p.effects()
                        .iter()
                        .map(|e| e.name())
                        .collect::<Vec<_>>()
                        .join(" / ")
                ),
            });
        }
        EffectParams::default().set(p, v)?;
        self.overrides.insert(p, v);
        Ok(self)
    }

    /// Whether an effect is on.
    pub fn has(&self, e: Effect) -> bool {
        self.on.contains(&e)
    }

    /// The magnitudes: `defaults` (a robot description's) with the overrides.
    pub fn params(&self, defaults: &EffectParams) -> Result<EffectParams, DynamicsError> {
        let mut p = defaults.clone();
        for (&k, &v) in &self.overrides {
            p.set(k, v)?;
        }
        Ok(p)
    }
}

/// The true robot: a model (with or without rotors) plus effects.
#[derive(Clone, Debug)]
pub struct TrueRobot {
    model: Model,
    effects: Effects,
    params: EffectParams,
    friction: Friction,
    gear: Vec<f64>,
}

impl TrueRobot {
    /// Builds the robot for `robot` (its model's own parameters are the truth).
    pub fn new(robot: &RobotDescription, effects: &Effects) -> Result<Self, SimError> {
        let model = &robot.model;
        let params = effects.params(&robot.effects)?;
        let n = model.dof();
        let gear: Vec<f64> = (0..n)
            .map(|i| model.rotor_of(i).map_or(1.0, |r| r.gear_ratio))
            .collect();
        let mut joints = model.joints.clone();
        if effects.has(Effect::Payload) {
            let tool = model.tool.ok_or_else(|| SimError::Setting {
                setting: "payload",
                value: params.payload_mass,
                message: "the model has no moving body to carry it".into(),
            })?;
            let p = InertialParams::from_mass_com_inertia(
                params.payload_mass,
                tool.point,
                nalgebra::Matrix3::zeros(),
            );
            joints[tool.body].inertia = joints[tool.body].inertia.plus(&p);
        }
        let rotors = if effects.has(Effect::RotorInertia) {
            model.rotors.clone()
        } else {
            vec![]
        };
        let mut m = Model::new(&model.name, joints, rotors, model.gravity)?;
        m.frames = model.frames.clone();
        m.tool = model.tool;
        let scale = |v: &[f64], s: f64| v.iter().map(|c| c * s).collect::<Vec<f64>>();
        let friction = Friction {
            viscous: scale(&robot.friction.viscous, params.viscous_scale),
            coulomb: scale(&robot.friction.coulomb, params.coulomb_scale),
        };
        Ok(Self {
            model: m,
            effects: effects.clone(),
            params,
            friction,
            gear,
        })
    }

    /// Effects that are on but change nothing (a friction effect whose
    /// nominal friction is zero on every joint).
    pub fn warnings(&self) -> Vec<String> {
        let mut w = vec![];
        for (e, v) in [
            (Effect::Coulomb, &self.friction.coulomb),
            (Effect::Viscous, &self.friction.viscous),
            (Effect::AsymmetricFriction, &self.friction.coulomb),
        ] {
            if self.effects.has(e) && v.iter().all(|x| *x == 0.0) {
                w.push(format!(
                    "effect '{e}' is on but the robot's nominal friction it scales is zero on every joint"
                ));
            }
        }
        w
    }

    /// The effects.
    pub fn effects(&self) -> &Effects {
        &self.effects
    }

    /// The magnitudes in use.
    pub fn params(&self) -> &EffectParams {
        &self.params
    }

    /// The compliance of the transmission, when `elasticity` or `backlash` is on.
    pub fn compliance(&self) -> Option<Compliance> {
        let e = &self.effects;
        let p = &self.params;
        (e.has(Effect::Elasticity) || e.has(Effect::Backlash)).then(|| Compliance {
            stiffness: p.stiffness,
            damping: p.damping,
            backlash: if e.has(Effect::Backlash) {
                p.backlash_width
            } else {
                0.0
            },
        })
    }

    /// The measured-torque gain `1 + ε` (1 without `torque_gain`).
    pub fn gain(&self) -> f64 {
        if self.effects.has(Effect::TorqueGain) {
            1.0 + self.params.gain_error
        } else {
            1.0
        }
    }

    /// The link side of the true robot driven through a compliant
    /// transmission (payload included; rotor housings welded to the links
    /// they are mounted on, rotor spin on the motor side): [`Model::link_side`].
    pub fn links_model(&self) -> Model {
        self.model.link_side()
    }

    /// The delay (s) the trajectory must be sampled with for the torques.
    pub fn delay(&self) -> f64 {
        if self.effects.has(Effect::TimeDelay) {
            self.params.delay
        } else {
            0.0
        }
    }

    /// The friction the true robot has (nominal, scaled; zero where the
    /// effect is off).
    fn friction_on(&self) -> Friction {
        let n = self.model.dof();
        let on = |e: Effect, v: &[f64]| {
            if self.effects.has(e) {
                v.to_vec()
            } else {
                vec![0.0; n]
            }
        };
        Friction {
            viscous: on(Effect::Viscous, &self.friction.viscous),
            coulomb: on(Effect::Coulomb, &self.friction.coulomb),
        }
    }

    /// Adds the per-joint effect terms of joint i to its torque `t`.
    fn add_terms(&self, t: &mut f64, i: usize, q: f64, v: f64) {
        let (e, p) = (&self.effects, &self.params);
        if e.has(Effect::Stribeck) {
            *t += p.stribeck_force * (-(v / p.stribeck_velocity).powi(2)).exp() * sign(v);
        }
        if e.has(Effect::AsymmetricFriction) {
            *t += p.asymmetry * self.friction.coulomb[i] * sign(v).abs();
        }
        if e.has(Effect::Offset) {
            *t += p.offset;
        }
        if e.has(Effect::Cogging) {
            *t += p.cogging_amplitude * (p.cogging_period * self.gear[i] * q).sin();
        }
    }

    /// Torques at the given states (already shifted by the delay if any).
    pub fn torques(
        &self,
        q: &[Vec<f64>],
        qd: &[Vec<f64>],
        qdd: &[Vec<f64>],
    ) -> Result<Vec<Vec<f64>>, SimError> {
        let n = self.model.dof();
        let shifted: Vec<Vec<f64>>;
        let q = if self.effects.has(Effect::JointOffset) {
            // the encoders read q − δ: the robot is really at q + δ
            let d = self.params.joint_offset;
            shifted = q
                .iter()
                .map(|r| r.iter().map(|x| x + d).collect())
                .collect();
            &shifted[..]
        } else {
            q
        };
        let mut tau = predict_torques(&self.model, &self.friction_on(), q, qd, qdd)?;
        let gain = self.gain();
        for (k, t) in tau.iter_mut().enumerate() {
            for i in 0..n {
                self.add_terms(&mut t[i], i, q[k][i], qd[k][i]);
                t[i] *= gain;
            }
        }
        Ok(tau)
    }
}
