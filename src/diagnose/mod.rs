//! # `diagnose`: where the sim-to-real gap lies and which effect explains it
//!
//! Given a nominal model (parameters + friction) and measured data, the data
//! are split in time (training first, held-out last). **Where:** the
//! held-out residual `τ − τ̂` per joint, by motion regime, position,
//! frequency band and time, with whiteness and cross-correlation checks
//! ([`where_`]). **Which:** every effect of the candidate library (an
//! [`crate::effects::Library`], the built-in one by default) proposes an
//! addition to the current model ([`crate::effects::Effect::hypothesis`]),
//! fitted on the training part only; it is scored by its held-out RMS reduction, a block
//! test on the held-out part (robust to correlated residuals) and ΔBIC on
//! the training part. Forward selection accepts the best significant one,
//! adds it, and repeats. Candidates within noise of the best are reported
//! as tied. **How far:** held-out RMS per joint before and after, the share
//! of the gap above the noise floor that is closed, and whether a remainder
//! is left unexplained.
//!
//! See `docs/diagnosis.md` for the method in full and the confusion table
//! of the withheld-effect benchmark.

mod alias;
mod build;
mod candidate;
mod carry;
mod error;
mod fit;
pub mod floating;
pub mod floor;
mod forward;
mod memory;
mod options;
mod report;
mod screen;
mod select;
mod split;
mod warning;
pub mod where_;

pub use error::{DiagnoseError, FitError};
pub use floor::{FloorSource, NoiseFloor};
pub use memory::{MemoryEstimate, OptionalGroup, memory_estimate};
pub use options::{DEFAULT_MAX_MEMORY_BYTES, DiagnoseOptions};
pub use report::{Diagnosis, EffectReport, HeldOut};
pub use warning::DiagnoseWarning;

use crate::data::Dataset;
use crate::data::rms_per_joint;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Friction, Model};
use crate::effects::Context;
use split::Split;
use where_::{JointWhere, Sampling, analyse_joint, summarise};

/// The fewest samples a diagnosis takes.
pub const MIN_SAMPLES: usize = 100;

/// Samples per second within the segments: one over the median step
/// between samples of one segment (a gap between files is not a step).
fn sampling_rate(data: &Dataset) -> f64 {
    let mut steps: Vec<f64> = (data.segment_ranges().into_iter())
        .flat_map(|s| {
            data.t[s]
                .windows(2)
                .map(|w| w[1] - w[0])
                .collect::<Vec<_>>()
        })
        .collect();
    if steps.is_empty() {
        return 1.0;
    }
    let mid = steps.len() / 2;
    let (_, m, _) = steps.select_nth_unstable_by(mid, f64::total_cmp);
    1.0 / *m
}

/// The where-analysis of every joint's held-out residual.
fn where_of(split: &Split, data: &Dataset, r: &[f64]) -> Vec<JointWhere> {
    let val = data.slice(split.first_heldout..split.samples);
    let segments = val.segment_ranges();
    let sampling = Sampling {
        fs: sampling_rate(data),
        segments: &segments,
    };
    (0..split.joints)
        .map(|i| {
            let col = |v: &crate::dynamics::Samples| v.column(i);
            analyse_joint(
                &data.joints[i],
                &split.heldout_of(r, i),
                &col(&val.q),
                &col(&val.qd),
                &col(&val.qdd),
                &col(&val.tau),
                &sampling,
            )
        })
        .collect()
}

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

/// Share of the gap above the noise floor closed, per joint, in [0, 1]
/// (1 where the nominal model is already at the floor).
fn gap_closed(nominal: &[f64], last: &[f64], floor: &[f64]) -> Vec<f64> {
    (0..nominal.len())
        .map(|i| {
            if nominal[i] > floor[i] {
                ((nominal[i] - last[i]) / (nominal[i] - floor[i])).clamp(0.0, 1.0)
            } else {
                1.0
            }
        })
        .collect()
}

/// The held-out signals and residuals, per joint, for plots.
fn held_out(split: &Split, data: &Dataset, nominal: &[f64], after: &[f64]) -> HeldOut {
    let val = data.slice(split.first_heldout..split.samples);
    let n = split.joints;
    let per_joint = |r: &[f64]| (0..n).map(|i| split.heldout_of(r, i)).collect();
    HeldOut {
        t: val.t.clone(),
        q: (0..n)
            .map(|i| val.q.iter().map(|x| x[i]).collect())
            .collect(),
        qd: (0..n)
            .map(|i| val.qd.iter().map(|x| x[i]).collect())
            .collect(),
        nominal: per_joint(nominal),
        after: per_joint(after),
    }
}

