//! A joint's rate and effort limits: the sidecar's `[[joint]]`
//! `max_velocity`, `max_acceleration`, `max_effort`, else the URDF's
//! `<limit velocity effort>` (a zero there is "not given"). Position limits
//! are the model's ([`super::Joint::limits`]).

use super::error::DynamicsError;
use super::model::Model;
use super::sidecar::Sidecar;
use serde::Serialize;

/// One joint's rate and effort limits; `None`: not given.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct JointRates {
    /// Largest |q̇| (rad/s or m/s).
    pub velocity: Option<f64>,
    /// Largest |q̈| (rad/s² or m/s²).
    pub acceleration: Option<f64>,
    /// Largest |τ| (N·m or N).
    pub effort: Option<f64>,
}

/// Every joint's limits, in the model's joint order; a sidecar value that
/// is not positive and finite is an error naming the joint and the key.
pub(super) fn joint_rates(
    model: &Model,
    sidecar: &Sidecar,
    urdf: Option<&crate::urdf::Robot>,
    err: &impl Fn(String) -> DynamicsError,
) -> Result<Vec<JointRates>, DynamicsError> {
    let given = |v: f64| (v > 0.0 && v.is_finite()).then_some(v);
    model
        .joints
        .iter()
        .map(|j| {
            let side = sidecar.joints.iter().find(|s| s.name == j.name);
            let limit = urdf
                .and_then(|r| r.joints.iter().find(|u| u.name == j.name))
                .and_then(|u| u.limit);
            let pick = |key: &str, s: Option<f64>, u: Option<f64>| match s {
                Some(v) if given(v).is_none() => Err(err(format!(
                    "[[joint]] '{}': {key} = {v} must be positive and finite",
                    j.name
                ))),
                Some(v) => Ok(Some(v)),
                None => Ok(u.and_then(given)),
            };
            Ok(JointRates {
                velocity: pick(
                    "max_velocity",
                    side.and_then(|s| s.max_velocity),
                    limit.map(|l| l.velocity),
                )?,
                acceleration: pick(
                    "max_acceleration",
                    side.and_then(|s| s.max_acceleration),
                    None,
                )?,
                effort: pick(
                    "max_effort",
                    side.and_then(|s| s.max_effort),
                    limit.map(|l| l.effort),
                )?,
            })
        })
        .collect()
}
