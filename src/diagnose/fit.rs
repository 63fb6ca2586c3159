//! Fitting one candidate's columns to the residual: plain least squares, or
//! least squares with the pseudo-inertia LMIs for inertial corrections.

use super::candidate::Variant;
use super::error::FitError;
use crate::conic::{AffExpr, Problem, Settings, Status};
use crate::identify::Reduced;
use crate::moments::lmi::BodyVars;
use faer::Mat;
use faer::linalg::solvers::Solve;

/// Least squares `min ‖X β − r‖` over `rows` (tiny ridge for rank
/// deficiency), `XᵀX` from the columns' kept Gram matrix.
pub fn least_squares(
    c: &Variant,
    rows: std::ops::Range<usize>,
    r: &[f64],
) -> Result<Vec<f64>, FitError> {
    let all: Vec<usize> = (0..c.columns.cols.len()).collect();
    least_squares_on(c, &all, rows, r)
}

/// [`least_squares`] with only the columns `on` (the others' β are 0).
pub fn least_squares_on(
    c: &Variant,
    on: &[usize],
    rows: std::ops::Range<usize>,
    r: &[f64],
) -> Result<Vec<f64>, FitError> {
    let (k, m) = (c.columns.cols.len(), on.len());
    let xtx = c.gram(&rows);
    let mut g = Mat::<f64>::from_fn(m, m, |a, b| xtx[on[a] * k + on[b]]);
    let b = Mat::<f64>::from_fn(m, 1, |a, _| xtr(c, on[a], &rows, r));
    let tr: f64 = (0..m).map(|a| g[(a, a)]).sum::<f64>().max(1e-300);
    for a in 0..m {
        g[(a, a)] += 1e-10 * tr / m as f64;
    }
    let l = g
        .llt(faer::Side::Lower)
        .map_err(|_| FitError::Factorisation)?;
    let x = l.solve(&b);
    let mut beta = vec![0.0; k];
    for (a, &col) in on.iter().enumerate() {
        beta[col] = x[(a, 0)];
    }
    if beta.iter().all(|v| v.is_finite()) {
        Ok(beta)
    } else {
        Err(FitError::Factorisation)
    }
}

/// `X[:, a]ᵀ r` over `rows`.
fn xtr(c: &Variant, a: usize, rows: &std::ops::Range<usize>, r: &[f64]) -> f64 {
    rows.clone().map(|i| c.columns.cols[a][i] * r[i]).sum()
}

/// The Gram form `[X r]ᵀ[X r]` of the candidate's rows.
fn reduced(c: &Variant, rows: std::ops::Range<usize>, r: &[f64]) -> Result<Reduced, FitError> {
    let k = c.columns.cols.len();
    let xtx = c.gram(&rows);
    let mut gram = Mat::<f64>::zeros(k + 1, k + 1);
    for a in 0..k {
        for b in 0..k {
            gram[(a, b)] = xtx[a * k + b];
        }
        let v = xtr(c, a, &rows, r);
        gram[(a, k)] = v;
        gram[(k, a)] = v;
    }
    gram[(k, k)] = rows.clone().map(|i| r[i] * r[i]).sum();
    Reduced::from_gram(gram, rows.len()).map_err(|_| FitError::Factorisation)
}

/// The fit of a candidate: plain least squares, or — for inertial
/// corrections — least squares with `J(π_nominal + β) ⪰ 0` for every
/// corrected body (and β ≥ 0 for a payload mass), through `conic` with the
/// LMIs of `moments`, on the reduced (Gram) form of the rows. A status that
/// is not solved is an error; an inaccurate solve is flagged.
pub fn fit_candidate(
    c: &Variant,
    rows: std::ops::Range<usize>,
    r: &[f64],
) -> Result<Fit, FitError> {
    fit_with(c, rows, r, &Settings::default())
}

/// A candidate's coefficients.
#[derive(Debug)]
pub struct Fit {
    /// β, one per column.
    pub beta: Vec<f64>,
    /// The constrained fit was solved only to Clarabel's reduced tolerances.
    pub inaccurate: bool,
}

