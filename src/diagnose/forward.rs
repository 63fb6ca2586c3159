//! Forward selection: each round scores every candidate not yet accepted
//! against the current residual and accepts the chosen one (updating the
//! residual) until nothing is significant.

use super::candidate::Candidate;
use super::options::DiagnoseOptions;
use super::report::EffectReport;
use super::select::{Evaluation, choose, evaluate};
use super::split::Split;
use super::warning::DiagnoseWarning;
use crate::data::rms_per_joint;
use rayon::prelude::*;

/// What the selection ends with.
pub struct Selected {
    /// Every round's reports, the accepted one first in its round.
    pub ranked: Vec<EffectReport>,
    /// The accepted effects, in order.
    pub accepted: Vec<String>,
    /// The residual with them (sample-major).
    pub residual: Vec<f64>,
}

/// Forward selection over `candidates` from the residual `r`.
pub fn forward_selection(
    candidates: &[Candidate],
    mut r: Vec<f64>,
    split: &Split,
    opts: &DiagnoseOptions,
    names: &[String],
    warnings: &mut Vec<DiagnoseWarning>,
) -> Selected {
    let mut ranked = vec![];
    let mut accepted: Vec<String> = vec![];
    for round in 1..=opts.max_effects() {
        let before = rms_per_joint(&r[split.heldout.clone()], split.joints);
        let mut evals = score(
            candidates,
            &accepted,
            (split, &r),
            (round, opts.blocks()),
            names,
            warnings,
        );
        let Some((chosen, tied)) = choose(&mut evals, &before) else {
            ranked.extend(evals.into_iter().map(|e| e.report));
            break;
        };
        let tied_names = tied
            .iter()
            .map(|&j| evals[j].report.effect.clone())
            .collect();
        let e = &mut evals[chosen];
        if let Some(why) = &e.report.implausible {
            warnings.push(DiagnoseWarning::AcceptedDoubtful {
                round,
                effect: e.report.effect.clone(),
                why: why.clone(),
            });
        }
        e.report.accepted = true;
        e.report.tied_with = tied_names;
        r = e.after.clone();
        accepted.push(e.report.effect.clone());
        ranked.push(e.report.clone());
        ranked.extend(
            evals
                .into_iter()
                .enumerate()
                .filter(|(j, _)| *j != chosen)
                .map(|(_, e)| e.report),
        );
    }
    Selected {
        ranked,
        accepted,
        residual: r,
    }
}

/// Every candidate not yet accepted, scored in parallel against `r`; the
/// warnings kept in the candidates' order.
fn score(
    candidates: &[Candidate],
    accepted: &[String],
    (split, r): (&Split, &[f64]),
    round_blocks: (usize, usize),
    names: &[String],
    warnings: &mut Vec<DiagnoseWarning>,
) -> Vec<Evaluation> {
    let scored: Vec<(Option<Evaluation>, Vec<DiagnoseWarning>)> = candidates
        .par_iter()
        .filter(|c| !accepted.iter().any(|a| a == c.name()))
        .map(|c| {
            let mut w = vec![];
            (evaluate(c, split, r, round_blocks, names, &mut w), w)
        })
        .collect();
    let mut evals = vec![];
    for (e, w) in scored {
        warnings.extend(w);
        evals.extend(e);
    }
    evals
}
