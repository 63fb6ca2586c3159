//! # `sim`: a simulated robot and its data
//!
//! - [`trajectory`]: the paper's shell excitation (cheetah3-leg, through
//!   inverse kinematics) and a multi-sine for any robot;
//! - [`robot`]: the "true robot" with switchable effects ([`Effects`] of
//!   [`crate::dynamics::Effect`]);
//! - [`simulate`](mod@simulate): measurement noise, encoder quantisation and the
//!   offline zero-phase filtering and differentiation, with a JSON record;
//!
//! The data format itself (CSV, filter, differentiator) is [`crate::data`].

pub mod compliance;
mod error;
pub mod robot;
pub mod simulate;
pub mod trajectory;

pub use error::SimError;
pub use robot::{Effects, TrueRobot};
pub use simulate::{SimConfig, simulate};
