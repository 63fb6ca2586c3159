//! # `diagnose`: where the sim-to-real gap lies and which effect explains it
//!
//! Given a nominal model (parameters + friction) and measured data, the data
//! are cut into folds (files, else blocks of time; [`folds`]). **Where:**
//! the held-out residual `τ − τ̂` per joint, by motion regime, position,
//! frequency band and time, with whiteness and cross-correlation checks
//! ([`where_`]). **Which:** every effect of the candidate library (an
//! [`crate::effects::Library`], the built-in one by default) proposes an
//! addition to the current model ([`crate::effects::Effect::hypothesis`]);
//! each is refit with the nominal friction law and the effects accepted
//! before it on the other folds and scored on the fold left out
//! ([`rule`]: every fold improves, a block test, materiality against the
//! noise floor, a gain per parameter). Forward selection with backward
//! elimination accepts the best, adds it, and repeats; candidates within
//! noise of it are reported as tied, with what would separate them.
//! **How far:** held-out RMS per joint as given, with the law refit and
//! with the accepted effects, the share of the gap above the noise floor
//! that is closed, and whether a remainder is left unexplained.
//!
//! See `docs/diagnosis.md` for the method in full and the confusion table
//! of the withheld-effect benchmark.

mod alias;
mod build;
mod candidate;
mod check;
mod choose;
mod conclude;
mod cv;
mod error;
mod final_fit;
pub mod floating;
pub mod floor;
pub mod folds;
mod forward;
mod heldout;
mod implausible;
mod law;
mod memory;
mod model_out;
mod nominal_data;
mod options;
mod reestimate;
mod refine;
mod refit;
mod report;
pub mod rule;
mod score;
mod split;
mod store;
mod warning;
pub mod where_;

pub use error::{DiagnoseError, FitError};
pub use floor::{FloorSource, NoiseFloor};
pub use memory::{MemoryEstimate, OptionalGroup, memory_estimate};
pub use options::{DEFAULT_MAX_MEMORY_BYTES, DiagnoseOptions};
pub use report::{Diagnosis, EffectReport, HeldOut, Reestimate, SizeReport, Tie};
pub use warning::DiagnoseWarning;

use crate::data::Dataset;
use crate::dynamics::params_file::FittedEffect;
use crate::dynamics::{Friction, Model};
use crate::effects::Context;
use folds::Folds;
use heldout::{residual_of, where_of};
use law::Law;
use split::Split;
use store::Store;
use where_::JointWhere;

pub use check::MIN_SAMPLES;
use check::check_data;

/// The noise floor given in `opts` (one per joint, else an error), else
/// the residual's first differences, naming the joints where they are a
/// lower bound (a low-passed residual).
fn noise_floor(opts: &DiagnoseOptions, where_: &[JointWhere]) -> Result<NoiseFloor, DiagnoseError> {
    if let Some(f) = opts.noise_floor() {
        if f.per_joint.len() != where_.len() {
            return Err(DiagnoseError::NotRepeats {
                why: format!(
                    "a floor of {} joints for data of {}",
                    f.per_joint.len(),
                    where_.len()
                ),
            });
        }
        return Ok(f.clone());
    }
    Ok(NoiseFloor {
        per_joint: where_.iter().map(|w| w.noise_floor).collect(),
        source: FloorSource::FirstDifferences {
            low_passed: (where_.iter().filter(|w| w.low_passed))
                .map(|w| w.joint.clone())
                .collect(),
        },
    })
}

/// Diagnoses `data` against the nominal `model` + `friction` with the
/// effects of `opts.library()`: where the gap lies, which effects explain
/// it (forward selection over cross-validated refits: each candidate with
/// the nominal friction law and the effects accepted before it), how far
/// they close it on the held-out part, and their sizes.
pub fn diagnose(
    model: &Model,
    friction: &Friction,
    data: &Dataset,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    diagnose_with((model, friction, &[]), data, opts)
}

/// [`diagnose`] of a nominal model with fitted effects (a model file a
/// diagnosis wrote): they are part of the nominal model, held as they are
/// like its bodies, and carried into the diagnosis' model.
pub fn diagnose_with(
    nominal: (&Model, &Friction, &[FittedEffect]),
    data: &Dataset,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    let (model, friction, _) = nominal;
    check_data(model, data)?;
    let n = model.dof();
    let mut warnings = vec![];
    let est = memory_estimate(opts.library(), model, data.len());
    let left_out = memory::plan(&est, opts.max_memory(), &mut warnings)?;
    let folds = Folds::new(data, opts.folds(), opts.train_fraction());
    let split = Split::at(data.len(), n, folds.first_heldout());
    let r_nominal = residual_of(nominal, data, opts.library())?;
    let where_nominal = where_of(&split, data, &r_nominal);
    let floor = noise_floor(opts, &where_nominal)?;
    let mut store = Store::new(r_nominal.clone(), n, &folds);
    let law = Law::new(model, friction, data, &mut store).map_err(DiagnoseError::Predict)?;
    let cx = Context::new(model, friction, data, &r_nominal, folds.first_heldout());
    let law = match opts.nominal_data() {
        Some(own) => {
            let prior = nominal_data::prior(nominal, own, data, opts.library())?;
            let cols = (cx.regressor_columns(model.params().len(), |y, i, c| y[(i, c)]))
                .map_err(DiagnoseError::Effects)?;
            law.with_bodies((cols, &model.params()), prior, &mut store)
        }
        None => law,
    };
    let candidates = build::candidates(
        opts.library(),
        &cx,
        (&left_out, &law),
        &mut store,
        &mut warnings,
    );
    let setup = forward::Setup {
        store: &store,
        folds: &folds,
        law: &law.group,
        candidates: &candidates,
        names: &data.joints,
        floor: &floor.per_joint,
        repeats: matches!(floor.source, FloorSource::Repeats { .. }),
        max_effects: opts.max_effects(),
        blocks: opts.blocks(),
        model,
    };
    let selected =
        forward::forward_selection(&setup, &mut warnings).map_err(|source| DiagnoseError::Fit {
            what: "the selection",
            source,
        })?;
    conclude::Conclude {
        setup: &setup,
        law: &law,
        data,
        split: &split,
        nominal,
        r_nominal: &r_nominal,
        library: opts.library(),
    }
    .report(selected, where_nominal, floor.clone(), warnings)
}
