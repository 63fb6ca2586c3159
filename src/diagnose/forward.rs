//! Forward selection: each round cross-validates the current model (the
//! nominal friction law refit, with the effects accepted so far refit with
//! it), scores every candidate not yet accepted against it, and accepts
//! the one [`choose`] picks among those the rule accepts, until none is.

use super::candidate::Candidate;
use super::choose::choose;
use super::cv::{Cv, cross_validate, sse, sse_on};
use super::error::FitError;
use super::folds::Folds;
use super::refit::Group;
use super::report::{EffectReport, Tie};
use super::rule::Rule;
use super::score::{Evaluation, Round};
use super::store::Store;
use super::warning::DiagnoseWarning;
use crate::data::rms_per_joint;
use rayon::prelude::*;

/// An accepted effect.
#[derive(Clone, Debug)]
pub struct Accepted {
    /// Its candidate.
    pub candidate: usize,
    /// The variant the whole data chose.
    pub variant: usize,
    /// Its columns on the joints kept, with its constraints.
    pub group: Group,
}

/// What the selection ends with.
pub struct Selected {
    /// Every round's reports, the accepted one first in its round.
    pub ranked: Vec<EffectReport>,
    /// The accepted effects, in order.
    pub accepted: Vec<Accepted>,
    /// The candidates removed by backward elimination: not proposed again
    /// (an effect added and removed in turn would never end).
    pub removed: Vec<usize>,
}

/// The selection's fixed inputs.
pub struct Setup<'a> {
    /// The columns.
    pub store: &'a Store,
    /// The folds.
    pub folds: &'a Folds,
    /// The nominal friction law's group.
    pub law: &'a Group,
    /// The candidates.
    pub candidates: &'a [Candidate],
    /// Joint names.
    pub names: &'a [String],
    /// The noise floor per joint.
    pub floor: &'a [f64],
    /// Whether it is the repeatability of repeated runs.
    pub repeats: bool,
    /// At most this many effects.
    pub max_effects: usize,
    /// Blocks of the block bootstrap.
    pub blocks: usize,
    /// The nominal model (for the sizes' names).
    pub model: &'a crate::dynamics::Model,
}

/// Forward selection over the candidates.
pub fn forward_selection(
    s: &Setup,
    warnings: &mut Vec<DiagnoseWarning>,
) -> Result<Selected, FitError> {
    let mut out = Selected {
        ranked: vec![],
        accepted: vec![],
        removed: vec![],
    };
    for number in 1..=s.max_effects {
        let round = round(s, &out.accepted, number)?;
        let mut evals = score(s, &round, (&out.accepted, &out.removed), warnings);
        let choice = choose(&evals);
        let mut reports: Vec<EffectReport> = evals.iter().map(|e| report(s, &round, e)).collect();
        let Some((chosen, tied)) = choice else {
            out.ranked.extend(reports);
            break;
        };
        let names: Vec<String> = tied.iter().map(|&j| reports[j].effect.clone()).collect();
        let ties = (tied.iter())
            .map(|&j| tie(s, &evals[chosen], &evals[j]))
            .collect();
        let r = &mut reports[chosen];
        r.accepted = true;
        r.tied_with = names;
        r.ties = ties;
        if let Some(why) = &r.implausible {
            warnings.push(DiagnoseWarning::AcceptedDoubtful {
                round: number,
                effect: r.effect.clone(),
                why: why.clone(),
            });
        }
        let e = evals.swap_remove(chosen);
        out.accepted.push(Accepted {
            candidate: e.candidate,
            group: e.groups[e.variant].clone(),
            variant: e.variant,
        });
        out.ranked.push(reports.swap_remove(chosen));
        out.ranked.extend(reports);
        backward(s, &mut out, number)?;
    }
    Ok(out)
}

