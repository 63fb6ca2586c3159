//! The simulated "true robot": the model's rigid-body torques plus
//! switchable effects the nominal model may lack. Every effect is off by
//! default; each adds a documented term to the joint torque (i = joint,
//! q̇ᵢ in rad/s, N the gear ratio, sign(0) = 0):
//!
//! | effect | term | parameters (default) |
//! |---|---|---|
//! | `rotor_inertia` | the rotors are part of the robot (else links only) | — |
//! | `coulomb` | `B_c,i sign(q̇ᵢ)` | `coulomb_scale` (1: the robot's B_c; cheetah3-leg (3.12, 1.25, 0.95) N·m, others 0.5 N·m) |
//! | `viscous` | `B_i q̇ᵢ` | `viscous` (0.1 N·m·s/rad) |
//! | `stribeck` | `F_s e^{−(q̇ᵢ/v_s)²} sign(q̇ᵢ)` | `stribeck_force` (1.0 N·m), `stribeck_velocity` (0.2 rad/s) |
//! | `asymmetric_friction` | `a B_c,i \|sign(q̇ᵢ)\|` (Coulomb (1 + a)·B_c forward, (1 − a)·B_c backward) | `asymmetry` (0.3) |
//! | `offset` | `cᵢ` | `offset` (0.5 N·m) |
//! | `payload` | a point mass at the foot / last body's origin, in the dynamics | `payload_mass` (0.5 kg) |
//! | `time_delay` | the torque is that of the state at `t − δ` | `delay` (0.005 s) |
//! | `cogging` | `A sin(p N qᵢ)` | `cogging_amplitude` (0.2 N·m), `cogging_period` p (6 per motor turn) |
//! | `torque_gain` | measured `(1 + ε) τ` | `gain_error` ε (0.1) |
//!
//! | `elasticity` | the links are driven through a spring–damper from the motor side ([`super::compliance`]) | `stiffness` (2000 N·m/rad), `damping` (5 N·m·s/rad) |
//! | `backlash` | as elasticity, with a dead band of half-width b | `backlash_width` b (0.005 rad), and the two above |

use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Model, cheetah3, params_file::Friction, sign};
use crate::moments::InertialParams;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The effects the simulator knows.
pub const EFFECTS: [&str; 12] = [
    "rotor_inertia",
    "coulomb",
    "viscous",
    "stribeck",
    "asymmetric_friction",
    "offset",
    "payload",
    "time_delay",
    "cogging",
    "torque_gain",
    "elasticity",
    "backlash",
];

/// Effects not implemented yet (accepted names that are rejected with a message).
pub const NOT_YET: [&str; 0] = [];

fn default_param(name: &str) -> Option<f64> {
    Some(match name {
        "coulomb_scale" => 1.0,
        "viscous" => 0.1,
        "stribeck_force" => 1.0,
        "stribeck_velocity" => 0.2,
        "asymmetry" => 0.3,
        "offset" => 0.5,
        "payload_mass" => 0.5,
        "delay" => 0.005,
        "cogging_amplitude" => 0.2,
        "cogging_period" => 6.0,
        "gain_error" => 0.1,
        "stiffness" => 2000.0,
        "damping" => 5.0,
        "backlash_width" => 0.005,
        _ => return None,
    })
}

/// Which effects are on and their parameters (documented in the module).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Effects {
    /// Effects switched on.
    pub on: Vec<String>,
    /// Parameter overrides by name.
    pub params: BTreeMap<String, f64>,
}

impl Effects {
    /// Parses `a,b,c` and `NAME=VALUE` overrides, rejecting unknown names.
    pub fn parse(list: &str, overrides: &[String]) -> Result<Self, String> {
        let mut on = Vec::new();
        for e in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            if NOT_YET.contains(&e) {
                return Err(format!(
                    "effect '{e}' is not implemented yet (it needs a state-carrying simulation)"
                ));
            }
            if !EFFECTS.contains(&e) {
                return Err(format!(
                    "unknown effect '{e}' (known: {})",
                    EFFECTS.join(", ")
                ));
            }
            if !on.iter().any(|x| x == e) {
                on.push(e.to_string());
            }
        }
        let mut params = BTreeMap::new();
        for o in overrides {
            let (k, v) = o
                .split_once('=')
                .ok_or_else(|| format!("effect parameter '{o}': expected NAME=VALUE"))?;
            let k = k.trim();
            if default_param(k).is_none() {
                return Err(format!("unknown effect parameter '{k}'"));
            }
            let v: f64 = v
                .trim()
                .parse()
                .map_err(|_| format!("effect parameter '{k}': '{v}' is not a number"))?;
            if !v.is_finite() {
                return Err(format!("effect parameter '{k}': not finite"));
            }
            params.insert(k.to_string(), v);
        }
        Ok(Self { on, params })
    }

    /// Whether an effect is on.
    pub fn has(&self, e: &str) -> bool {
        self.on.iter().any(|x| x == e)
    }

    /// A parameter (override or default).
    pub fn param(&self, name: &str) -> f64 {
        self.params
            .get(name)
            .copied()
            .or_else(|| default_param(name))
            .unwrap_or(0.0)
    }
}

