//! What an identification reports without failing.

use serde::Serialize;
use std::fmt;

/// A warning of the identification (in [`super::IdentifyResult::warnings`]
/// and the JSON's `warnings`, each with a stable `kind`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum IdentifyWarning {
    /// The SDP was solved only to the solver's reduced tolerances.
    Inaccurate {
        /// Interior-point iterations.
        iterations: u32,
    },
    /// The masses' extra weight is on but not ≫ the Euclidean prior's
    /// weight, so it does not hold the masses.
    MassWeightLow {
        /// The masses' weight.
        mass_weight: f64,
        /// The prior's weight.
        weight: f64,
    },
    /// Bodies at the ellipsoid level whose prior is consistent but not
    /// density realizable in their bounding ellipsoid (`tr(J(π̂) Q) < 0`).
    PriorOutsideEllipsoid {
        /// The bodies.
        bodies: Vec<String>,
    },
    /// The load friction term's passes (each reduced with the previous
    /// solution's rigid torques as the load) stopped before the load
    /// settled.
    LoadNotSettled {
        /// Passes made.
        passes: usize,
        /// The last pass's change of the load, relative (RMS).
        change: f64,
    },
    /// The per-joint noise estimates of weighted least squares still
    /// moved by over 1 % after the passes allowed.
    WeightsNotSettled {
        /// Weighted solves made.
        passes: usize,
    },
    /// The friction law (and the prior's weight) were to be chosen from
    /// the data by default, but the training data could not score them
    /// (too few samples for the folds): the law the model names and the
    /// weight given instead were fitted.
    LawNotChosen {
        /// Why the laws could not be scored.
        reason: String,
        /// The law fitted instead.
        terms: Vec<String>,
        /// The prior's weight fitted instead.
        weight: f64,
    },
}

impl IdentifyWarning {
    /// [`IdentifyWarning::Inaccurate`] when the solve ended at the solver's
    /// reduced tolerances.
    pub fn of_status(status: crate::conic::Status, iterations: u32) -> Option<Self> {
        (status == crate::conic::Status::SolvedInaccurately)
            .then_some(IdentifyWarning::Inaccurate { iterations })
    }
}

impl fmt::Display for IdentifyWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IdentifyWarning::Inaccurate { iterations } => write!(
                f,
                "the SDP was solved only to Clarabel's reduced tolerances ({iterations} iterations)"
            ),
            IdentifyWarning::MassWeightLow {
                mass_weight,
                weight,
            } => write!(
                f,
                "the masses' extra weight {mass_weight:e} is not ≫ the prior's weight {weight:e} (ratio {}, under 100): the masses are not held at the prior's",
                (mass_weight / weight * 1e3).round() / 1e3
            ),
            IdentifyWarning::PriorOutsideEllipsoid { bodies } => write!(
                f,
                "the prior is not density realizable in the bounding ellipsoid of {} (tr(J(π̂) Q) < 0): the identified bodies cannot stay at the prior there (a check of the robot's URDF shows its CAD inertias against the geometry)",
                bodies.join(", ")
            ),
            IdentifyWarning::LoadNotSettled { passes, change } => write!(
                f,
                "the load friction's load (the rigid model's torque) still changed by {change:.1e} (relative RMS) after {passes} passes: its coefficients are approximate"
            ),
            IdentifyWarning::LawNotChosen {
                reason,
                terms,
                weight,
            } => write!(
                f,
                "the friction law was not chosen from the data ({reason}): {} at weight {weight:e} fitted instead (a law and a weight given are fitted as given)",
                terms.join(" + ")
            ),
            IdentifyWarning::WeightsNotSettled { passes } => write!(
                f,
                "the joints' noise estimates of the weighted least squares still moved by over 1 % after {passes} passes: the weights are approximate"
            ),
        }
    }
}
