//! # `diagnose`: where the sim-to-real gap lies and which effect explains it
//!
//! Given a nominal model (parameters + friction) and measured data, the data
//! are split in time (training first, held-out last). **Where:** the
//! held-out residual `τ − τ̂` per joint, by motion regime, position,
//! frequency band and time, with whiteness and cross-correlation checks
//! ([`where_`]). **Which:** every candidate effect of the library
//! ([`candidates`]) is an addition to the current model, fitted on the
//! training part only; it is scored by its held-out RMS reduction, a block
//! test on the held-out part (robust to correlated residuals) and ΔBIC on
//! the training part. Forward selection accepts the best significant one,
//! adds it, and repeats. Candidates within noise of the best are reported
//! as tied. **How far:** held-out RMS per joint before and after, the share
//! of the gap above the noise floor that is closed, and whether a remainder
//! is left unexplained.
//!
//! See `docs/diagnosis.md` for the method in full and the confusion table
//! of the withheld-effect benchmark.

pub mod candidates;
pub mod compliance;
pub mod where_;

use crate::data::Dataset;
use crate::dynamics::Model;
use crate::dynamics::params_file::Friction;
use crate::dynamics::predict::predict_torques;
use candidates::{CANDIDATES, Columns, build, flat};
use faer::Mat;
use faer::linalg::solvers::Solve;
use serde::Serialize;
use where_::{JointWhere, analyse_joint, summarise};

/// Options.
#[derive(Clone, Debug)]
pub struct DiagnoseOptions {
    /// Fraction of the samples (from the start) used for fitting.
    pub train_fraction: f64,
    /// At most this many effects are accepted.
    pub max_effects: usize,
    /// Blocks of the held-out block test.
    pub blocks: usize,
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        Self {
            train_fraction: 0.6,
            max_effects: 4,
            blocks: 20,
        }
    }
}

/// One candidate's evaluation in one round.
#[derive(Clone, Debug, Serialize)]
pub struct EffectReport {
    /// Effect name.
    pub effect: String,
    /// The chosen nonlinear parameter, if any.
    pub detail: String,
    /// Selection round (1-based).
    pub round: usize,
    /// Joints whose held-out RMS it reduces by more than 1 %.
    pub joints: Vec<String>,
    /// Number of fitted parameters.
    pub params: usize,
    /// Held-out RMS per joint before (current model) (N·m).
    pub heldout_rms_before: Vec<f64>,
    /// Held-out RMS per joint with the effect added (N·m).
    pub heldout_rms_after: Vec<f64>,
    /// ΔBIC on the training part (negative: better).
    pub delta_bic: f64,
    /// Block-test z score of the held-out improvement.
    pub z: f64,
    /// Accepted into the model.
    pub accepted: bool,
    /// Candidates that explain the same within noise.
    pub tied_with: Vec<String>,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// Joint names.
    pub joints: Vec<String>,
    /// Where the gap lies (held-out residual of the nominal model).
    #[serde(rename = "where")]
    pub where_: Vec<JointWhere>,
    /// One line per joint.
    pub summary: Vec<String>,
    /// Candidates per round, best first.
    pub ranked_effects: Vec<EffectReport>,
    /// Accepted effects in order.
    pub accepted: Vec<String>,
    /// Held-out RMS per joint of the nominal model (N·m).
    pub heldout_rms_nominal: Vec<f64>,
    /// Held-out RMS per joint after the accepted effects (N·m).
    pub heldout_rms_final: Vec<f64>,
    /// Noise floor per joint (N·m).
    pub noise_floor: Vec<f64>,
    /// Share of the gap above the noise floor closed, per joint.
    pub gap_closed: Vec<f64>,
    /// A remainder above the noise floor is left that no candidate explains.
    pub unexplained: bool,
    /// Where the unexplained remainder lies.
    pub unexplained_where: Vec<String>,
    /// Held-out signals and residuals for plots (not serialised).
    #[serde(skip)]
    pub heldout: HeldOut,
}

