//! Fitting groups of columns together on a union of folds: least squares
//! from the kept normal equations, or — when a group carries constraints
//! and they are enforced — the same least squares through `conic`, with
//! the pseudo-inertia LMIs of `moments` for bodies (a corrected link stays
//! physically consistent, a payload is a body of its own) and bounds on
//! coefficients (a friction coefficient stays ≥ 0).

use super::error::FitError;
use super::store::Store;
use crate::conic::{AffExpr, Problem, Settings, Status};
use crate::identify::Reduced;
use crate::moments::lmi::BodyVars;
use faer::Mat;
use faer::linalg::solvers::Solve;

/// Columns fitted together, with what constrains their coefficients.
#[derive(Clone, Debug, Default)]
pub struct Group {
    /// Column ids in the [`Store`].
    pub ids: Vec<usize>,
    /// The `10·b` coefficients from [`Group::bodies_at`] correct these
    /// bodies (paper's order): `J(π_b + β_b) ⪰ 0` each.
    pub bodies: Vec<[f64; 10]>,
    /// Where the bodies' coefficients start (0 but in the law's group,
    /// whose friction columns come first).
    pub bodies_at: usize,
    /// Every coefficient ≥ 0.
    pub nonneg: bool,
    /// A lower bound per coefficient (`-∞`: none).
    pub lower: Option<Vec<f64>>,
    /// The coefficients already applied (a refinement's step from them;
    /// zeros for the final fit): a constrained fit of such groups has a
    /// ridge pulling their sum with the step toward zero, in the units of
    /// the bodies before them ([`RIDGE`]); `None`: no ridge (scoring).
    pub applied: Option<Vec<f64>>,
}

impl Group {
    /// The same, fitted with the ridge of reported sizes (nothing applied
    /// yet when nothing was).
    pub fn reported(&self) -> Self {
        Self {
            applied: Some(
                self.applied
                    .clone()
                    .unwrap_or_else(|| vec![0.0; self.ids.len()]),
            ),
            ..self.clone()
        }
    }

    /// Plain columns.
    #[cfg(test)]
    pub fn plain(ids: Vec<usize>) -> Self {
        Self {
            ids,
            ..Self::default()
        }
    }

    /// Whether its coefficients are constrained.
    pub fn constrained(&self) -> bool {
        !self.bodies.is_empty()
            || self.nonneg
            || (self.lower.as_ref()).is_some_and(|l| l.iter().any(|x| x.is_finite()))
    }

    /// Appends the unbounded columns `ids` of the bodies `bodies` (10
    /// columns each, in the paper's order): `J(π_b + β_b) ⪰ 0` each.
    pub fn push_bodies(&mut self, ids: &[usize], bodies: Vec<[f64; 10]>) {
        self.bodies_at = self.ids.len();
        self.bodies = bodies;
        self.ids.extend(ids);
        if let Some(lower) = self.lower.as_mut() {
            lower.extend(std::iter::repeat_n(f64::NEG_INFINITY, ids.len()));
        }
    }

    /// The group with only the columns at `keep` (by position), keeping a
    /// lower bound per column; bodies and the sign stay only when all are kept.
    pub fn only(&self, keep: &[usize]) -> Self {
        if keep.len() == self.ids.len() {
            return self.clone();
        }
        Self {
            ids: keep.iter().map(|&a| self.ids[a]).collect(),
            bodies: vec![],
            bodies_at: 0,
            nonneg: self.nonneg,
            lower: (self.lower.as_ref()).map(|l| keep.iter().map(|&a| l[a]).collect()),
            applied: (self.applied.as_ref()).map(|l| keep.iter().map(|&a| l[a]).collect()),
        }
    }
}

/// The coefficients of `groups` (concatenated) fitted on the folds `on`
/// (and the rows outside the folds where the store has them, [`Store::with_prior`]);
/// the constraints of group g are enforced when `enforce[g]`. A solve that
/// is not solved is an error; an inaccurate one is flagged.
pub fn fit(
    store: &Store,
    groups: &[&Group],
    on: &[bool],
    enforce: &[bool],
) -> Result<Fit, FitError> {
    let ids: Vec<usize> = groups.iter().flat_map(|g| g.ids.iter().copied()).collect();
    let (g, b, rr) = store.with_prior(&ids, store.normal(&ids, on));
    fit_normal(&g, &b, rr, groups, enforce)
}

