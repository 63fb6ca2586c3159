//! Scoring candidates and choosing one: each candidate's best variant on
//! the training part, its held-out RMS, the held-out block test and ΔBIC;
//! then the best significant one among those within noise of it.

use super::candidate::{Candidate, Variant};
use super::carry::drop_hurting;
use super::fit::{Fit, apply, fit_candidate, least_squares_on};
use super::report::EffectReport;
use super::screen::screened_columns;
use super::split::Split;
use super::warning::DiagnoseWarning;
use crate::data::rms_per_joint;

/// Resamples of the block bootstrap.
const BOOTSTRAP: usize = 20_000;

/// The held-out block test: a bootstrap over the per-block gains `d` (MSE
/// before − after, one per consecutive block of the held-out part, so that
/// correlated residuals stay inside a block). Returns the one-sided p-value
/// of "the mean gain is ≤ 0", `(#{mean* ≤ 0} + 1)/(B + 1)`, as a normal
/// quantile `z = Φ⁻¹(1 − p)` (at most ≈ 3.9 for B = 20 000). Unlike
/// mean/SE, it does not call an effect that acts only at some moments
/// (large gains in a few blocks, none in the others) noise. Deterministic
/// (fixed seed).
pub(crate) fn block_bootstrap_z(d: &[f64]) -> f64 {
    use rand::{RngExt, SeedableRng};
    use statrs::distribution::{ContinuousCDF, Normal};
    let m = d.len();
    if m < 2 {
        return 0.0;
    }
    let mut rng = rand::rngs::StdRng::seed_from_u64(0x6d6f6d);
    let below = (0..BOOTSTRAP)
        .filter(|_| (0..m).map(|_| d[rng.random_range(0..m)]).sum::<f64>() <= 0.0)
        .count();
    let b = (BOOTSTRAP + 1) as f64;
    let p = ((below + 1) as f64 / b).min(1.0 - 1.0 / b);
    Normal::standard().inverse_cdf(1.0 - p)
}

/// One candidate scored in one round.
pub struct Evaluation {
    /// The report.
    pub report: EffectReport,
    /// The residual with the candidate added (all rows).
    pub after: Vec<f64>,
    /// Mean held-out block gain (MSE before − after).
    pub gain: f64,
    /// Its standard error over the blocks.
    pub gain_se: f64,
}

/// The variant (nonlinear parameter) that fits the training part best
/// (each on its screened joints: [`screened_columns`]): its index,
/// training RSS, coefficients and the number of columns fitted; failed
/// fits are reported in `warnings`.
fn best_variant(
    c: &Candidate,
    split: &Split,
    r: &[f64],
    round: usize,
    warnings: &mut Vec<DiagnoseWarning>,
) -> Option<Best> {
    let mut best: Option<Best> = None;
    for (j, v) in c.variants.iter().enumerate() {
        let (effect, variant) = (c.name().to_string(), v.columns.detail.clone());
        let fit = screened_columns(v, split, r).and_then(|on| {
            if on.len() < v.columns.cols.len() {
                let beta = least_squares_on(v, &on, split.train.clone(), r)?;
                Ok((
                    Fit {
                        beta,
                        inaccurate: false,
                    },
                    on.len(),
                ))
            } else {
                Ok((fit_candidate(v, split.train.clone(), r)?, on.len()))
            }
        });
        let (beta, fitted) = match fit {
            Ok((f, fitted)) => {
                if f.inaccurate {
                    warnings.push(DiagnoseWarning::Inaccurate {
                        round,
                        effect,
                        variant,
                    });
                }
                (f.beta, fitted)
            }
            Err(e) => {
                warnings.push(DiagnoseWarning::FitFailed {
                    round,
                    effect,
                    variant,
                    reason: e.to_string(),
                });
                continue;
            }
        };
        let after = apply(&v.columns.cols, &beta, r);
        let rss: f64 = after[split.train.clone()].iter().map(|x| x * x).sum();
        if best.as_ref().is_none_or(|b| rss < b.rss) {
            best = Some(Best {
                at: j,
                rss,
                beta,
                fitted,
            });
        }
    }
    best
}

/// A candidate's best variant.
struct Best {
    at: usize,
    rss: f64,
    beta: Vec<f64>,
    /// Columns fitted (the others' β are 0).
    fitted: usize,
}

