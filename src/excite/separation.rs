//! What a motion designed to tell two effects apart gives
//! ([`super::separate`]).

use serde::Serialize;

/// Below this value two effects are reported as inseparable: no motion
/// found lets either show beyond the other's fit.
pub const INSEPARABLE: f64 = 1e-6;

/// What a separating motion gives.
#[derive(Clone, Debug, Serialize)]
pub struct Separation {
    /// The two effects.
    pub effects: [String; 2],
    /// The share of the first's predicted torques (mean over its unit
    /// columns) that the second cannot fit, on the motion.
    pub first_not_fitted_by_second: f64,
    /// The share of the second's that the first cannot fit.
    pub second_not_fitted_by_first: f64,
    /// The smaller of the two at the best random start (before the search).
    pub best_start: f64,
    /// Whether the motion separates them (the smaller share ≥
    /// [`INSEPARABLE`]); when not, one effect's columns lie within the
    /// other's on every motion searched (a payload on the last link within
    /// a change of that link's inertia).
    pub separable: bool,
}