/// [`fit`] from the normal equations `XᵀX = g`, `Xᵀr = b`, `rᵀr = rr` of
/// the groups' columns.
pub fn fit_normal(
    g: &Mat<f64>,
    b: &[f64],
    rr: f64,
    groups: &[&Group],
    enforce: &[bool],
) -> Result<Fit, FitError> {
    let active = (groups.iter().zip(enforce)).any(|(g, e)| *e && g.constrained());
    let mut fit = match active {
        false => least_squares(g, b).map(|beta| Fit {
            beta,
            inaccurate: false,
            rss: 0.0,
        })?,
        true => constrained(g, b, rr, groups, enforce, &Settings::default())?,
    };
    fit.rss = rss(g, b, rr, &fit.beta);
    Ok(fit)
}

/// `‖Xβ − r‖²` from the normal equations (at least 0).
fn rss(g: &Mat<f64>, b: &[f64], rr: f64, beta: &[f64]) -> f64 {
    let m = beta.len();
    let quad: f64 = (0..m)
        .map(|i| beta[i] * (0..m).map(|j| g[(i, j)] * beta[j]).sum::<f64>())
        .sum();
    let lin: f64 = beta.iter().zip(b).map(|(x, y)| x * y).sum();
    (rr - 2.0 * lin + quad).max(0.0)
}

/// A fit's coefficients.
#[derive(Clone, Debug)]
pub struct Fit {
    /// β, one per column of the groups, in order.
    pub beta: Vec<f64>,
    /// The constrained fit was solved only to Clarabel's reduced tolerances.
    pub inaccurate: bool,
    /// The residual sum of squares on the rows fitted.
    pub rss: f64,
}

/// The ridge of a constrained fit: a change of each coefficient by its
/// unit ([`units`]) costs this share of the residual's sum of squares
/// (directions the rows do not determine stay at zero change).
const RIDGE: f64 = 1e-6;

/// `min ‖Xβ − r‖²` from `XᵀX = g`, `Xᵀr = b`: the columns scaled to unit
/// norm and a ridge of 1e-9 on the scaled diagonal (directions the rows do
/// not determine stay at zero).
pub fn least_squares(g: &Mat<f64>, b: &[f64]) -> Result<Vec<f64>, FitError> {
    let m = b.len();
    if m == 0 {
        return Ok(vec![]);
    }
    let s: Vec<f64> = (0..m)
        .map(|a| match g[(a, a)] {
            d if d > 0.0 && d.is_finite() => 1.0 / d.sqrt(),
            _ => 1.0,
        })
        .collect();
    let mut gs = Mat::<f64>::from_fn(m, m, |a, c| g[(a, c)] * s[a] * s[c]);
    for a in 0..m {
        gs[(a, a)] += 1e-9;
    }
    let rhs = Mat::<f64>::from_fn(m, 1, |a, _| b[a] * s[a]);
    let l = gs
        .llt(faer::Side::Lower)
        .map_err(|_| FitError::Factorisation)?;
    let z = l.solve(&rhs);
    let beta: Vec<f64> = (0..m).map(|a| z[(a, 0)] * s[a]).collect();
    match beta.iter().all(|v| v.is_finite()) {
        true => Ok(beta),
        false => Err(FitError::Factorisation),
    }
}

/// The least squares of `groups` with their enforced constraints, on the
/// reduced (Gram) form `[X r]ᵀ[X r]`.
fn constrained(
    g: &Mat<f64>,
    b: &[f64],
    rr: f64,
    groups: &[&Group],
    enforce: &[bool],
    settings: &Settings,
) -> Result<Fit, FitError> {
    let k = b.len();
    let gram = Mat::<f64>::from_fn(k + 1, k + 1, |i, j| match (i == k, j == k) {
        (false, false) => g[(i, j)],
        (false, true) => b[i],
        (true, false) => b[j],
        (true, true) => rr,
    });
    let red = Reduced::from_gram(gram, 1).map_err(|_| FitError::Factorisation)?;
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
    let mut res: Vec<AffExpr> = (0..f.nrows())
        .map(|i| {
            let mut e = AffExpr::constant(-d[i]);
            (0..k).for_each(|j| e.add_term(z[j], f[(i, j)] * scale[j]));
            e
        })
        .collect();
    // a ridge on the coefficients in their own units, a change of a body's
    // own size costing RIDGE of the residual's sum of squares: a direction
    // the rows do not determine (a link's mass that enters no torque)
    // stays at zero change instead of wherever the constraints let it go.
    // Only for a fit whose sizes are reported (groups with `applied`): the
    // candidates' scoring fits without it.
    if groups.iter().any(|g| g.applied.is_some()) {
        let (units, applied) = units(groups);
        let mu = (RIDGE * rr.max(f64::MIN_POSITIVE)).sqrt();
        res.extend((0..k).map(|j| {
            let mut e = AffExpr::constant(mu * applied[j] / units[j]);
            e.add_term(z[j], mu * scale[j] / units[j]);
            e
        }));
    }
    p.add_soc(t, res)?;
    let mut at = 0;
    for (grp, on) in groups.iter().zip(enforce) {
        let mine = &beta[at..at + grp.ids.len()];
        at += grp.ids.len();
        if *on {
            constrain(&mut p, grp, mine)?;
        }
    }
    p.minimize(t);
    let sol = p.solve(settings)?;
    match sol.status {
        Status::Solved | Status::SolvedInaccurately => Ok(Fit {
            beta: sol.eval_all(&beta)?,
            inaccurate: sol.status == Status::SolvedInaccurately,
            rss: 0.0,
        }),
        s => Err(FitError::Status(s)),
    }
}

