//! The values an effect is applied with ([`Values`]), and the range check
//! of one value.

use super::error::EffectError;
use super::params::ParamSpec;
use std::collections::BTreeMap;

/// `value` if `spec`'s range admits it, else the error naming the parameter.
pub fn checked(spec: &ParamSpec, value: f64) -> Result<f64, EffectError> {
    if spec.range.admits(value) {
        Ok(value)
    } else {
        Err(EffectError::OutOfRange {
            param: spec.name,
            value,
            range: spec.range,
        })
    }
}

/// The values of the parameters one effect is applied with: every one it
/// declares, after the robot's defaults and the user's overrides.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Values {
    effect: String,
    values: BTreeMap<&'static str, f64>,
}

impl Values {
    /// The values of `effect`'s parameters.
    pub fn new(effect: &str, values: impl IntoIterator<Item = (&'static str, f64)>) -> Self {
        Self {
            effect: effect.to_string(),
            values: values.into_iter().collect(),
        }
    }

    /// The value of the parameter `name` (an error if the effect does not
    /// declare it).
    pub fn get(&self, name: &str) -> Result<f64, EffectError> {
        self.values
            .get(name)
            .copied()
            .ok_or_else(|| EffectError::Undeclared {
                effect: self.effect.clone(),
                param: name.to_string(),
            })
    }
}