/// Backward elimination after round `number`: an effect accepted earlier
/// that the rule no longer accepts beside the later ones — refit with
/// them, it no longer lowers every fold's error by enough (a torque gain
/// on two joints that a payload accepted after it explains on every
/// joint) — is removed, its report saying why; repeated until none is.
fn backward(s: &Setup, out: &mut Selected, number: usize) -> Result<(), FitError> {
    while out.accepted.len() > 1 {
        let with = cross_validate(s.store, s.folds, &base(s.law, &out.accepted), &[])?;
        let mut drop = None;
        for idx in 0..out.accepted.len() - 1 {
            let mut others = out.accepted.clone();
            let a = others.remove(idx);
            let round = round(s, &others, number)?;
            let c = &s.candidates[a.candidate];
            let params = a.group.ids.len() + c.variants[a.variant].columns.nonlinear;
            let scores = round.scores(&with, joints_of(c, &a, s.store.joints()));
            if let Err(why) = round.rule.verdict(&scores, params, s.folds, s.names) {
                drop = Some((idx, why));
                break;
            }
        }
        let Some((idx, why)) = drop else {
            return Ok(());
        };
        let a = out.accepted.remove(idx);
        out.removed.push(a.candidate);
        let name = s.candidates[a.candidate].name();
        if let Some(r) = out
            .ranked
            .iter_mut()
            .find(|r| r.accepted && r.effect == name)
        {
            r.accepted = false;
            r.removed = Some(format!(
                "removed after round {number}, refit with the effects accepted after it: {why}"
            ));
        }
    }
    Ok(())
}

/// What would separate the tied `b` from the accepted `a`: the joints where
/// their cross-validated predictions differ most and the motions that show
/// each.
fn tie(s: &Setup, a: &Evaluation, b: &Evaluation) -> Tie {
    let n = s.store.joints();
    let diff: Vec<f64> = (a.cv.resid.iter().zip(&b.cv.resid))
        .map(|(x, y)| x - y)
        .collect();
    let rms = rms_per_joint(&diff, n);
    let top = rms.iter().copied().fold(0.0, f64::max);
    let mut joints: Vec<usize> = (0..n).filter(|&i| rms[i] >= 0.5 * top).collect();
    joints.sort_by(|&x, &y| rms[y].total_cmp(&rms[x]));
    Tie {
        effect: s.candidates[b.candidate].name().to_string(),
        joints: joints.iter().map(|&i| s.names[i].clone()).collect(),
        difference_rms: rms,
        motions: [a, b].map(|e| s.candidates[e.candidate].effect.motion().to_string()),
    }
}

/// The joints an accepted effect is kept on.
fn joints_of(c: &Candidate, a: &Accepted, n: usize) -> Vec<usize> {
    let v = &c.variants[a.variant];
    if !c.per_joint() {
        return (0..n).collect();
    }
    let mut j: Vec<usize> = (a.group.ids.iter())
        .filter_map(|id| v.group.ids.iter().position(|x| x == id))
        .filter_map(|p| v.col_joints[p])
        .collect();
    j.sort_unstable();
    j.dedup();
    j
}

/// The groups of the current model: the law and the accepted effects.
pub fn base<'a>(law: &'a Group, accepted: &'a [Accepted]) -> Vec<&'a Group> {
    std::iter::once(law)
        .chain(accepted.iter().map(|a| &a.group))
        .collect()
}

/// Round `number`: the current model cross-validated, the rule's
/// thresholds for it, and every pair of columns its fits need kept.
fn round<'a>(s: &'a Setup, accepted: &'a [Accepted], number: usize) -> Result<Round<'a>, FitError> {
    let base = base(s.law, accepted);
    let ids: Vec<usize> = base.iter().flat_map(|g| g.ids.iter().copied()).collect();
    let pairs = (s.candidates.iter())
        .flat_map(|c| c.variants.iter())
        .flat_map(|v| {
            let own = v
                .group
                .ids
                .iter()
                .flat_map(|&a| v.group.ids.iter().map(move |&b| (a, b)));
            let with = v
                .group
                .ids
                .iter()
                .flat_map(|&a| ids.iter().map(move |&b| (a, b)));
            own.chain(with).collect::<Vec<_>>()
        })
        .chain(ids.iter().flat_map(|&a| ids.iter().map(move |&b| (a, b))));
    s.store.prepare(pairs);
    let without: Cv = cross_validate(s.store, s.folds, &base, &[])?;
    let inner_without = inner(s, &base)?;
    let n = s.store.joints();
    let sse_without = sse(s.folds, n, &without.resid);
    let mse = rms_per_joint(&without.resid, n)
        .iter()
        .map(|x| x * x)
        .collect::<Vec<_>>();
    Ok(Round {
        number,
        store: s.store,
        folds: s.folds,
        base,
        rule: Rule::new(s.floor, s.repeats, &mse),
        without,
        sse_without,
        names: s.names,
        blocks: s.blocks,
        inner_without,
    })
}

