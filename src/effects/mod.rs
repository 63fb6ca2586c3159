//! # `effects`: what a real robot has and a nominal model may lack
//!
//! An effect (Coulomb friction, a payload, a time delay, backlash, a
//! user's own cable spring, …) is one implementation of the [`Effect`]
//! trait, which says everything about it:
//!
//! - its parameters ([`ParamSpec`]: name, unit, meaning, nominal value,
//!   range), which a robot's sidecar `[effects]` table and `NAME=VALUE`
//!   overrides change;
//! - how the simulator's true robot has it ([`Effect::apply`] on a
//!   [`crate::sim::Truth`], through the mechanisms `sim` provides);
//! - how a diagnosis looks for it in a residual ([`Effect::hypothesis`]:
//!   regressor columns where it is linear in its magnitudes, a grid of
//!   variants over a nonlinear parameter, or a search by simulation — the
//!   transmission's compliance, [`compliance`]), what the hypothesis costs
//!   in memory, when its fit is physically doubtful and its line in the
//!   report.
//!
//! A [`Library`] is an ordered list of effects: [`Library::builtin`] (one
//! file per effect in `src/effects/builtin/`, one line each in its
//! registry) plus any the user adds ([`Library::add`]). Names resolve
//! against it ([`Library::check`]), the simulator applies it
//! ([`Library::simulate`]; [`simulate`] with the built-in library) and the
//! diagnosis proposes it ([`crate::diagnose::DiagnoseOptions::with_library`]).
//!
//! Layers: `effects` is a client of `dynamics`, `data` and `sim`; the
//! diagnosis is its client.

pub mod builtin;
pub mod compliance;
mod context;
mod effect;
mod error;
pub mod fitted;
mod hypothesis;
mod library;
mod params;
mod size;
mod values;

pub use context::Context;
pub use effect::Effect;
pub use error::EffectError;
pub use hypothesis::{Columns, Hypothesis, Memory, Part, Shape};
pub use library::Library;
pub use params::{MAX_ABS_EFFECT, ParamSpec, Range};
pub use size::{Size, SizeContext};
pub use values::Values;

use crate::data::Dataset;
use crate::dynamics::RobotDescription;
use crate::sim::SimConfig;

/// Simulates `robot` with the built-in effects that `cfg.effects` names
/// ([`Library::simulate`] of [`Library::builtin`]).
pub fn simulate(
    robot: &RobotDescription,
    cfg: &SimConfig,
    progress: impl FnMut(usize, usize),
) -> Result<Dataset, EffectError> {
    Library::builtin().simulate(robot, cfg, progress)
}
