//! The identification's set-up from Python's arguments, as the command
//! line makes it from its flags: the level, the regulariser, the weight
//! and the prior.

use momentlmi::dynamics::{ParamChoice, RobotDescription};
use momentlmi::identify::{Identification, Level, Regularizer};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// What `constraints`, `weight` and `regularizer` ask for, checked.
pub(crate) struct Setup {
    pub level: Level,
    pub regularizer: Regularizer,
}

impl Setup {
    /// `weight`: `None` when it is to be chosen (by cross-validation).
    pub fn parse(constraints: &str, regularizer: &str, weight: Option<f64>) -> PyResult<Self> {
        let level = Level::parse(constraints).ok_or_else(|| {
            let m = format!(
                "constraints: '{constraints}' is not one of none, semi, consistent, ellipsoid"
            );
            PyValueError::new_err(m)
        })?;
        let regularizer = match regularizer {
            "euclidean" => Regularizer::Euclidean,
            "entropic" => Regularizer::Entropic,
            r => {
                let m = format!("regularizer: '{r}' is not one of euclidean, entropic");
                return Err(PyValueError::new_err(m));
            }
        };
        if let Some(w) = weight
            && (!(w.is_finite() && w >= 0.0) || (regularizer == Regularizer::Entropic && w <= 0.0))
        {
            let m = format!("weight: {w} (≥ 0; > 0 with the entropic regulariser)");
            return Err(PyValueError::new_err(m));
        }
        Ok(Self { level, regularizer })
    }

    /// The identification of `robot` toward the `prior`'s parameters with `weight`.
    pub fn identification<'r>(
        &self,
        robot: &'r RobotDescription,
        prior: &ParamChoice,
        weight: f64,
    ) -> Result<Identification<'r>, String> {
        let (prior, _) = robot.parameters(prior).map_err(|e| format!("prior: {e}"))?;
        let id = Identification::for_robot(robot, self.level, weight)
            .and_then(|id| id.prior(weight, prior.params()))
            .map_err(|e| format!("weight / prior: {e}"))?;
        Ok(id.regularizer(self.regularizer))
    }
}