/// Checks that `data` can be diagnosed against `model`: enough samples
/// with torques, the model's joints, some motion.
fn check_data(model: &Model, data: &Dataset) -> Result<(), DiagnoseError> {
    if data.tau.len() != data.len() || data.len() < MIN_SAMPLES {
        return Err(DiagnoseError::TooFewSamples {
            needed: MIN_SAMPLES,
            found: if data.tau.len() == data.len() {
                data.len()
            } else {
                0
            },
        });
    }
    let names: Vec<String> = model.joint_names().iter().map(|s| s.to_string()).collect();
    if data.joints != names {
        return Err(DiagnoseError::Joints {
            expected: names,
            found: data.joints.clone(),
        });
    }
    let n = model.dof();
    if (0..n).all(|i| data.q.iter().all(|q| q[i] == data.q[0][i])) {
        return Err(DiagnoseError::NoMotion);
    }
    Ok(())
}

/// The nominal model's residual `τ − τ̂`, sample-major.
fn nominal_residual(
    model: &Model,
    friction: &Friction,
    data: &Dataset,
) -> Result<Vec<f64>, DiagnoseError> {
    let pred = predict_torques(model, friction, &data.q, &data.qd, &data.qdd)
        .map_err(DiagnoseError::Predict)?;
    Ok(data
        .tau
        .iter()
        .flatten()
        .zip(pred.iter().flatten())
        .map(|(a, b)| a - b)
        .collect())
}

/// Diagnoses `data` against the nominal `model` + `friction` with the
/// effects of `opts.library()`: where the gap lies, which effects explain
/// it (forward selection), how far they close it.
pub fn diagnose(
    model: &Model,
    friction: &Friction,
    data: &Dataset,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    check_data(model, data)?;
    let n = model.dof();
    let mut warnings = vec![];
    let est = memory_estimate(opts.library(), model, data.len());
    let left_out = memory::plan(&est, opts.max_memory(), &mut warnings)?;
    let split = Split::new(data.len(), n, opts.train_fraction());
    let r_nominal = nominal_residual(model, friction, data)?;
    let where_nominal = where_of(&split, data, &r_nominal);
    let floor = noise_floor(opts, &where_nominal)?;
    let noise_floor = floor.per_joint.clone();
    let nominal = rms_per_joint(&r_nominal[split.heldout.clone()], n);
    let cx = Context::new(model, friction, data, &r_nominal, split.first_heldout);
    let library = build::candidates(opts.library(), &cx, &left_out, &split.train, &mut warnings);
    let selected = forward::forward_selection(
        &library,
        r_nominal.clone(),
        &split,
        opts,
        &data.joints,
        &mut warnings,
    );
    let r = &selected.residual;
    let final_rms = rms_per_joint(&r[split.heldout.clone()], n);
    let numbers = [&nominal, &final_rms, &noise_floor];
    if let Some(k) = numbers
        .iter()
        .position(|v| !v.iter().all(|x| x.is_finite()))
    {
        return Err(DiagnoseError::NonFinite {
            what: ["the nominal RMS", "the final RMS", "the noise floor"][k],
        });
    }
    let unexplained: Vec<usize> = (0..n)
        .filter(|&i| final_rms[i] > 1.15 * noise_floor[i] && final_rms[i] - noise_floor[i] > 0.05)
        .collect();
    let where_final = where_of(&split, data, r);
    Ok(Diagnosis {
        joints: data.joints.clone(),
        summary: where_nominal.iter().map(summarise).collect(),
        where_: where_nominal,
        ranked_effects: selected.ranked,
        accepted: selected.accepted,
        gap_closed: gap_closed(&nominal, &final_rms, &noise_floor),
        heldout_rms_nominal: nominal,
        heldout_rms_final: final_rms,
        noise_floor,
        noise_floor_source: floor.source,
        unexplained: !unexplained.is_empty(),
        unexplained_where: unexplained
            .iter()
            .map(|&i| summarise(&where_final[i]))
            .collect(),
        warnings,
        heldout: held_out(&split, data, &r_nominal, r),
    })
}
