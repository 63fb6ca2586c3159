//! What the physics pins down when the data cannot: each parameter's range
//! over every model that satisfies the identification's constraints and
//! fits the data almost as well as the estimate,
//!
//! ```text
//! { θ : every body's level holds, friction ≥ 0, the caller's constraints,
//!       ‖R θ − d‖ ≤ (1 + δ) ‖R θ̂ − d‖ }
//! ```
//!
//! (`R, d` the reduced factor, θ̂ the estimate, which is inside), two conic
//! problems per parameter (its minimum and its maximum), solved in
//! parallel. A parameter whose range is narrow is pinned — by the data
//! when it is determined alone ([`Identifiability::determined_alone`]),
//! else by the physics — whatever the prior. The pseudo-inertia LMIs bound
//! a body's inertia by its mass and its size, so most ranges are finite;
//! one that is not is reported unbounded.

use super::builder::Identification;
use super::error::IdentifyError;
use super::identifiability::Identifiability;
use super::reduce::Reduced;
use crate::conic::{AffExpr, Problem};
use crate::moments::lmi::BodyVars;
use faer::Mat;
use rayon::prelude::*;
use serde::Serialize;

/// The box every parameter is kept in, in multiples of the robot's scale
/// (`add_box`).
pub const BOX: f64 = 100.0;

/// A parameter's end and what to know about it.
type End = (Option<f64>, Option<String>);

/// The solver's tolerances, tried in turn until one solves.
const RETRY_TOLERANCES: [f64; 3] = [1e-8, 1e-7, 1e-6];

/// The residual radius is at least this fraction of ‖d‖ (the torques'
/// norm), so that an exact fit's set is not a single point.
pub const FLOOR: f64 = 1e-6;

/// How much every box grows for the second solve: an end that moves with
/// it is held by a box, not by the data or the physics.
pub const BOX_GROWTH: f64 = 4.0;

/// A range no wider than this fraction of the parameter's scale is pinned.
pub const PINNED_FRACTION: f64 = 0.1;

/// What decides a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PinnedBy {
    /// Determined by the data alone, and narrow.
    Data,
    /// Not determined by the data alone, but narrow: the constraints pin it.
    Physics,
    /// Wide or unbounded: the prior decides it.
    Unknown,
}

/// One parameter's range.
#[derive(Clone, Debug, Serialize)]
pub struct ParamRange {
    /// `<body>.<m|hx|…>` or `<term>.<joint>`.
    pub name: String,
    /// The estimate.
    pub estimate: f64,
    /// The prior's value (bodies' parameters with a prior).
    pub prior: Option<f64>,
    /// The smallest value in the set; `None`: unbounded below (or the
    /// solve failed: `note` says).
    pub min: Option<f64>,
    /// The largest.
    pub max: Option<f64>,
    /// What decides it.
    pub pinned_by: PinnedBy,
    /// A solve that did not end in `solved` (its status).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The ranges of every parameter.
#[derive(Clone, Debug, Serialize)]
pub struct ParameterBounds {
    /// δ: the residual may grow by this fraction.
    pub delta: f64,
    /// The estimate's residual norm ‖R θ̂ − d‖ (N·m, over every row).
    pub residual: f64,
    /// Per parameter, in θ's order.
    pub ranges: Vec<ParamRange>,
}

impl Identification<'_> {
    /// Each parameter's range over the constrained models whose residual is
    /// at most `(1 + delta)` × the estimate `theta`'s, on reduced data `red`.
    pub fn parameter_bounds(
        &self,
        red: &Reduced,
        theta: &[f64],
        ident: &Identifiability,
        delta: f64,
    ) -> Result<ParameterBounds, IdentifyError> {
        if !(delta >= 0.0 && delta.is_finite()) {
            return Err(IdentifyError::Negative {
                option: "bounds delta",
                value: delta,
            });
        }
        if self.joint_weighting != super::JointWeighting::Equal
            || self
                .layout
                .terms
                .contains(&crate::dynamics::FrictionTerm::Load)
        {
            return Err(IdentifyError::Unsupported {
                what: "parameter bounds with noise-weighted joints or a load friction term (the estimate comes from other rows than these data)",
            });
        }
        let (r, d) = red.r_d()?;
        let residual = super::identifiability::rss(&r, &d, theta).sqrt();
        // a floor keeps an exact fit's set from being a single point
        let floor = FLOOR * d.iter().map(|v| v * v).sum::<f64>().sqrt();
        let radius = ((1.0 + delta) * residual).max(floor);
        let rows = red.samples * self.layout.rows;
        let half = self.box_halves(theta, rms_of(&d, rows));
        // an end that moves when every box grows is held by a box: no end
        let ends = self.ends((&r, &d), radius, &half)?;
        let wide: Vec<f64> = half.iter().map(|h| h * BOX_GROWTH).collect();
        let wider = self.ends((&r, &d), radius, &wide)?;
        let ends: Vec<End> = (ends.into_iter().zip(wider).enumerate())
            .map(|(i, (e, w))| match (e.0, w.0) {
                (Some(a), Some(b)) if (a - b).abs() <= 1e-5 * half[i / 2] => e,
                (Some(_), _) => (None, Some("unbounded (held only by the box)".into())),
                _ => e,
            })
            .collect();
        let names = self.layout.parameter_names();
        let nb = self.layout.num_bodies();
        let ranges = (0..theta.len())
            .map(|k| {
                let ((lo, n1), (hi, n2)) = (ends[2 * k].clone(), ends[2 * k + 1].clone());
                let prior = (k < self.prior.len()).then(|| self.prior[k]);
                ParamRange {
                    name: names[k].clone(),
                    estimate: theta[k],
                    prior,
                    min: lo,
                    max: hi,
                    pinned_by: pinned_by(k, lo, hi, scale(k, theta, prior, nb), ident),
                    note: n1.or(n2),
                }
            })
            .collect();
        Ok(ParameterBounds {
            delta,
            residual,
            ranges,
        })
    }