/// The true robot: a model (with or without rotors) plus effects.
#[derive(Clone, Debug)]
pub struct TrueRobot {
    model: Model,
    effects: Effects,
    coulomb: Vec<f64>,
    gear: Vec<f64>,
}

impl TrueRobot {
    /// Builds the robot for `model` (its own parameters are the truth).
    pub fn new(model: &Model, effects: Effects) -> Result<Self, String> {
        let n = model.dof();
        let gear: Vec<f64> = (0..n)
            .map(|i| model.rotor_of(i).map_or(1.0, |r| r.gear_ratio))
            .collect();
        let mut joints = model.joints.clone();
        if effects.has("payload") {
            let m = effects.param("payload_mass");
            let last = n - 1;
            let at = if model.name == "cheetah3-leg" {
                Vector3::from(cheetah3::FOOT)
            } else {
                Vector3::zeros()
            };
            let p = InertialParams::from_mass_com_inertia(m, at, nalgebra::Matrix3::zeros());
            joints[last].inertia = joints[last].inertia.plus(&p);
        }
        let rotors = if effects.has("rotor_inertia") {
            model.rotors.clone()
        } else {
            vec![]
        };
        let m =
            Model::new(&model.name, joints, rotors, model.gravity).map_err(|e| e.to_string())?;
        let base: Vec<f64> = if model.name == "cheetah3-leg" {
            cheetah3::COULOMB.to_vec()
        } else {
            vec![0.5; n]
        };
        let coulomb = base
            .iter()
            .map(|c| c * effects.param("coulomb_scale"))
            .collect();
        Ok(Self {
            model: m,
            effects,
            coulomb,
            gear,
        })
    }

    /// The effects.
    pub fn effects(&self) -> &Effects {
        &self.effects
    }

    /// The compliance of the transmission, when `elasticity` or `backlash` is on.
    pub fn compliance(&self) -> Option<super::compliance::Compliance> {
        let e = &self.effects;
        (e.has("elasticity") || e.has("backlash")).then(|| super::compliance::Compliance {
            stiffness: e.param("stiffness"),
            damping: e.param("damping"),
            backlash: if e.has("backlash") {
                e.param("backlash_width")
            } else {
                0.0
            },
        })
    }

    /// The link side of the true robot driven through a compliant
    /// transmission (payload included; rotor housings welded to the links
    /// they are mounted on, rotor spin on the motor side): [`Model::link_side`].
    pub fn links_model(&self) -> Model {
        self.model.link_side()
    }

    /// The delay (s) the trajectory must be sampled with for the torques.
    pub fn delay(&self) -> f64 {
        if self.effects.has("time_delay") {
            self.effects.param("delay")
        } else {
            0.0
        }
    }

    /// Torques at the given states (already shifted by the delay if any).
    pub fn torques(
        &self,
        q: &[Vec<f64>],
        qd: &[Vec<f64>],
        qdd: &[Vec<f64>],
    ) -> Result<Vec<Vec<f64>>, String> {
        let n = self.model.dof();
        let e = &self.effects;
        let fr = Friction {
            viscous: vec![
                if e.has("viscous") {
                    e.param("viscous")
                } else {
                    0.0
                };
                n
            ],
            coulomb: if e.has("coulomb") {
                self.coulomb.clone()
            } else {
                vec![0.0; n]
            },
        };
        let mut tau = predict_torques(&self.model, &fr, q, qd, qdd).map_err(|e| e.to_string())?;
        for (k, t) in tau.iter_mut().enumerate() {
            for i in 0..n {
                let v = qd[k][i];
                if e.has("stribeck") {
                    let vs = e.param("stribeck_velocity");
                    t[i] += e.param("stribeck_force") * (-(v / vs).powi(2)).exp() * sign(v);
                }
                if e.has("asymmetric_friction") {
                    t[i] += e.param("asymmetry") * self.coulomb[i] * sign(v).abs();
                }
                if e.has("offset") {
                    t[i] += e.param("offset");
                }
                if e.has("cogging") {
                    t[i] += e.param("cogging_amplitude")
                        * (e.param("cogging_period") * self.gear[i] * q[k][i]).sin();
                }
                if e.has("torque_gain") {
                    t[i] *= 1.0 + e.param("gain_error");
                }
            }
        }
        Ok(tau)
    }
}