/// Scores one candidate (its best variant) against the current residual.
pub fn evaluate(
    c: &Candidate,
    split: &Split,
    r: &[f64],
    (round, blocks): (usize, usize),
    names: &[String],
    warnings: &mut Vec<DiagnoseWarning>,
) -> Option<Evaluation> {
    let n = split.joints;
    let Best {
        at,
        mut rss,
        mut beta,
        mut fitted,
    } = best_variant(c, split, r, round, warnings)?;
    let dropped = drop_hurting(&c.variants[at], split, r, &mut beta);
    let v = &c.variants[at].columns;
    let after = apply(&v.cols, &beta, r);
    if dropped > 0 {
        fitted -= dropped;
        rss = after[split.train.clone()].iter().map(|x| x * x).sum();
    }
    let before = rms_per_joint(&r[split.heldout.clone()], n);
    let after_rms = rms_per_joint(&after[split.heldout.clone()], n);
    let diffs = split.block_gains(r, &after, blocks, None);
    let m = diffs.iter().sum::<f64>() / diffs.len() as f64;
    let sd = (diffs.iter().map(|d| (d - m).powi(2)).sum::<f64>() / (diffs.len() - 1).max(1) as f64)
        .sqrt();
    let nt = split.train.len() as f64;
    let rss_tr: f64 = r[split.train.clone()].iter().map(|x| x * x).sum();
    let params = fitted + v.nonlinear;
    let dbic = nt * (rss / rss_tr.max(1e-300)).ln() + params as f64 * nt.ln();
    let joints = (0..n)
        .filter(|&i| after_rms[i] < 0.99 * before[i])
        .map(|i| names[i].clone())
        .collect();
    Some(Evaluation {
        report: EffectReport {
            effect: c.name().to_string(),
            detail: c.effect.detail(v, &beta),
            fitted: c
                .effect
                .fitted(v, &beta)
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect(),
            round,
            joints,
            params,
            heldout_rms_before: before,
            heldout_rms_after: after_rms,
            delta_bic: dbic,
            z: block_bootstrap_z(&diffs),
            accepted: false,
            tied_with: vec![],
            same_as: c.aliases.iter().map(|a| a.to_string()).collect(),
            implausible: implausible(c, at, &beta, names),
        },
        after,
        gain: m,
        gain_se: sd / (diffs.len() as f64).sqrt(),
    })
}

/// Why the fit of `c`'s variant `at` (coefficients `beta`) is physically
/// doubtful, if it is: the doubt its search found, a grid point at an open
/// edge of the grid, or the effect's own rule.
fn implausible(c: &Candidate, at: usize, beta: &[f64], names: &[String]) -> Option<String> {
    let chosen: &Variant = &c.variants[at];
    if let Some(why) = &chosen.columns.doubt {
        return Some(why.clone());
    }
    let last = c.variants.len() - 1;
    let edge = (at == last && c.open_high) || (at == 0 && c.open_low);
    if c.variants.len() > 2 && edge {
        return Some(format!(
            "its nonlinear parameter ({}) is at the edge of the grid searched; the true value may lie beyond it",
            chosen.columns.detail
        ));
    }
    c.effect.doubt(&chosen.columns, beta, names)
}

/// Whether a candidate is accepted on its own merits: the block test
/// (z > 3), ΔBIC < −10 and a held-out MSE at least 2 % lower.
fn significant(e: &Evaluation, total_before: f64) -> bool {
    let total_after: f64 = e.report.heldout_rms_after.iter().map(|x| x * x).sum();
    e.report.z > 3.0 && e.report.delta_bic < -10.0 && total_after < 0.98 * total_before
}

