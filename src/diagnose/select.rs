//! Scoring candidates and choosing one: each candidate's best variant on
//! the training part, its held-out RMS, the held-out block test and ΔBIC;
//! then the best significant one among those within noise of it.

use super::EffectReport;
use super::candidates::Columns;
use super::fit::{apply, fit_candidate};
use super::split::{Split, rms_per_joint};

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

/// The variant (nonlinear parameter) that fits the training part best, and
/// its coefficients; failed fits are reported in `warnings`.
fn best_variant<'c>(
    variants: &'c [Columns],
    split: &Split,
    r: &[f64],
    round: usize,
    warnings: &mut Vec<String>,
) -> Option<(f64, &'c Columns, Vec<f64>)> {
    let mut best: Option<(f64, &Columns, Vec<f64>)> = None;
    for v in variants {
        let beta = match fit_candidate(v, split.train.clone(), r) {
            Ok(f) => {
                if f.inaccurate {
                    warnings.push(format!(
                        "round {round}: candidate '{}' {}: the constrained fit was solved only to reduced tolerances",
                        v.name(),
                        v.detail
                    ));
                }
                f.beta
            }
            Err(e) => {
                warnings.push(format!(
                    "round {round}: candidate '{}' {} skipped: {e}",
                    v.name(),
                    v.detail
                ));
                continue;
            }
        };
        let after = apply(&v.cols, &beta, r);
        let rss: f64 = after[split.train.clone()].iter().map(|x| x * x).sum();
        if best.as_ref().is_none_or(|b| rss < b.0) {
            best = Some((rss, v, beta));
        }
    }
    best
}

/// Per-block held-out gains `MSE(r) − MSE(after)`.
fn block_gains(split: &Split, r: &[f64], after: &[f64], blocks: usize) -> Vec<f64> {
    let n = split.joints;
    let va = split.heldout.clone();
    let per_block = (va.len() / n / blocks.max(2)).max(1) * n;
    va.clone()
        .step_by(per_block)
        .map(|s| {
            let e = (s + per_block).min(va.end);
            (s..e)
                .map(|i| r[i] * r[i] - after[i] * after[i])
                .sum::<f64>()
                / (e - s) as f64
        })
        .collect()
}

/// Scores one candidate (its best variant) against the current residual.
pub fn evaluate(
    variants: &[Columns],
    split: &Split,
    r: &[f64],
    round: usize,
    blocks: usize,
    names: &[String],
    warnings: &mut Vec<String>,
) -> Option<Evaluation> {
    let n = split.joints;
    let (rss_after_tr, v, beta) = best_variant(variants, split, r, round, warnings)?;
    let before = rms_per_joint(&r[split.heldout.clone()], n);
    let after = apply(&v.cols, &beta, r);
    let after_rms = rms_per_joint(&after[split.heldout.clone()], n);
    let diffs = block_gains(split, r, &after, blocks);
    let m = diffs.iter().sum::<f64>() / diffs.len() as f64;
    let sd = (diffs.iter().map(|d| (d - m).powi(2)).sum::<f64>() / (diffs.len() - 1).max(1) as f64)
        .sqrt();
    let nt = split.train.len() as f64;
    let rss_tr: f64 = r[split.train.clone()].iter().map(|x| x * x).sum();
    let params = v.cols.len() + v.nonlinear;
    let dbic = nt * (rss_after_tr / rss_tr.max(1e-300)).ln() + params as f64 * nt.ln();
    let joints = (0..n)
        .filter(|&i| after_rms[i] < 0.99 * before[i])
        .map(|i| names[i].clone())
        .collect();
    Some(Evaluation {
        report: EffectReport {
            effect: v.name().to_string(),
            detail: fitted_detail(v, &beta),
            joint_offsets: is_joint_offset(v).then(|| beta.clone()),
            round,
            joints,
            params,
            heldout_rms_before: before,
            heldout_rms_after: after_rms,
            delta_bic: dbic,
            z: block_bootstrap_z(&diffs),
            accepted: false,
            tied_with: vec![],
            implausible: implausible(variants, v, &beta, names),
        },
        after,
        gain: m,
        gain_se: sd / (diffs.len() as f64).sqrt(),
    })
}

/// The report's detail: the variant's nonlinear parameter, or for an
/// encoder zero offset the offsets fitted (the coefficients of ∂τ̂/∂q_j).
fn fitted_detail(chosen: &Columns, beta: &[f64]) -> String {
    if !is_joint_offset(chosen) {
        return chosen.detail.clone();
    }
    let d: Vec<String> = beta.iter().map(|b| format!("{b:.3}")).collect();
    format!("δ = ({}) rad or m, true q = measured q + δ", d.join(", "))
}

fn is_joint_offset(c: &Columns) -> bool {
    c.candidate == super::candidates::Candidate::Effect(crate::dynamics::Effect::JointOffset)
}

/// The largest encoder zero offset (rad or m) a calibration error is taken
/// to have.
const MAX_JOINT_OFFSET: f64 = 0.2;

