//! The residuals of the nominal model and of the diagnosis' model on the
//! held-out part, and what the report derives from them: where the gap
//! lies, the share of it closed, the signals for plots.

use super::error::DiagnoseError;
use super::report::HeldOut;
use super::split::Split;
use super::where_::{JointWhere, Sampling, analyse_joint};
use crate::data::Dataset;
use crate::dynamics::params_file::FittedEffect;
use crate::dynamics::{Friction, Model};
use crate::effects::Library;
use crate::effects::fitted::predict_with;

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
pub fn where_of(split: &Split, data: &Dataset, r: &[f64]) -> Vec<JointWhere> {
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

/// Share of the gap above the noise floor closed, per joint, in [0, 1]
/// (1 where the nominal model is already at the floor).
pub fn gap_closed(nominal: &[f64], last: &[f64], floor: &[f64]) -> Vec<f64> {
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
pub fn held_out(split: &Split, data: &Dataset, nominal: &[f64], after: &[f64]) -> HeldOut {
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

/// The residual `τ − τ̂` of `model` + `friction` + fitted `effects` (of
/// `library`) on `data`, sample-major.
pub fn residual_of(
    (model, friction, effects): (&Model, &Friction, &[FittedEffect]),
    data: &Dataset,
    library: &Library,
) -> Result<Vec<f64>, DiagnoseError> {
    let pred = predict_with(model, friction, effects, data, library).map_err(|e| match e {
        crate::effects::EffectError::Dynamics(e) => DiagnoseError::Predict(e),
        e => DiagnoseError::Effects(e),
    })?;
    Ok(data
        .tau
        .iter()
        .flatten()
        .zip(pred.iter().flatten())
        .map(|(a, b)| a - b)
        .collect())
}

/// The held-out part's residual `part` put in place of `r`'s.
pub fn with_heldout(r: &[f64], split: &Split, part: &[f64]) -> Vec<f64> {
    let mut out = r.to_vec();
    out[split.heldout.clone()].copy_from_slice(part);
    out
}
