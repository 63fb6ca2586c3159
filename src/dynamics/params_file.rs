//! The model-parameter file (JSON): inertial parameters per body plus
//! friction. `identify --json` prints a superset of it; `predict --params`,
//! `identify --prior` and `diagnose --nominal` read it.
//!
//! ```json
//! { "robot": "cheetah3-leg",
//!   "joints": ["abad", "hip", "knee"],
//!   "parameter_order": "m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz",
//!   "bodies": [ { "name": "abad", "params": [10 numbers] }, … ],
//!   "friction": { "viscous": [n numbers], "coulomb": [n numbers] } }
//! ```

use super::error::{DynamicsError, read_text};
use super::model::Model;
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

/// Per-joint friction `B q̇ + B_c sign(q̇)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Friction {
    /// Viscous coefficients (N·m·s/rad).
    pub viscous: Vec<f64>,
    /// Coulomb coefficients (N·m).
    pub coulomb: Vec<f64>,
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
}

impl Friction {
    /// No friction on `n` joints.
    pub fn zeros(n: usize) -> Self {
        Self {
            viscous: vec![0.0; n],
            coulomb: vec![0.0; n],
        }
    }
}

fn order() -> String {
    "m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz".into()
}

impl ParamsFile {
    /// The parameters and friction currently in a model.
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
        }
    }

    /// Reads a file.
    pub fn read(path: &Path) -> Result<Self, DynamicsError> {
        serde_json::from_str(&read_text(path)?).map_err(|e| DynamicsError::File {
            path: path.display().to_string(),
            message: format!("invalid parameter file: {e}"),
        })
    }

    /// Applies the parameters to `model` (bodies matched by name; every body
    /// of the model must be present) and returns the friction, checked for
    /// length n (missing friction: zeros).
    pub fn apply(&self, model: &mut Model, path: &str) -> Result<Friction, DynamicsError> {
        let err = |m: String| DynamicsError::File {
            path: path.into(),
            message: m,
        };
        let names = model.body_names();
        let mut p = Vec::with_capacity(10 * names.len());
        for n in &names {
            let b = self
                .bodies
                .iter()
                .find(|b| &b.name == n)
                .ok_or_else(|| err(format!("no parameters for body '{n}'")))?;
            if b.params.iter().any(|x| !x.is_finite()) {
                return Err(err(format!("body '{n}': non-finite parameters")));
            }
            p.extend(b.params);
        }
        model.set_params(&p)?;
        let n = model.dof();
        let fix = |v: &Vec<f64>, what: &str| -> Result<Vec<f64>, DynamicsError> {
            match v.len() {
                0 => Ok(vec![0.0; n]),
                l if l == n && v.iter().all(|x| x.is_finite()) => Ok(v.clone()),
                l => Err(err(format!(
                    "friction.{what}: expected {n} finite numbers, found {l}"
                ))),
            }
        };
        Ok(Friction {
            viscous: fix(&self.friction.viscous, "viscous")?,
            coulomb: fix(&self.friction.coulomb, "coulomb")?,
        })
    }
}
