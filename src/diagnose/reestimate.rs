//! Which coefficients of the nominal friction law the data move: those
//! whose refit value's 95 % interval (a block jackknife over the fitting
//! part) leaves out the nominal value, and whose change is material — the
//! torque it makes, `|Δc| · RMS(φ)` on its joint, reaches the square root
//! of the acceptance rule's threshold there ([`super::rule`]).

use super::cv::cross_validate;
use super::error::FitError;
use super::forward::{Accepted, Setup, base};
use super::law::Law;
use super::report::{Reestimate, SizeReport};
use super::rule::Rule;
use crate::data::rms_per_joint;

/// The moved coefficients of `law`, with their refit values `refit` (one
/// per law column, from the final fit).
pub fn reestimates(
    s: &Setup,
    law: &Law,
    accepted: &[Accepted],
    refit: &[SizeReport],
) -> Result<Vec<Reestimate>, FitError> {
    let n = s.store.joints();
    let cv = cross_validate(s.store, s.folds, &base(&law.group, accepted), &[])?;
    let mse: Vec<f64> = rms_per_joint(&cv.resid, n).iter().map(|x| x * x).collect();
    let rule = Rule::new(s.floor, s.repeats, &mse);
    let moved = (law.labels.iter().enumerate())
        .filter_map(|(c, &(term, i))| {
            let (nominal, r) = (law.nominal[c], &refit[c]);
            let col = &s.store.col(law.group.ids[c]).values;
            let rms = (col.iter().map(|x| x * x).sum::<f64>() / (col.len() / n).max(1) as f64).sqrt();
            let torque = (r.value - nominal).abs() * rms;
            let outside = nominal < r.low || nominal > r.high;
            let need = rule.material[i].sqrt();
            (outside && torque >= need).then(|| Reestimate {
                term: term.name().into(),
                joint: s.names[i].clone(),
                nominal,
                refit: r.clone(),
                rule: format!(
                    "its 95 % interval leaves out the nominal value, and the change makes {torque:.3} N·m RMS on {}, {:.1}× the square root of the rule's threshold there",
                    s.names[i],
                    torque / need.max(1e-300)
                ),
            })
        })
        .collect();
    Ok(moved)
}