    /// Every parameter's minimum and maximum (2p ends, in parallel) over
    /// the set in the box `half`.
    fn ends(
        &self,
        (r, d): (&Mat<f64>, &[f64]),
        radius: f64,
        half: &[f64],
    ) -> Result<Vec<End>, IdentifyError> {
        let (prob, th) = self.feasible_set((r, d), radius, half)?;
        let base = &self.settings;
        let solve = |k: usize, sense: f64| -> Result<End, IdentifyError> {
            let mut q = prob.clone();
            q.minimize(th[k].clone() * sense);
            let mut note = None;
            for (i, tol) in RETRY_TOLERANCES.iter().enumerate() {
                let settings = (base.clone())
                    .tol_gap_abs(*tol)
                    .tol_gap_rel(*tol)
                    .tol_feas(*tol);
                let sol = q.solve(&settings)?;
                note = match sol.status {
                    s if s.is_solved() => {
                        let v = sol.eval(&th[k])?;
                        let tol_note = (i > 0).then(|| format!("solved at tolerance {tol:e}"));
                        let at_box = v.abs() >= (1.0 - 1e-3) * half[k];
                        return Ok(if at_box {
                            (None, Some("unbounded".into()))
                        } else {
                            (Some(v), tol_note)
                        });
                    }
                    s if s.is_dual_infeasible() => return Ok((None, Some("unbounded".into()))),
                    s => Some(format!("solver status {}", s.as_str())),
                };
            }
            Ok((None, note))
        };
        (0..2 * th.len())
            .into_par_iter()
            .map(|i| solve(i / 2, if i % 2 == 0 { 1.0 } else { -1.0 }))
            .collect()
    }

    /// The constraint set with `‖R θ − d‖ ≤ radius`, every parameter in
    /// its box `|θ_j| ≤ half_j`, in variables scaled by the box
    /// (θ_j = half_j z_j, |z_j| ≤ 1) and the residual by the radius;
    /// returns θ as expressions.
    fn feasible_set(
        &self,
        (r, d): (&Mat<f64>, &[f64]),
        radius: f64,
        half: &[f64],
    ) -> Result<(Problem, Vec<AffExpr>), IdentifyError> {
        let p = r.ncols();
        let mut prob = Problem::new();
        let z = prob.vector("z", p);
        let theta: Vec<AffExpr> = (0..p).map(|j| AffExpr::term(z[j], half[j])).collect();
        for &zj in &z {
            prob.add_le(zj, 1.0)?;
            prob.add_ge(zj, -1.0)?;
        }
        let rows: Vec<AffExpr> = (0..r.nrows())
            .map(|i| {
                let mut e = AffExpr::constant(-d[i] / radius);
                for j in 0..p {
                    e.add_term(z[j], r[(i, j)] * half[j] / radius);
                }
                e
            })
            .collect();
        prob.add_soc(AffExpr::constant(1.0), rows)?;
        let vars = self.vars(&theta);
        let bodies: Vec<BodyVars> = vars.bodies.iter().map(|(_, b)| b.clone()).collect();
        self.add_body_constraints(&mut prob, &bodies, &self.layout.bodies)?;
        self.friction_nonneg(&mut prob, &theta)?;
        for h in &self.hooks {
            h(&mut prob, &vars)?;
        }
        Ok((prob, theta))
    }

    /// Each parameter's box half-width, far beyond any real robot (so that
    /// every problem has a finite answer; an end at the box is reported
    /// unbounded): masses [`BOX`] × M (M the larger of the estimate's and
    /// the prior's total mass), first moments BOX × M·L, inertias
    /// BOX × M·L² (L the largest CoM distance, at least 1 m), friction
    /// coefficients BOX × the torques' RMS (per unit velocity for viscous).
    fn box_halves(&self, theta: &[f64], tau_rms: f64) -> Vec<f64> {
        let nb = self.layout.num_bodies();
        let total = |v: &[f64]| {
            (0..nb.min(v.len() / 10))
                .map(|b| v[10 * b].abs())
                .sum::<f64>()
        };
        let m = total(theta).max(total(&self.prior)).max(1e-3);
        let l = (0..nb)
            .filter(|&b| theta[10 * b] > 0.0)
            .map(|b| {
                (1..4)
                    .map(|i| theta[10 * b + i].powi(2))
                    .sum::<f64>()
                    .sqrt()
                    / theta[10 * b]
            })
            .fold(1.0, f64::max);
        (0..theta.len())
            .map(|k| {
                BOX * match (k < 10 * nb, k % 10) {
                    (true, 0) => m,
                    (true, 1..=3) => m * l,
                    (true, _) => m * l * l,
                    (false, _) => tau_rms.max(1e-3),
                }
            })
            .collect()
    }
}

