//! # `sim`: a simulated robot and its data
//!
//! - [`trajectory`]: the paper's shell excitation (cheetah3-leg, through
//!   inverse kinematics) and a multi-sine for any robot;
//! - [`robot`]: the "true robot" with switchable effects;
//! - [`simulate`](mod@simulate): measurement noise, encoder quantisation and the
//!   offline zero-phase filtering and differentiation, with a JSON record;
//! - [`dataset`]: the CSV data format with validation;
//! - [`filter`]: zero-phase Butterworth low-pass and differentiation.

pub mod compliance;
pub mod dataset;
pub mod filter;
pub mod robot;
pub mod simulate;
pub mod trajectory;

pub use dataset::{DataError, Dataset, ReadOptions};
pub use robot::{Effects, TrueRobot};
pub use simulate::{SimConfig, simulate};