/// The bodies `bodies` changed by `by` (10 coefficients each, in order):
/// where a step's constraints `J(π + by + Δ) ⪰ 0` are taken.
pub fn moved_bodies(bodies: &[[f64; 10]], by: &[f64]) -> Vec<[f64; 10]> {
    (bodies.iter().enumerate())
        .map(|(b, p)| std::array::from_fn(|q| p[q] + by[10 * b + q]))
        .collect()
}

/// Each coefficient's unit for the ridge — 1, but a body's parameters
/// relative to its size before any change (a mass of its mass, at least
/// 1 kg; a first moment of that mass at 0.1 m; a second moment of it at
/// 0.1 m squared) — and the coefficients already applied.
fn units(groups: &[&Group]) -> (Vec<f64>, Vec<f64>) {
    let (mut out, mut applied) = (vec![], vec![]);
    for g in groups {
        let a = g.applied.clone().unwrap_or_else(|| vec![0.0; g.ids.len()]);
        let mut u = vec![1.0; g.ids.len()];
        for (b, nominal) in g.bodies.iter().enumerate() {
            let at = g.bodies_at + 10 * b;
            let m = (nominal[0] - a[at]).abs().max(1.0);
            for (q, x) in u[at..at + 10].iter_mut().enumerate() {
                *x = m * match q {
                    0 => 1.0,
                    1..=3 => 0.1,
                    _ => 0.01,
                };
            }
        }
        out.extend(u);
        applied.extend(a);
    }
    (out, applied)
}

/// Adds `grp`'s constraints on its coefficients `beta` to `p`.
fn constrain(p: &mut Problem, grp: &Group, beta: &[AffExpr]) -> Result<(), FitError> {
    for (b, nominal) in grp.bodies.iter().enumerate() {
        let at = grp.bodies_at + 10 * b;
        let pi = std::array::from_fn(|q| beta[at + q].clone() + nominal[q]);
        p.add_psd(&BodyVars::from_exprs(pi).pseudo_inertia())?;
    }
    if grp.nonneg {
        p.add_nonneg(beta.to_vec())?;
    }
    if let Some(lower) = &grp.lower {
        for (e, &lo) in beta.iter().zip(lower) {
            if lo.is_finite() {
                p.add_ge(e.clone(), AffExpr::constant(lo))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{Group, fit};
    use crate::diagnose::folds::Folds;
    use crate::diagnose::store::Store;

    /// Two columns and a residual `2 x₀ − x₁`: least squares recovers the
    /// coefficients on any folds; a bound at 0 on the second holds it at 0
    /// (and the first then takes what it can).
    #[test]
    fn fits_plain_and_bounded() {
        let samples = 200;
        let x0: Vec<f64> = (0..samples).map(|k| (k as f64 * 0.3).sin()).collect();
        let x1: Vec<f64> = (0..samples).map(|k| (k as f64 * 0.05).cos()).collect();
        let r: Vec<f64> = (0..samples).map(|k| 2.0 * x0[k] - x1[k]).collect();
        let folds = Folds {
            ranges: vec![0..100, 100..200],
            fit: 1,
            by_file: false,
        };
        let mut s = Store::new(r, 1, &folds);
        let ids = s.add_all(vec![x0, x1]);
        let g = Group::plain(ids.clone());
        for on in [[true, true], [true, false], [false, true]] {
            let b = fit(&s, &[&g], &on, &[true]).unwrap().beta;
            assert!(
                (b[0] - 2.0).abs() < 1e-6 && (b[1] + 1.0).abs() < 1e-6,
                "{b:?}"
            );
        }
        let bounded = Group {
            lower: Some(vec![f64::NEG_INFINITY, 0.0]),
            ..g.clone()
        };
        let b = fit(&s, &[&bounded], &[true, true], &[true]).unwrap().beta;
        assert!(b[1].abs() < 1e-6, "{b:?}");
        // not enforced: the plain fit
        let b = fit(&s, &[&bounded], &[true, true], &[false]).unwrap().beta;
        assert!((b[1] + 1.0).abs() < 1e-6, "{b:?}");
    }
}