/// Picks this round's effect among `evals` (sorted here by held-out gain):
/// the best significant one and every significant candidate within two
/// standard errors of its gain form a tie group, in which the lowest ΔBIC
/// (then the fewest parameters) wins — unless a [`leaner`] candidate
/// explains the winner's joints as well, which then goes first with its
/// own tie group. Returns the chosen index and the others of its group, or
/// `None` when nothing is significant.
pub fn choose(evals: &mut [Evaluation], before: &[f64]) -> Option<(usize, Vec<usize>)> {
    let total_before: f64 = before.iter().map(|x| x * x).sum();
    evals.sort_by(|a, b| b.gain.total_cmp(&a.gain));
    let bi = evals.iter().position(|e| significant(e, total_before))?;
    let mut group = tie_group(evals, bi, total_before);
    by_criterion(evals, &mut group);
    let chosen = group[0];
    if let Some(lean) = leaner(evals, chosen, total_before) {
        // the one deferred is not tied: it explains more elsewhere; the
        // leaner one's group is decided like any other, among those
        // leaner than the one deferred
        let params = evals[chosen].report.params;
        let mut tied: Vec<usize> = tie_group(evals, lean, total_before)
            .into_iter()
            .filter(|&j| j != chosen && evals[j].report.params < params)
            .collect();
        by_criterion(evals, &mut tied);
        return Some((tied[0], tied[1..].to_vec()));
    }
    Some((chosen, group[1..].to_vec()))
}

/// Orders a tie group by the penalised criterion: among tied candidates a
/// 1-parameter effect beats a 30-parameter refit that explains the same
/// on the training part (the lowest ΔBIC, then the fewest parameters).
fn by_criterion(evals: &[Evaluation], group: &mut [usize]) {
    group.sort_by(|&a, &b| {
        evals[a]
            .report
            .delta_bic
            .total_cmp(&evals[b].report.delta_bic)
            .then(evals[a].report.params.cmp(&evals[b].report.params))
    });
}

/// `at` and every significant candidate whose gain is within two standard
/// errors of its gain.
fn tie_group(evals: &[Evaluation], at: usize, total_before: f64) -> Vec<usize> {
    let (bm, bse) = (evals[at].gain, evals[at].gain_se);
    let mut group: Vec<usize> = (0..evals.len())
        .filter(|&j| {
            j != at
                && significant(&evals[j], total_before)
                && evals[j].gain >= bm - 2.0 * bse.max(evals[j].gain_se)
        })
        .collect();
    group.push(at);
    group
}

/// The share of what the chosen candidate removes on the joints both
/// lower that a leaner one must remove there to be preferred.
const PARSIMONY: f64 = 0.9;

/// A significant candidate with fewer parameters than `chosen` that, on
/// the joints both lower (held-out MSE by ≥ 1 % each), removes at least
/// [`PARSIMONY`] of what `chosen` removes there: an offset on one joint
/// before a 70-parameter inertia refit that also bends to it (the refit
/// can follow in a later round for the other joints). The one with the
/// largest held-out gain among them, if any.
fn leaner(evals: &[Evaluation], chosen: usize, total_before: f64) -> Option<usize> {
    let gains = |e: &Evaluation| -> Vec<f64> {
        let (b, a) = (&e.report.heldout_rms_before, &e.report.heldout_rms_after);
        b.iter().zip(a).map(|(b, a)| b * b - a * a).collect()
    };
    let big = gains(&evals[chosen]);
    (0..evals.len())
        .filter(|&j| {
            let e = &evals[j];
            if j == chosen || e.report.params >= evals[chosen].report.params {
                return false;
            }
            let (g, b) = (gains(e), &e.report.heldout_rms_before);
            let lowers = |x: &[f64], i: usize| x[i] >= 0.01 * b[i] * b[i];
            let shared: Vec<usize> = (0..g.len())
                .filter(|&i| lowers(&g, i) && lowers(&big, i))
                .collect();
            let (mine, theirs) = shared
                .iter()
                .fold((0.0, 0.0), |(m, t), &i| (m + g[i], t + big[i]));
            significant(e, total_before) && theirs > 0.0 && mine >= PARSIMONY * theirs
        })
        .max_by(|&a, &b| evals[a].gain.total_cmp(&evals[b].gain))
}

#[cfg(test)]
mod tests {
    use super::{Evaluation, Split, block_bootstrap_z, choose, evaluate, implausible};
    use crate::diagnose::candidate::Candidate;
    use crate::diagnose::report::EffectReport;
    use crate::effects::{Columns, Hypothesis, Library};

    fn candidate(name: &str, h: Hypothesis) -> Candidate {
        let lib = Library::builtin();
        Candidate::new(lib.get(name).unwrap().clone(), h).unwrap()
    }

