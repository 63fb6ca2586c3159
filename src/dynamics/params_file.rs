//! The model-parameter file (JSON): inertial parameters per body plus
//! friction. `identify --json` prints a superset of it; `predict --params`,
//! `identify --prior` and `diagnose --nominal` read it.
//!
//! ```json
//! { "robot": "cheetah3-leg",
//!   "joints": ["abad", "hip", "knee"],
//!   "parameter_order": "m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz",
//!   "bodies": [ { "name": "abad", "params": [10 numbers] }, … ],
//!   "friction": { "viscous": [n numbers], "coulomb": [n numbers] },
//!   "effects": [ { "effect": "torque_gain", "key": {}, "columns": ["hip#0"],
//!                  "coefficients": [0.05] } ] }
//! ```
//!
//! `effects` (optional) holds effects a diagnosis accepted that neither the
//! bodies nor the friction law can hold (a gain error, a delay, a ripple):
//! each its recorded variant and one coefficient per column, the columns
//! named by joint (`hip#0`: the joint's first column) or `all#k` for one
//! spanning every joint. This layer only carries them; the `effects`
//! layer builds their columns again to predict with them.

use super::error::{DynamicsError, read_text};
use super::friction::{Friction, FrictionTerm};
use super::model::Model;
use crate::moments::{InertialParams, MAX_ABS_PARAM};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One body's parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyParams {
    /// Body name (links by their URDF link name, rotors by their name).
    pub name: String,
    /// π in the paper's order.
    pub params: [f64; 10],
}

/// The file's content (unknown extra fields are ignored).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamsFile {
    /// Model name.
    pub robot: String,
    /// Joint names.
    pub joints: Vec<String>,
    /// The parameter order, stated.
    #[serde(default = "order")]
    pub parameter_order: String,
    /// Bodies.
    pub bodies: Vec<BodyParams>,
    /// Friction (absent: zero).
    #[serde(default)]
    pub friction: Friction,
    /// Effects beyond the bodies and the friction law (absent: none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<FittedEffect>,
}

/// An effect a diagnosis fitted, as a model file records it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FittedEffect {
    /// The effect's name in its library.
    pub effect: String,
    /// Its variant's nonlinear parameters (SI units).
    #[serde(default)]
    pub key: std::collections::BTreeMap<String, f64>,
    /// Its columns' names (`joint#k`, or `all#k`).
    pub columns: Vec<String>,
    /// One coefficient per column.
    pub coefficients: Vec<f64>,
}

fn order() -> String {
    "m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz".into()
}

