//! # `identify`: physically consistent identification, the paper's SDP (25)
//!
//! [`identify`] reduces the stacked regressor of the training data to a
//! p × p factor ([`reduce`]), assembles (25) at the chosen constraint levels
//! ([`Identification`], open to the caller's constraints; [`IdentifyOptions`]
//! for one level and a prior), solves it ([`solve_identification`]) through
//! [`conic`](crate::conic) with LMIs from [`moments`](crate::moments),
//! checks every body with `moments`, and validates on held-out data.
//!
//! Files: `options` (levels, regulariser, options, tolerances), `error`,
//! `warning`, `reduce`, `identifiability` (rank, base parameters, standard deviations), `bounds` (each parameter's range over the models that fit), `builder` (assembling), `robot_facts` (a robot's
//! set-up), `solved` (the answer, by name), `solve` (solving), `fit`
//! (the end-to-end identification), `result` (its report), `stream` (training logs
//! reduced while they are read), `weighting` (per-joint
//! weighted least squares), `choose_weight` (the prior's weight by
//! cross-validation), `cutoff` (a raw log's low-pass by held-out torque
//! error), `friction_choice` (the friction law and weight chosen),
//! `choice_pass` (its one pass over the data, whence the chosen law's
//! reduction), `law_scores` (a law's held-out errors from that pass),
//! `load_rows` and `load_passes` (a load term's passes from kept rows).

pub mod bounds;
mod builder;
mod choice_pass;
pub mod choose_weight;
pub mod cutoff;
mod error;
mod fit;
pub mod fleet;
pub mod floating;
pub mod floating_fit;
pub mod friction_choice;
mod gram;
pub mod identifiability;
mod law_scores;
mod load_passes;
mod load_rows;
mod options;
pub mod planned;
mod pullback;
pub mod reduce;
pub mod repeats;
pub mod result;
mod robot_facts;
mod solve;
mod solved;
pub mod stream;
mod warning;
pub mod weighting;

pub use bounds::{Margin, ParamRange, ParameterBounds, PinnedBy, confidence_delta, marginal_delta};
pub use builder::{Identification, Vars};
pub use choose_weight::{WEIGHT_GRID, WeightChoice};
pub use error::{GramProblem, IdentifyError};
pub use fit::{LOAD_PASSES, identify};
pub use floating::{Rows, reduce_floating, reduce_floating_weighted};
pub use identifiability::{BaseParameter, Identifiability};
pub use options::{CHECK_TOL, IdentifyOptions, Level, Regularizer, default_settings};
pub use reduce::{Cost, Reduced, StreamReducer, cost, reduce_samples};
pub use result::{
    BodyResult, Contributions, DEGENERATE_ADVICE, DataPreparation, Degenerate, IdentifyResult,
    Timings, predict_split, rms,
};
pub use solve::solve_identification;
pub use solved::{Solved, parameter_names};
pub use stream::{StreamedLogs, reduce_logs};
pub use warning::IdentifyWarning;
pub use weighting::JointWeighting;