    /// A fit at an open edge of its grid, or an encoder offset beyond a
    /// calibration error, is flagged; one inside its grid is not.
    #[test]
    fn implausible_fits_are_flagged() {
        let col = |detail: &str| Columns::variant(detail, vec![vec![1.0; 4]], 1);
        let grid = |name| candidate(name, Hypothesis::grid(["1", "2", "3"].map(col).to_vec()));
        let names = vec!["knee".to_string()];
        let delay = grid("time_delay");
        assert!(implausible(&delay, 1, &[1.0], &names).is_none());
        // a one-sample delay is the bottom of what can be resolved, not a doubt
        assert!(implausible(&delay, 0, &[1.0], &names).is_none());
        let edge = implausible(&delay, 2, &[1.0], &names).unwrap();
        assert!(edge.contains("(3)") && edge.contains("edge"), "{edge}");
        // a grid open below (Stribeck velocities) is doubtful at its bottom too
        let low = candidate(
            "stribeck",
            Hypothesis::grid(["1", "2", "3"].map(col).to_vec()).open_below(),
        );
        assert!(implausible(&low, 0, &[1.0], &names).is_some());
        let off = candidate("joint_offset", Hypothesis::linear(vec![vec![1.0; 4]]));
        assert!(implausible(&off, 0, &[0.05], &names).is_none());
        let far = implausible(&off, 0, &[-0.4], &names).unwrap();
        assert!(far.contains("'knee'") && far.contains("-0.400"), "{far}");
        // a doubt found where the parameters were fitted (a compliance fit) is kept
        let mut soft = col("K = (3)");
        soft.doubt = Some("stiffness 3 N·m/rad".into());
        let soft = candidate("elasticity", Hypothesis::single(soft));
        let why = implausible(&soft, 0, &[1.0], &names).unwrap();
        assert!(why.contains("stiffness 3"), "{why}");
    }

    /// A candidate whose fit fails is skipped with a warning naming it, and
    /// the variant that fits is still scored.
    #[test]
    fn a_failed_variant_is_a_warning_not_a_zero() {
        let n = 1;
        let x: Vec<f64> = (0..400).map(|k| (k as f64 * 0.05).sin()).collect();
        let r: Vec<f64> = x.iter().map(|v| 0.5 * v).collect();
        let mut bad = x.clone();
        bad[3] = f64::NAN;
        let variant = |cols, detail: &str| Columns::variant(detail, cols, 0);
        let offset = |vs| {
            candidate(
                "offset",
                Hypothesis {
                    variants: vs,
                    ..Hypothesis::default()
                },
            )
        };
        let split = Split::new(400, n, 0.6);
        let names = vec!["j".to_string()];
        let mut warnings = vec![];
        let both = offset(vec![
            variant(vec![bad.clone()], "broken"),
            variant(vec![x], "good"),
        ]);
        let e = evaluate(&both, &split, &r, (1, 20), &names, &mut warnings)
            .expect("the good variant is scored");
        assert_eq!(e.report.detail, "good");
        assert!(e.report.heldout_rms_after[0] < 1e-6, "{:?}", e.report);
        assert_eq!(warnings.len(), 1);
        let w = warnings[0].to_string();
        assert!(w.contains("'offset' broken skipped"), "{w}");
        // nothing fits: no evaluation, and the warning says so
        let mut warnings = vec![];
        let broken = offset(vec![variant(vec![bad], "broken")]);
        let none = evaluate(&broken, &split, &r, (2, 20), &names, &mut warnings);
        assert!(none.is_none() && warnings.len() == 1);
    }

    /// A significant candidate scored with held-out RMS `after` per joint
    /// (from 1.0 each) and `params` parameters.
    fn scored(effect: &str, after: &[f64], params: usize, delta_bic: f64) -> Evaluation {
        let before = vec![1.0; after.len()];
        let gain = after.iter().map(|a| 1.0 - a * a).sum::<f64>() / after.len() as f64;
        Evaluation {
            report: EffectReport {
                effect: effect.into(),
                detail: String::new(),
                fitted: Default::default(),
                round: 1,
                joints: vec![],
                params,
                heldout_rms_before: before,
                heldout_rms_after: after.to_vec(),
                delta_bic,
                z: 3.9,
                accepted: false,
                tied_with: vec![],
                same_as: vec![],
                implausible: None,
            },
            after: vec![],
            gain,
            gain_se: 1e-4,
        }
    }

