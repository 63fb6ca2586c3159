//! # `sim`: a simulated robot and its data
//!
//! - [`trajectory`]: the paper's shell excitation (cheetah3-leg, through
//!   inverse kinematics) and a multi-sine for any robot;
//! - [`truth`]: the "true robot" — the description's model plus what
//!   effects add to it (the mechanisms: rotors, inertia, friction, torque
//!   terms, gain, delay, encoder offset, compliance; the effects themselves
//!   and their names are [`crate::effects`]);
//! - [`effects`](mod@effects): the record of which effects are on ([`Effects`]);
//! - [`simulate`](mod@simulate): measurement noise, encoder quantisation and the
//!   offline zero-phase filtering and differentiation, with a JSON record;
//!
//! The data format itself (CSV, filter, differentiator) is [`crate::data`].

pub mod compliance;
pub mod effects;
mod error;
pub mod floating;
pub mod sampled;
pub mod simulate;
pub mod standing;
pub mod trajectory;
pub mod truth;
mod warning;

pub use effects::Effects;
pub use error::{OverrideProblem, SimError, TrajectoryProblem};
pub use sampled::SampledTrajectory;
pub use simulate::{SimConfig, simulate_with};
pub use truth::{JointState, TorqueTerm, TrueRobot, Truth};
pub use warning::SimWarning;