/// The RMS of the torques behind `d` (‖d‖ over √rows: ‖d‖² is Σ τ²).
fn rms_of(d: &[f64], rows: usize) -> f64 {
    (d.iter().map(|v| v * v).sum::<f64>() / rows.max(1) as f64).sqrt()
}

/// The margin δ whose set is the data's joint confidence region at
/// `level` (e.g. 0.95) for `rank` identified directions and `rows` data
/// rows: `(1 + δ)² = 1 + χ²_rank(level) / (rows − rank)` (the χ²
/// approximation of the F-test's region; Gaussian, white residuals).
pub fn confidence_delta(rank: usize, rows: usize, level: f64) -> Result<f64, IdentifyError> {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let dof = rows.saturating_sub(rank);
    if rank == 0 || dof == 0 || !(level > 0.0 && level < 1.0) {
        return Err(IdentifyError::Negative {
            option: "bounds confidence (needs rows > rank > 0 and a level in (0, 1))",
            value: level,
        });
    }
    let chi = ChiSquared::new(rank as f64).map_err(|_| IdentifyError::Factorisation {
        what: "the χ² quantile of the bounds' confidence level",
    })?;
    Ok((1.0 + chi.inverse_cdf(level) / dof as f64).sqrt() - 1.0)
}

/// The margin δ whose range for each parameter is that parameter's own
/// interval at `level` (e.g. 0.95): the set's projection at
/// `(1 + δ)² = 1 + χ²₁(level) / (rows − rank)` (≈ ±1.96 σ at 0.95 for a
/// parameter the data determine). [`confidence_delta`] is the joint region
/// of all `rank` directions (wider: ±√χ²_rank σ).
pub fn marginal_delta(rank: usize, rows: usize, level: f64) -> Result<f64, IdentifyError> {
    let joint = confidence_delta(1, rows.saturating_sub(rank).saturating_add(1), level)?;
    Ok(joint)
}

/// The margin of [`Identification::parameter_bounds`] as a user writes
/// it: a number δ ≥ 0, or `auto` (the 95 % [`marginal_delta`], which needs
/// the fit's rank).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Margin {
    /// Each parameter's own 95 % interval.
    Auto,
    /// A given δ.
    Delta(f64),
}

impl Margin {
    /// `auto` or a finite number ≥ 0 (surrounding spaces ignored).
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim() {
            "auto" => Some(Margin::Auto),
            t => t
                .parse::<f64>()
                .ok()
                .filter(|d| *d >= 0.0 && d.is_finite())
                .map(Margin::Delta),
        }
    }

    /// δ for a fit of `rank` on `rows` rows.
    pub fn delta(self, rank: usize, rows: usize) -> Result<f64, IdentifyError> {
        match self {
            Margin::Auto => marginal_delta(rank, rows, 0.95),
            Margin::Delta(d) => Ok(d),
        }
    }
}

/// Parameter k's scale: the largest of its estimate, its prior and its
/// body's like parameters (the mass; the first moments' norm; the largest
/// diagonal inertia), so that a product of inertia near zero is judged
/// against its body's inertia.
fn scale(k: usize, theta: &[f64], prior: Option<f64>, nb: usize) -> f64 {
    let own = theta[k].abs().max(prior.map_or(0.0, f64::abs));
    let body = |b: usize, kind: &[usize]| {
        (kind.iter())
            .map(|&i| theta[10 * b + i].abs())
            .fold(0.0, f64::max)
    };
    let like = match (k / 10, k % 10) {
        (b, 1..=3) if b < nb => body(b, &[1, 2, 3]),
        (b, 4..=9) if b < nb => body(b, &[4, 7, 9]),
        _ => 0.0,
    };
    own.max(like)
}

/// Data, physics or unknown: narrow against `scale`, and determined alone.
fn pinned_by(
    k: usize,
    lo: Option<f64>,
    hi: Option<f64>,
    scale: f64,
    ident: &Identifiability,
) -> PinnedBy {
    let narrow = match (lo, hi) {
        (Some(lo), Some(hi)) => hi - lo <= PINNED_FRACTION * scale || hi - lo <= 1e-12,
        _ => false,
    };
    match (narrow, ident.determined_alone(k)) {
        (true, true) => PinnedBy::Data,
        (true, false) => PinnedBy::Physics,
        (false, _) => PinnedBy::Unknown,
    }
}