/// `[k][j][joint]`: `base` fitted on the folds but j and k, its sum of
/// squares on fold j (empty for j = k).
fn inner(s: &Setup, base: &[&Group]) -> Result<Vec<Vec<Vec<f64>>>, FitError> {
    let ids: Vec<usize> = base.iter().flat_map(|g| g.ids.iter().copied()).collect();
    let k = s.folds.len();
    (0..k)
        .map(|out| {
            (0..k)
                .map(|j| {
                    if j == out {
                        return Ok(vec![]);
                    }
                    let on: Vec<bool> = (0..k).map(|x| x != j && x != out).collect();
                    let f = super::cv::fit_with(s.store, base, None, &on)?;
                    Ok(sse_on(s.store, &ids, &f.beta, s.folds.ranges[j].clone()))
                })
                .collect()
        })
        .collect()
}

/// Every candidate neither accepted nor removed, scored in parallel; the warnings kept
/// in the candidates' order.
fn score(
    s: &Setup,
    round: &Round,
    (accepted, removed): (&[Accepted], &[usize]),
    warnings: &mut Vec<DiagnoseWarning>,
) -> Vec<Evaluation> {
    let taken = |j: usize| accepted.iter().any(|a| a.candidate == j) || removed.contains(&j);
    let scored: Vec<(Option<Evaluation>, Vec<DiagnoseWarning>)> = (0..s.candidates.len())
        .into_par_iter()
        .filter(|&j| !taken(j))
        .map(|j| {
            let mut w = vec![];
            (round.evaluate(&s.candidates[j], j, &mut w), w)
        })
        .collect();
    let mut evals = vec![];
    for (e, w) in scored {
        warnings.extend(w);
        evals.extend(e);
    }
    evals
}

/// The report of one evaluation (not yet accepted).
fn report(s: &Setup, round: &Round, e: &Evaluation) -> EffectReport {
    let c = &s.candidates[e.candidate];
    let v = &c.variants[e.variant];
    let n = s.store.joints();
    let beta = full_beta(v, &e.groups[e.variant], &e.beta);
    EffectReport {
        effect: c.name().to_string(),
        detail: c.effect.detail(&v.columns, &beta),
        fitted: (c.effect.fitted(&v.columns, &beta).into_iter())
            .map(|(k, x)| (k.to_string(), x))
            .collect(),
        round: round.number,
        joints: e
            .scores
            .joints
            .iter()
            .map(|&i| s.names[i].clone())
            .collect(),
        params: e.params,
        heldout_rms_nominal: rms_per_joint(s.store.residual(), n),
        heldout_rms_before: rms_per_joint(&round.without.resid, n),
        heldout_rms_after: rms_per_joint(&e.cv.resid, n),
        fold_gains: e.scores.fold_gains.clone(),
        z: e.scores.z,
        accepted: false,
        rule: match &e.verdict {
            Ok(why) => why.clone(),
            Err(why) => format!("not accepted: {why}"),
        },
        tied_with: vec![],
        ties: vec![],
        same_as: c.aliases.iter().map(|a| a.to_string()).collect(),
        implausible: super::implausible::implausible(c, e.variant, &beta, s.names),
        sizes: point_sizes(c, e.variant, &beta, s),
        removed: None,
    }
}

/// The sizes of variant `at` of `c` at `beta` (one per column of the
/// variant), without intervals.
fn point_sizes(
    c: &Candidate,
    at: usize,
    beta: &[f64],
    s: &Setup,
) -> Vec<super::report::SizeReport> {
    let v = &c.variants[at];
    let cx = crate::effects::SizeContext {
        model: s.model,
        col_joints: &v.col_joints,
    };
    (c.effect.sizes(&v.columns, beta, &cx).into_iter())
        .map(|z| super::report::SizeReport {
            name: z.name,
            unit: z.unit,
            value: z.value,
            low: z.value,
            high: z.value,
        })
        .collect()
}

/// The coefficients of every column of variant `v`, from those of `group`
/// (its columns on the joints kept; the others 0).
pub fn full_beta(v: &super::candidate::Variant, group: &Group, beta: &[f64]) -> Vec<f64> {
    (v.group.ids.iter())
        .map(|id| {
            (group.ids.iter().position(|g| g == id))
                .map_or(0.0, |p| beta.get(p).copied().unwrap_or(0.0))
        })
        .collect()
}
