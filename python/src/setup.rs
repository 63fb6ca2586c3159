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
    /// None: the command line's default (entropic for a strictly
    /// consistent prior when the weight is chosen, else Euclidean).
    pub regularizer: Option<Regularizer>,
    /// The weight is chosen from the data.
    pub weight_chosen: bool,
}

impl Setup {
    /// `weight`: `None` when it is to be chosen (by cross-validation).
    pub fn parse(
        constraints: &str,
        regularizer: Option<&str>,
        weight: Option<f64>,
    ) -> PyResult<Self> {
        let level = Level::parse(constraints).ok_or_else(|| {
            let m = format!(
                "constraints: '{constraints}' is not one of none, semi, consistent, ellipsoid"
            );
            PyValueError::new_err(m)
        })?;
        let regularizer = match regularizer {
            None => None,
            Some("euclidean") => Some(Regularizer::Euclidean),
            Some("entropic") => Some(Regularizer::Entropic),
            Some("pullback") => Some(Regularizer::Pullback),
            Some(r) => {
                let m = format!("regularizer: '{r}' is not one of euclidean, entropic, pullback");
                return Err(PyValueError::new_err(m));
            }
        };
        if let Some(w) = weight
            && (!(w.is_finite() && w >= 0.0)
                || (regularizer == Some(Regularizer::Entropic) && w <= 0.0))
        {
            let m = format!("weight: {w} (≥ 0; > 0 with the entropic regulariser)");
            return Err(PyValueError::new_err(m));
        }
        Ok(Self {
            level,
            regularizer,
            weight_chosen: weight.is_none(),
        })
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
        let regularizer = match self.regularizer {
            Some(r) => r,
            None if self.weight_chosen => {
                Regularizer::for_chosen_weight(&prior.params(), self.level)
            }
            None => Regularizer::Euclidean,
        };
        Ok(id.regularizer(regularizer))
    }
}