impl FittedEffect {
    /// The effects' names, `a, b`: how a message names a file's effects.
    pub fn names(effects: &[FittedEffect]) -> String {
        (effects.iter())
            .map(|e| e.effect.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl ParamsFile {
    /// The parameters and friction currently in a model (a free-flying
    /// base's first, by its name).
    pub fn from_model(model: &Model, friction: Friction) -> Self {
        let p = model.params();
        Self {
            robot: model.name.clone(),
            joints: model.joints.iter().map(|j| j.name.clone()).collect(),
            parameter_order: order(),
            bodies: model
                .body_names()
                .into_iter()
                .enumerate()
                .map(|(k, name)| BodyParams {
                    name,
                    params: std::array::from_fn(|i| p[10 * k + i]),
                })
                .collect(),
            friction,
            effects: vec![],
        }
    }

    /// Reads a file.
    pub fn read(path: &Path) -> Result<Self, DynamicsError> {
        serde_json::from_str(&read_text(path)?).map_err(|e| DynamicsError::File {
            path: path.display().to_string(),
            message: format!("invalid parameter file: {e}"),
        })
    }

    /// Applies the parameters to `model` and returns the friction in the
    /// model's joint order. The file must be for this robot (`robot`), in
    /// the stated parameter order, with every body of the model exactly
    /// once and no other, each passing [`InertialParams::validate`];
    /// friction (missing: zeros) has one finite, non-negative number per
    /// joint, matched by the file's `joints` names.
    pub fn apply(&self, model: &mut Model, path: &str) -> Result<Friction, DynamicsError> {
        let err = |m: String| DynamicsError::File {
            path: path.into(),
            message: m,
        };
        self.check_header(&model.name).map_err(err)?;
        let p = self.body_params(&model.body_names()).map_err(err)?;
        model.set_params(&p)?;
        self.friction_of(&model.joint_names()).map_err(err)
    }

    /// The file is for robot `robot`, in the stated parameter order.
    fn check_header(&self, robot: &str) -> Result<(), String> {
        if self.robot != robot {
            return Err(format!(
                "parameters for robot '{}', but the model is '{robot}'",
                self.robot
            ));
        }
        if self.parameter_order.replace(' ', "") != order().replace(' ', "") {
            return Err(format!(
                "parameter_order '{}' is not '{}'",
                self.parameter_order,
                order()
            ));
        }
        Ok(())
    }

    /// The file's friction for the model's `joints` (absent: zeros).
    fn friction_of(&self, joints: &[&str]) -> Result<Friction, String> {
        let mut f = Friction::zeros(joints.len());
        for t in FrictionTerm::ALL {
            *f.coefficients_mut(t) = self.joint_values(self.friction.coefficients(t), t, joints)?;
        }
        if let Some(v) = self.friction.stribeck_velocity {
            if !(v.is_finite() && v > 0.0 && v <= MAX_ABS_PARAM) {
                return Err(format!(
                    "friction.stribeck_velocity = {v:e}: must be positive, ≤ {MAX_ABS_PARAM:e} rad/s"
                ));
            }
            f.stribeck_velocity = Some(v);
        }
        Ok(f)
    }

    /// The parameters of `names` in that order, each body exactly once.
    fn body_params(&self, names: &[String]) -> Result<Vec<f64>, String> {
        let mut by_name = std::collections::HashMap::with_capacity(self.bodies.len());
        for b in &self.bodies {
            if by_name.insert(b.name.as_str(), b).is_some() {
                return Err(format!("body '{}' appears twice", b.name));
            }
            if !names.contains(&b.name) {
                return Err(format!(
                    "body '{}' is not in the model (bodies: {})",
                    b.name,
                    names.join(", ")
                ));
            }
            InertialParams(b.params)
                .validate()
                .map_err(|e| format!("body '{}': {e}", b.name))?;
        }
        let mut p = Vec::with_capacity(10 * names.len());
        for n in names {
            let b = by_name
                .get(n.as_str())
                .ok_or_else(|| format!("no parameters for body '{n}'"))?;
            p.extend(b.params);
        }
        Ok(p)
    }

    /// One friction coefficient per model joint, matched by the file's
    /// joint names (absent: zeros).
    fn joint_values(
        &self,
        v: &[f64],
        term: FrictionTerm,
        joints: &[&str],
    ) -> Result<Vec<f64>, String> {
        let what = term.name();
        // an offset has either sign; the other coefficients are ≥ 0
        let low = if term.signed() { -MAX_ABS_PARAM } else { 0.0 };
        if v.is_empty() {
            return Ok(vec![0.0; joints.len()]);
        }
        if v.len() != self.joints.len() {
            return Err(format!(
                "friction.{what} has {} numbers for {} joints",
                v.len(),
                self.joints.len()
            ));
        }
        if let Some((j, x)) = self
            .joints
            .iter()
            .zip(v)
            .find(|(_, x)| !(x.is_finite() && (low..=MAX_ABS_PARAM).contains(*x)))
        {
            let range = if term.signed() { "|x|" } else { "≥ 0 and" };
            return Err(format!(
                "friction.{what} of joint '{j}' = {x}: must be finite, {range} ≤ {MAX_ABS_PARAM:e}"
            ));
        }
        joints
            .iter()
            .map(|j| {
                let k = self.joints.iter().position(|n| n == j).ok_or_else(|| {
                    format!(
                        "joint '{j}' of the model is not in the file's joints ({})",
                        self.joints.join(", ")
                    )
                })?;
                Ok(v[k])
            })
            .collect()
    }
}