    /// A 70-parameter refit that removes most on joints 0–1 and also bends to
    /// joint 2's offset loses to the 1-parameter offset that removes as much
    /// on joint 2; an offset that removes only half of it there does not.
    #[test]
    fn a_leaner_candidate_that_explains_its_joints_goes_first() {
        let before = [1.0; 3];
        let mut evals = vec![
            scored("link_inertia", &[0.5, 0.5, 0.6], 70, -900.0),
            scored("offset", &[1.0, 1.0, 0.62], 1, -300.0),
        ];
        let (chosen, tied) = choose(&mut evals, &before).unwrap();
        assert_eq!(evals[chosen].report.effect, "offset");
        assert!(tied.is_empty());
        let mut evals = vec![
            scored("link_inertia", &[0.5, 0.5, 0.6], 70, -900.0),
            scored("offset", &[1.0, 1.0, 0.85], 1, -300.0),
        ];
        let (chosen, _) = choose(&mut evals, &before).unwrap();
        assert_eq!(evals[chosen].report.effect, "link_inertia");
        // a leaner one that works only where the chosen one does not is no rival
        let mut evals = vec![
            scored("torque_gain", &[0.3, 0.3, 1.0], 3, -900.0),
            scored("offset", &[1.0, 1.0, 0.96], 1, -300.0),
        ];
        let (chosen, _) = choose(&mut evals, &before).unwrap();
        assert_eq!(evals[chosen].report.effect, "torque_gain");
    }

    /// When a leaner candidate goes first, its tie group is decided like
    /// any other: a 1-parameter offset tied with the leaner 6-parameter
    /// delay, and with the lower ΔBIC, is chosen although on its own it
    /// explains too little of the refit's gain to be leaner.
    #[test]
    fn the_leaner_candidates_tie_group_goes_by_the_criterion() {
        let before = [1.0; 3];
        let mut evals = vec![
            scored("link_inertia", &[0.5, 0.5, 0.6], 70, -900.0),
            scored("time_delay", &[0.55, 0.55, 1.0], 6, -300.0),
            scored("offset", &[1.0, 1.0, 0.75], 1, -400.0),
        ];
        evals.iter_mut().for_each(|e| e.gain_se = 0.2);
        let (chosen, tied) = choose(&mut evals, &before).unwrap();
        assert_eq!(evals[chosen].report.effect, "offset");
        let tied: Vec<&str> = tied
            .iter()
            .map(|&j| evals[j].report.effect.as_str())
            .collect();
        assert_eq!(tied, ["time_delay"]);
    }

    /// 2,011 held-out samples in 20 blocks: 20 gains, not 20 and a block
    /// of the 11 left over, whose mean would weigh as much as 100 samples'.
    #[test]
    fn held_out_blocks_are_equal_and_leave_no_remainder() {
        let (n, samples) = (2, 5028);
        let split = Split::new(samples, n, 0.6);
        let held = split.heldout.len() / n;
        assert_eq!(held, 2012);
        let r = vec![1.0; samples * n];
        // the fit halves the residual everywhere but makes the last 11 samples 10× worse
        let after: Vec<f64> = (0..samples * n)
            .map(|i| if i / n >= samples - 11 { 10.0 } else { 0.5 })
            .collect();
        let g = split.block_gains(&r, &after, 20, None);
        assert_eq!(g.len(), 20);
        assert!(g[..19].iter().all(|x| (x - 0.75).abs() < 1e-12), "{g:?}");
        // the last block: 100 or 101 samples, 11 of them at −99
        let last = g[19];
        assert!(last < 0.0 && last > -11.0, "{last}");
    }

    #[test]
    fn block_bootstrap_separates_concentrated_gains_from_noise() {
        // large gains in a few blocks, ~nothing elsewhere: significant
        let concentrated = [
            0.19, 0.001, -0.0004, 0.04, 0.8, 0.75, 0.56, 0.04, 0.03, 0.009, 0.13, 0.2, 1.05, 0.1,
            0.007, 0.001, -0.0003, 0.07, 1.26, 0.18,
        ];
        assert!(block_bootstrap_z(&concentrated) > 3.0);
        // gains of either sign around zero: not significant
        let noise: Vec<f64> = (0..20).map(|k| ((k * 7919) % 13) as f64 - 6.0).collect();
        assert!(block_bootstrap_z(&noise).abs() < 2.0);
        // everything worse: strongly negative
        let worse = block_bootstrap_z(&[-1.0; 20]);
        assert!(worse < -3.0 && worse.is_finite());
    }
}
