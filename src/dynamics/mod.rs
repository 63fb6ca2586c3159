//! # `dynamics`: kinematic trees with geared rotors
//!
//! A [`Model`] (constant: joints, bodies, rotors, gravity, and its root
//! joint: fixed, or a free flyer as Pinocchio's `JointModelFreeFlyer`,
//! [`RootJoint`]) and a [`Data`]
//! (per-evaluation buffers, [`Data::new`]) in Pinocchio's split; every
//! algorithm has the shape `algo(&model, &mut data, q, …)` and allocates
//! nothing per call (the batch regressor allocates one `Data` per chunk).
//!
//! - [`rnea`]: inverse dynamics, links and rotors;
//! - [`crba`]: the mass matrix; [`forward_dynamics`]; [`energy`];
//! - [`regressor`]: `τ = Y π + Σ_t c_t φ_t(q̇)` with columns for every link
//!   and rotor and per-joint friction ([`friction`]: the one friction law); [`regressor_batch`] over many samples;
//! - [`RobotDescription`]: a model plus everything else known about the
//!   robot (prior, bounding ellipsoids, nominal friction, excitation, default
//!   effect magnitudes by name), from [`robots::load_robot`] for the built-in leg
//!   ([`cheetah3`]) and for a URDF ([`urdf`]) + [`sidecar`] alike;
//!
//! Frames: body i's frame is its joint frame after the joint's motion;
//! inertial parameters are in that frame (paper order, see
//! [`InertialParams`](crate::moments::InertialParams)). A rotor of joint i is
//! mounted on joint i's parent body and spins about its own axis at
//! `N q̇ᵢ` (Cheetah 3: N = 10.6).

mod bounding;
mod crba;
mod data;
mod description;
mod error;
mod fault;
mod free_flyer;
mod free_flyer_dynamics;
pub mod friction;
mod layout;
pub mod leg_kinematics;
mod model;
pub mod params_file;
pub mod predict;
mod random_states;
mod rates;
mod regressor;
mod rnea;
pub mod robots;
mod samples;
pub mod sidecar;
pub mod spatial;
pub mod urdf;
mod warning;

pub use bounding::Bounding;
pub use crba::{crba, energy, forward_dynamics, transform_matrix};
pub use data::{BodyRegressor, Data};
pub use description::{IdentificationFacts, ParamChoice, RobotDescription, total_mass_refusal};
pub use error::DynamicsError;
pub use fault::ModelFault;
pub use free_flyer::{BaseState, QUATERNION_TOLERANCE};
pub use free_flyer_dynamics::{ContactWrench, WrenchFrame};
pub use friction::{DEFAULT_STRIBECK_VELOCITY, Friction, FrictionTerm, sign};
pub use layout::ParamLayout;
pub use model::{BaseBody, Frame, Joint, JointKind, Model, RootJoint, Rotor, ToolPoint};
pub use random_states::random_states;
pub use rates::JointRates;
pub use regressor::{
    body_regressor, regressor, regressor_batch, regressor_blocks, regressor_row_columns,
};
pub use rnea::rnea;
pub use robots::cheetah3;
pub use samples::{RowIter, Samples};
pub use warning::DescriptionWarning;