/// Why the fit of `chosen` (one of `variants`, coefficients `beta`) is
/// physically doubtful, if it is.
fn implausible(
    variants: &[Columns],
    chosen: &Columns,
    beta: &[f64],
    names: &[String],
) -> Option<String> {
    use crate::dynamics::Effect;
    if let Some(why) = &chosen.doubt {
        return Some(why.clone());
    }
    let at = variants.iter().position(|v| std::ptr::eq(v, chosen))?;
    // the top of a grid (the longest delay, the finest cogging, the widest
    // Stribeck velocity) can hide a larger value; its bottom only can where
    // smaller values exist (a Stribeck velocity; not a one-sample delay or
    // one period per turn)
    let bottom_open = chosen.candidate == super::candidates::Candidate::Effect(Effect::Stribeck);
    if variants.len() > 2 && (at + 1 == variants.len() || (at == 0 && bottom_open)) {
        return Some(format!(
            "its nonlinear parameter ({}) is at the edge of the grid searched; the true value may lie beyond it",
            chosen.detail
        ));
    }
    if is_joint_offset(chosen)
        && let Some((j, b)) = beta
            .iter()
            .enumerate()
            .find(|(_, b)| b.abs() > MAX_JOINT_OFFSET)
    {
        return Some(format!(
            "the offset of joint '{}' is {b:.3} rad (or m), beyond {MAX_JOINT_OFFSET}: more than a calibration error",
            names.get(j).map_or("?", String::as_str)
        ));
    }
    None
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
/// (then the fewest parameters) wins. Returns the chosen index and the
/// others of its group, or `None` when nothing is significant.
pub fn choose(evals: &mut [Evaluation], before: &[f64]) -> Option<(usize, Vec<usize>)> {
    let total_before: f64 = before.iter().map(|x| x * x).sum();
    evals.sort_by(|a, b| b.gain.total_cmp(&a.gain));
    let bi = evals.iter().position(|e| significant(e, total_before))?;
    let (bm, bse) = (evals[bi].gain, evals[bi].gain_se);
    let mut group: Vec<usize> = (0..evals.len())
        .filter(|&j| {
            j != bi
                && significant(&evals[j], total_before)
                && evals[j].gain >= bm - 2.0 * bse.max(evals[j].gain_se)
        })
        .collect();
    group.push(bi);
    // among tied candidates the penalised criterion decides: a 1-parameter
    // effect beats a 30-parameter refit that explains the same on the
    // training part
    group.sort_by(|&a, &b| {
        evals[a]
            .report
            .delta_bic
            .total_cmp(&evals[b].report.delta_bic)
            .then(evals[a].report.params.cmp(&evals[b].report.params))
    });
    let chosen = group[0];
    Some((chosen, group.into_iter().filter(|&j| j != chosen).collect()))
}

#[cfg(test)]
mod tests {
    use super::{Split, block_bootstrap_z, evaluate, implausible};
    use crate::diagnose::candidates::{Candidate, Columns};
    use crate::dynamics::Effect;

    /// A fit at the edge of its grid, or an encoder offset beyond a
    /// calibration error, is flagged; one inside its grid is not.
    #[test]
    fn implausible_fits_are_flagged() {
        let col = |c, detail: &str| Columns {
            candidate: Candidate::Effect(c),
            detail: detail.into(),
            cols: vec![vec![1.0; 4]],
            bodies: vec![],
            nonneg: false,
            nonlinear: 1,
            doubt: None,
            gram: std::sync::OnceLock::new(),
        };
        let grid: Vec<Columns> = ["1 ms", "2 ms", "3 ms"]
            .iter()
            .map(|d| col(Effect::TimeDelay, d))
            .collect();
        let names = vec!["knee".to_string()];
        assert!(implausible(&grid, &grid[1], &[1.0], &names).is_none());
        // a one-sample delay is the bottom of what can be resolved, not a doubt
        assert!(implausible(&grid, &grid[0], &[1.0], &names).is_none());
        let edge = implausible(&grid, &grid[2], &[1.0], &names).unwrap();
        assert!(edge.contains("3 ms") && edge.contains("edge"), "{edge}");
        let off = [col(Effect::JointOffset, "")];
        assert!(implausible(&off, &off[0], &[0.05], &names).is_none());
        let far = implausible(&off, &off[0], &[-0.4], &names).unwrap();
        assert!(far.contains("'knee'") && far.contains("-0.400"), "{far}");
        // a doubt found where the parameters were fitted (a compliance fit) is kept
        let mut soft = col(Effect::Elasticity, "K = (3)");
        soft.doubt = Some("stiffness 3 N·m/rad".into());
        let why = implausible(std::slice::from_ref(&soft), &soft, &[1.0], &names).unwrap();
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
        let variant = |cols, detail: &str| Columns {
            candidate: Candidate::Effect(Effect::Offset),
            detail: detail.into(),
            cols,
            bodies: vec![],
            nonneg: false,
            nonlinear: 0,
            doubt: None,
            gram: std::sync::OnceLock::new(),
        };
        let split = Split::new(400, n, 0.6);
        let names = vec!["j".to_string()];
        let mut warnings = vec![];
        let e = evaluate(
            &[
                variant(vec![bad.clone()], "broken"),
                variant(vec![x], "good"),
            ],
            &split,
            &r,
            1,
            20,
            &names,
            &mut warnings,
        )
        .expect("the good variant is scored");
        assert_eq!(e.report.detail, "good");
        assert!(e.report.heldout_rms_after[0] < 1e-6, "{:?}", e.report);
        assert_eq!(warnings.len(), 1);
        assert!(
            warnings[0].contains("'offset' broken skipped"),
            "{warnings:?}"
        );
        // nothing fits: no evaluation, and the warning says so
        let mut warnings = vec![];
        let none = evaluate(
            &[variant(vec![bad], "broken")],
            &split,
            &r,
            2,
            20,
            &names,
            &mut warnings,
        );
        assert!(none.is_none() && warnings.len() == 1);
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