/// The held-out part's signals and residuals, per joint (for plots).
#[derive(Clone, Debug, Default)]
pub struct HeldOut {
    /// Time (s).
    pub t: Vec<f64>,
    /// Positions per joint.
    pub q: Vec<Vec<f64>>,
    /// Velocities per joint.
    pub qd: Vec<Vec<f64>>,
    /// Residual of the nominal model per joint.
    pub nominal: Vec<Vec<f64>>,
    /// Residual after the accepted effects per joint.
    pub after: Vec<Vec<f64>>,
}

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
fn block_bootstrap_z(d: &[f64]) -> f64 {
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

fn rms_per_joint(r: &[f64], n: usize) -> Vec<f64> {
    let m = (r.len() / n).max(1) as f64;
    (0..n)
        .map(|i| (r.iter().skip(i).step_by(n).map(|x| x * x).sum::<f64>() / m).sqrt())
        .collect()
}

/// Least squares `min ‖X β − r‖` (tiny ridge for rank deficiency).
fn fit(cols: &[Vec<f64>], rows: std::ops::Range<usize>, r: &[f64]) -> Vec<f64> {
    let k = cols.len();
    let mut g = Mat::<f64>::zeros(k, k);
    let mut b = Mat::<f64>::zeros(k, 1);
    for a in 0..k {
        for c in a..k {
            let v: f64 = rows.clone().map(|i| cols[a][i] * cols[c][i]).sum();
            g[(a, c)] = v;
            g[(c, a)] = v;
        }
        b[(a, 0)] = rows.clone().map(|i| cols[a][i] * r[i]).sum();
    }
    let tr: f64 = (0..k).map(|a| g[(a, a)]).sum::<f64>().max(1e-300);
    for a in 0..k {
        g[(a, a)] += 1e-10 * tr / k as f64;
    }
    match g.llt(faer::Side::Lower) {
        Ok(l) => {
            let x = l.solve(&b);
            (0..k).map(|a| x[(a, 0)]).collect()
        }
        Err(_) => vec![0.0; k],
    }
}

/// The fit of a candidate: plain least squares, or — for inertial
/// corrections — least squares with `J(π_nominal + β) ⪰ 0` for every
/// corrected body (and β ≥ 0 for a payload mass), through `conic` with the
/// LMIs of `moments`, on the reduced (Gram) form of the rows.
fn fit_candidate(c: &Columns, rows: std::ops::Range<usize>, r: &[f64]) -> Vec<f64> {
    if c.bodies.is_empty() && !c.nonneg {
        return fit(&c.cols, rows, r);
    }
    let k = c.cols.len();
    let mut gram = Mat::<f64>::zeros(k + 1, k + 1);
    let col = |a: usize, i: usize| if a < k { c.cols[a][i] } else { r[i] };
    for a in 0..=k {
        for b in a..=k {
            let v: f64 = rows.clone().map(|i| col(a, i) * col(b, i)).sum();
            gram[(a, b)] = v;
            gram[(b, a)] = v;
        }
    }
    let red = crate::identify::Reduced {
        gram,
        samples: rows.len(),
        p: k,
    };
    let (f, d) = (red.r(), red.d());
    let scale: Vec<f64> = (0..k)
        .map(|j| {
            (0..f.nrows())
                .map(|i| f[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .map(|n| if n > 1e-12 { 1.0 / n } else { 1.0 })
        .collect();
    let mut p = crate::conic::Problem::new();
    let z = p.vector("beta", k);
    let beta: Vec<crate::conic::AffExpr> = (0..k)
        .map(|j| crate::conic::AffExpr::term(z[j], scale[j]))
        .collect();
    let t = p.scalar("t");
    let res: Vec<crate::conic::AffExpr> = (0..f.nrows())
        .map(|i| {
            let mut e = crate::conic::AffExpr::constant(-d[i]);
            for j in 0..k {
                e.add_term(z[j], f[(i, j)] * scale[j]);
            }
            e
        })
        .collect();
    let ok = (|| -> Result<(), crate::conic::ConicError> {
        p.add_soc(t, res)?;
        for (b, nominal) in c.bodies.iter().enumerate() {
            let pi = std::array::from_fn(|q| beta[10 * b + q].clone() + nominal[q]);
            p.add_psd(&crate::moments::lmi::BodyVars::from_exprs(pi).pseudo_inertia())?;
        }
        if c.nonneg {
            p.add_nonneg(beta.clone())?;
        }
        p.minimize(t);
        Ok(())
    })();
    if ok.is_err() {
        return fit(&c.cols, rows, r);
    }
    match p.solve(&crate::conic::Settings::default()) {
        Ok(sol) if sol.status.is_solved() => beta.iter().map(|e| sol.eval(e)).collect(),
        _ => vec![0.0; k],
    }
}

fn apply(cols: &[Vec<f64>], beta: &[f64], r: &[f64]) -> Vec<f64> {
    let mut out = r.to_vec();
    for (c, b) in cols.iter().zip(beta) {
        for (o, x) in out.iter_mut().zip(c) {
            *o -= b * x;
        }
    }
    out
}

/// Diagnoses `data` against the nominal `model` + `friction`.
pub fn diagnose(
    model: &Model,
    friction: &Friction,
    data: &Dataset,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, String> {
    let n = model.dof();
    if data.tau.len() != data.len() || data.len() < 100 {
        return Err("diagnosis needs at least 100 samples with torques".into());
    }
    let ns = data.len();
    let split = ((ns as f64) * opts.train_fraction) as usize;
    let (tr_rows, va_rows) = (0..split * n, split * n..ns * n);
    let pred = predict_torques(model, friction, &data.q, &data.qd, &data.qdd)
        .map_err(|e| e.to_string())?;
    let mut r: Vec<f64> = flat(&data.tau)
        .iter()
        .zip(flat(&pred))
        .map(|(a, b)| a - b)
        .collect();
    let fs = (ns - 1) as f64 / (data.t[ns - 1] - data.t[0]);
    let val = data.slice(split..ns);
    let where_of = |r: &[f64]| -> Vec<JointWhere> {
        (0..n)
            .map(|i| {
                let col = |v: &Vec<Vec<f64>>| v.iter().map(|x| x[i]).collect::<Vec<f64>>();
                let ri: Vec<f64> = r[va_rows.clone()]
                    .iter()
                    .skip(i)
                    .step_by(n)
                    .copied()
                    .collect();
                analyse_joint(
                    &data.joints[i],
                    &ri,
                    &col(&val.q),
                    &col(&val.qd),
                    &col(&val.qdd),
                    &col(&val.tau),
                    fs,
                )
            })
            .collect()
    };
    let where_nominal = where_of(&r);
    let noise_floor: Vec<f64> = where_nominal.iter().map(|w| w.noise_floor).collect();
    let nominal = rms_per_joint(&r[va_rows.clone()], n);
    // the compliance hypotheses are nonlinear: fitted once, to the nominal
    // residual on the training part, then offered as per-joint columns
    let lin = compliance::Linearisation::new(model, data).ok();
    let all_cols: Vec<Vec<Columns>> = CANDIDATES
        .iter()
        .map(|&c| match (c, &lin) {
            ("elasticity" | "backlash", Some(lin)) => {
                compliance::fit(lin, &r, split, c == "backlash")
                    .and_then(|f| compliance::columns(c, lin, &f))
                    .into_iter()
                    .collect()
            }
            _ => build(c, model, friction, data),
        })
        .collect();
    let mut ranked = vec![];
    let mut accepted = vec![];
    let nt = tr_rows.len() as f64;
    for round in 1..=opts.max_effects {
        let before = rms_per_joint(&r[va_rows.clone()], n);
        let rss_tr: f64 = r[tr_rows.clone()].iter().map(|x| x * x).sum();
        let mut evals: Vec<(EffectReport, Vec<f64>, f64, f64)> = vec![];
        for variants in &all_cols {
            // pick the variant (nonlinear parameter) that fits the training part best
            let mut best: Option<(f64, &Columns, Vec<f64>)> = None;
            for v in variants {
                if accepted.contains(&v.name.to_string()) {
                    continue;
                }
                let beta = fit_candidate(v, tr_rows.clone(), &r);
                let after = apply(&v.cols, &beta, &r);
                let rss: f64 = after[tr_rows.clone()].iter().map(|x| x * x).sum();
                if best.as_ref().is_none_or(|b| rss < b.0) {
                    best = Some((rss, v, beta));
                }
            }
            let Some((rss_after_tr, v, beta)) = best else {
                continue;
            };
            let after = apply(&v.cols, &beta, &r);
            let after_rms = rms_per_joint(&after[va_rows.clone()], n);
            // block test on the held-out part
            let per_block = (va_rows.len() / n / opts.blocks.max(2)).max(1) * n;
            let diffs: Vec<f64> = va_rows
                .clone()
                .step_by(per_block)
                .map(|s| {
                    let e = (s + per_block).min(va_rows.end);
                    (s..e)
                        .map(|i| r[i] * r[i] - after[i] * after[i])
                        .sum::<f64>()
                        / (e - s) as f64
                })
                .collect();
            let m = diffs.iter().sum::<f64>() / diffs.len() as f64;
            let sd = (diffs.iter().map(|d| (d - m).powi(2)).sum::<f64>()
                / (diffs.len() - 1).max(1) as f64)
                .sqrt();
            let z = block_bootstrap_z(&diffs);
            let params = v.cols.len() + v.nonlinear;
            let dbic = nt * (rss_after_tr / rss_tr.max(1e-300)).ln() + params as f64 * nt.ln();
            let joints = (0..n)
                .filter(|&i| after_rms[i] < 0.99 * before[i])
                .map(|i| data.joints[i].clone())
                .collect();
            let rep = EffectReport {
                effect: v.name.to_string(),
                detail: v.detail.clone(),
                round,
                joints,
                params,
                heldout_rms_before: before.clone(),
                heldout_rms_after: after_rms,
                delta_bic: dbic,
                z,
                accepted: false,
                tied_with: vec![],
            };
            evals.push((rep, after, m, sd / (diffs.len() as f64).sqrt()));
        }
        let total_before: f64 = before.iter().map(|x| x * x).sum();
        let significant = |e: &(EffectReport, Vec<f64>, f64, f64)| {
            let total_after: f64 = e.0.heldout_rms_after.iter().map(|x| x * x).sum();
            e.0.z > 3.0 && e.0.delta_bic < -10.0 && total_after < 0.98 * total_before
        };
        // rank by held-out improvement per the BIC-preferred order: first the
        // held-out gain, ties broken by fewer parameters
        evals.sort_by(|a, b| b.2.total_cmp(&a.2));
        let best_idx = evals.iter().position(|e| significant(e));
        if let Some(bi) = best_idx {
            let (bm, bse) = (evals[bi].2, evals[bi].3);
            let tied: Vec<usize> = (0..evals.len())
                .filter(|&j| {
                    j != bi
                        && significant(&evals[j])
                        && evals[j].2 >= bm - 2.0 * bse.max(evals[j].3)
                })
                .collect();
            // among tied candidates the penalised criterion decides: a
            // 1-parameter effect beats a 30-parameter refit that explains
            // the same on the training part
            let mut group: Vec<usize> = tied.clone();
            group.push(bi);
            group.sort_by(|&a, &b| {
                evals[a]
                    .0
                    .delta_bic
                    .total_cmp(&evals[b].0.delta_bic)
                    .then(evals[a].0.params.cmp(&evals[b].0.params))
            });
            let chosen = group[0];
            let names: Vec<String> = group
                .iter()
                .filter(|&&j| j != chosen)
                .map(|&j| evals[j].0.effect.clone())
                .collect();
            evals[chosen].0.accepted = true;
            evals[chosen].0.tied_with = names;
            r = evals[chosen].1.clone();
            accepted.push(evals[chosen].0.effect.clone());
            let chosen_rep = evals[chosen].0.clone();
            ranked.push(chosen_rep);
            for (j, e) in evals.iter().enumerate() {
                if j != chosen {
                    ranked.push(e.0.clone());
                }
            }
        } else {
            ranked.extend(evals.into_iter().map(|e| e.0));
            break;
        }
    }
    let final_rms = rms_per_joint(&r[va_rows.clone()], n);
    let per_joint = |v: &[f64]| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| {
                v[va_rows.clone()]
                    .iter()
                    .skip(i)
                    .step_by(n)
                    .copied()
                    .collect()
            })
            .collect()
    };
    let r_nominal: Vec<f64> = flat(&data.tau)
        .iter()
        .zip(flat(&pred))
        .map(|(a, b)| a - b)
        .collect();
    let heldout = HeldOut {
        t: val.t.clone(),
        q: (0..n)
            .map(|i| val.q.iter().map(|x| x[i]).collect())
            .collect(),
        qd: (0..n)
            .map(|i| val.qd.iter().map(|x| x[i]).collect())
            .collect(),
        nominal: per_joint(&r_nominal),
        after: per_joint(&r),
    };
    let where_final = where_of(&r);
    let gap_closed = (0..n)
        .map(|i| {
            if nominal[i] > noise_floor[i] {
                ((nominal[i] - final_rms[i]) / (nominal[i] - noise_floor[i])).clamp(-1.0, 1.0)
            } else {
                1.0
            }
        })
        .collect();
    let unexplained_joints: Vec<usize> = (0..n)
        .filter(|&i| final_rms[i] > 1.15 * noise_floor[i] && final_rms[i] - noise_floor[i] > 0.05)
        .collect();
    Ok(Diagnosis {
        joints: data.joints.clone(),
        summary: where_nominal.iter().map(summarise).collect(),
        where_: where_nominal,
        ranked_effects: ranked,
        accepted,
        heldout_rms_nominal: nominal,
        heldout_rms_final: final_rms,
        noise_floor,
        gap_closed,
        unexplained: !unexplained_joints.is_empty(),
        unexplained_where: unexplained_joints
            .iter()
            .map(|&i| summarise(&where_final[i]))
            .collect(),
        heldout,
    })
}

#[cfg(test)]
mod tests {
    use super::block_bootstrap_z;

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