fn fit_with(
    v: &Variant,
    rows: std::ops::Range<usize>,
    r: &[f64],
    settings: &Settings,
) -> Result<Fit, FitError> {
    let c = &v.columns;
    if c.bodies.is_empty() && !c.nonneg {
        return least_squares(v, rows, r).map(|beta| Fit {
            beta,
            inaccurate: false,
        });
    }
    let k = c.cols.len();
    let red = reduced(v, rows, r)?;
    let (f, d) = red.r_d().map_err(|_| FitError::Factorisation)?;
    let scale: Vec<f64> = (0..k)
        .map(|j| {
            (0..f.nrows())
                .map(|i| f[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .map(|n| if n > 1e-12 { 1.0 / n } else { 1.0 })
        .collect();
    let mut p = Problem::new();
    let z = p.vector("beta", k);
    let beta: Vec<AffExpr> = (0..k).map(|j| AffExpr::term(z[j], scale[j])).collect();
    let t = p.scalar("t");
    let res: Vec<AffExpr> = (0..f.nrows())
        .map(|i| {
            let mut e = AffExpr::constant(-d[i]);
            for j in 0..k {
                e.add_term(z[j], f[(i, j)] * scale[j]);
            }
            e
        })
        .collect();
    p.add_soc(t, res)?;
    for (b, nominal) in c.bodies.iter().enumerate() {
        let pi = std::array::from_fn(|q| beta[10 * b + q].clone() + nominal[q]);
        p.add_psd(&BodyVars::from_exprs(pi).pseudo_inertia())?;
    }
    if c.nonneg {
        p.add_nonneg(beta.clone())?;
    }
    p.minimize(t);
    let sol = p.solve(settings)?;
    match sol.status {
        Status::Solved | Status::SolvedInaccurately => Ok(Fit {
            beta: sol.eval_all(&beta)?,
            inaccurate: sol.status == Status::SolvedInaccurately,
        }),
        s => Err(FitError::Status(s)),
    }
}

/// `r − Σ βᵢ colᵢ`.
pub fn apply(cols: &[Vec<f64>], beta: &[f64], r: &[f64]) -> Vec<f64> {
    let mut out = r.to_vec();
    for (c, b) in cols.iter().zip(beta) {
        for (o, x) in out.iter_mut().zip(c) {
            *o -= b * x;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Columns;

    fn columns(cols: Vec<Vec<f64>>, nonneg: bool) -> Variant {
        Variant::new(Columns {
            cols,
            nonneg,
            ..Columns::default()
        })
    }

    /// The Gram matrix kept from the first fit serves later residuals on
    /// the same rows and is not used for other rows.
    #[test]
    fn the_kept_gram_matrix_is_used_only_for_its_own_rows() {
        let x0: Vec<f64> = (0..60).map(|k| (k as f64 * 0.3).sin()).collect();
        let x1: Vec<f64> = (0..60).map(|k| ((k * k) as f64 * 0.01).cos()).collect();
        let r: Vec<f64> = (0..60)
            .map(|k| 2.0 * x0[k] - x1[k] + if k < 30 { 0.0 } else { 5.0 * x1[k] })
            .collect();
        let kept = columns(vec![x0.clone(), x1.clone()], false);
        let fresh = || columns(vec![x0.clone(), x1.clone()], false);
        let all = least_squares(&kept, 0..60, &r).unwrap();
        assert_eq!(all, least_squares(&fresh(), 0..60, &r).unwrap());
        // other rows, other coefficients: the first half sees 2, −1
        let half = least_squares(&kept, 0..30, &r).unwrap();
        assert!(
            (half[0] - 2.0).abs() < 1e-6 && (half[1] + 1.0).abs() < 1e-6,
            "{half:?}"
        );
        assert_eq!(half, least_squares(&fresh(), 0..30, &r).unwrap());
        // another residual on the kept rows
        let r2: Vec<f64> = x0.iter().map(|v| 3.0 * v).collect();
        let b = least_squares(&kept, 0..60, &r2).unwrap();
        assert!((b[0] - 3.0).abs() < 1e-6 && b[1].abs() < 1e-6, "{b:?}");
    }

    #[test]
    fn a_fit_that_fails_is_an_error_not_zeros() {
        let x: Vec<f64> = (0..50).map(|k| (k as f64 * 0.3).sin()).collect();
        let r: Vec<f64> = x.iter().map(|v| 2.0 * v + 0.01).collect();
        // the plain fit works and is not zero
        let b = fit_candidate(&columns(vec![x.clone()], false), 0..50, &r)
            .unwrap()
            .beta;
        assert!((b[0] - 2.0).abs() < 0.05, "{b:?}");
        // non-finite columns: the normal equations cannot be factorised
        let mut bad = x.clone();
        bad[7] = f64::NAN;
        let e = fit_candidate(&columns(vec![bad], false), 0..50, &r).unwrap_err();
        assert!(matches!(e, FitError::Factorisation), "{e}");
        // a constrained fit (β ≥ 0) whose solver stops early: its status, not zeros
        let tight = Settings::default().max_iter(1);
        let e = fit_with(&columns(vec![x.clone()], true), 0..50, &r, &tight).unwrap_err();
        assert!(matches!(e, FitError::Status(s) if !s.is_solved()), "{e}");
        // and with the default settings the same fit is solved
        let b = fit_candidate(&columns(vec![x], true), 0..50, &r)
            .unwrap()
            .beta;
        assert!((b[0] - 2.0).abs() < 0.05, "{b:?}");
    }
}
