//! # `identify`: physically consistent identification, the paper's SDP (25)
//!
//! [`identify`] reduces the stacked regressor of the training data to a
//! p × p factor ([`reduce`]), solves (25) at the chosen constraint level
//! ([`problem`]) through [`conic`](crate::conic) with LMIs from
//! [`moments`](crate::moments), checks every body with `moments`, and
//! validates on held-out data.

mod builder;
mod error;
pub mod problem;
pub mod reduce;
pub mod result;
mod robot_facts;

pub use builder::{Identification, Vars};
pub use error::IdentifyError;
pub use problem::{
    IdentifyOptions, Level, Regularizer, default_settings, parameter_names, solve_identification,
};
pub use reduce::{Cost, Reduced, StreamReducer, cost, reduce_samples};
pub use result::{BodyResult, Contributions, IdentifyResult, identify, predict_split, rms};
