//! # `excite`: which trajectory to run
//!
//! [`design`] designs a periodic Fourier-series excitation for any robot:
//! inside its joints' limits ([`limits`]), optimised for a criterion on the
//! base parameters' information matrix ([`information`]) by a compass
//! search (a derivative-free local search: each coefficient tried ± a step,
//! the step halved when none improves) from several random seeds in
//! parallel; optionally over a pool of random candidates, the convex
//! D- or E-optimal design ([`design::optimal_weights`], through `conic`)
//! bounds what mixing them could reach.
//!
//! [`separate`] designs, by the same search, a motion that tells two
//! effects apart (the diagnosis' ties): the smaller share of one's
//! predicted torques the other cannot fit, maximised.
//!
//! Files: `error`, `design` (convex pool design), `limits`, `information`,
//! `fourier` (the motion fitted into the limits), `report` (the design and
//! its samples), `separate` (two effects told apart) and `separation`
//! (what that gives).

pub mod design;
mod error;
pub mod fourier;
pub mod information;
pub mod limits;
mod report;
pub mod separate;
mod separation;

pub use design::{Criterion, PoolDesign, optimal_weights};
pub use error::ExciteError;
pub use information::{InfoBasis, condition_number, score};
pub use limits::{JointLimits, joint_limits};
pub use report::{Designed, PoolReport, design, samples};
pub use separate::{Separation, separate};

use serde::Serialize;

/// The settings of a design.
#[derive(Clone, Debug, Serialize)]
pub struct ExciteOptions {
    /// Length of the motion (s): a whole number of periods.
    pub seconds: f64,
    /// What is maximised.
    pub criterion: Criterion,
    /// Harmonics per joint.
    pub harmonics: usize,
    /// The wished base frequency (Hz); the period divides `seconds`.
    pub base_hz: f64,
    /// Random seeds searched from (in parallel).
    pub seeds: usize,
    /// The first seed.
    pub seed: u64,
    /// Candidates of the convex pool design (0: none).
    pub pool: usize,
    /// Criterion evaluations per seed.
    pub evaluations: usize,
}

impl Default for ExciteOptions {
    /// 10 s, D-optimal, 5 harmonics of 0.2 Hz, 8 seeds, no pool, 600
    /// evaluations per seed.
    fn default() -> Self {
        Self {
            seconds: 10.0,
            criterion: Criterion::D,
            harmonics: 5,
            base_hz: 0.2,
            seeds: 8,
            seed: 1,
            pool: 0,
            evaluations: 600,
        }
    }
}
