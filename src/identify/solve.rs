//! Solving the identification problem (25) of the paper, built with `conic`:
//!
//! ```text
//! minimise    (1/n_s) Σ ‖Y π + Σ_t c_t φ_t(q̇) − τ‖² + w_π R(π, π̂)
//! subject to  per body, the chosen level: none | I(π) ⪰ εI | J(π) ⪰ εI
//!             | J(π) ⪰ εI and tr(J(π) Q) ≥ 0   [and the CoM LMI (22)],
//!             every friction coefficient c ≥ 0
//! ```
//!
//! with the friction law of [`crate::dynamics::friction`] (viscous B q̇ and
//! Coulomb B_c sign(q̇)), `R(π, π̂)` the [`super::Regularizer`]: `‖π − π̂‖²` (Euclidean),
//! `Σ_bodies d(J(π) ‖ J(π̂))` (entropic, the log-det divergence of
//! [`crate::moments::entropic_divergence`]) or its second-order term at the
//! prior (pullback, [`super::pullback`]), and the data entering only
//! through the reduced factor `R, d`
//! ([`super::reduce`]). The unconstrained level is solved directly (SVD, no
//! interior point), so noise-free data are fitted to round-off. For the
//! constrained levels the variables are scaled by the column norms of R so
//! that every direction the data see has unit size, which keeps Clarabel's
//! tolerances from being what limits the fit.

use super::builder::{Identification, Vars};
use super::error::IdentifyError;
use super::identifiability::Identifiability;
use super::options::{IdentifyOptions, Level, MassWeight, Regularizer};
use super::reduce::Reduced;
use super::solved::Solved;
use crate::conic::{AffExpr, Problem, Status};
use crate::dynamics::Model;
use crate::moments::{MomentsError, add_entropic_divergence, lmi::BodyVars};
use faer::Mat;
use nalgebra::SMatrix;

/// Solves (25) on reduced data with the options' set-up
/// ([`Identification::from_options`]).
pub fn solve_identification(
    model: &Model,
    red: &Reduced,
    opts: &IdentifyOptions,
) -> Result<Solved, IdentifyError> {
    Identification::from_options(model, opts)?.solve(red)
}

impl Identification<'_> {
    /// Solves on reduced data.
    pub fn solve(&self, red: &Reduced) -> Result<Solved, IdentifyError> {
        let layout = &self.layout;
        let p = layout.columns();
        if red.p != p {
            return Err(IdentifyError::Columns {
                expected: p,
                found: red.p,
            });
        }
        if let Some(found) = red.row_range.clone().filter(|r| *r != layout.row_range()) {
            return Err(IdentifyError::RowCount {
                expected: layout.row_range(),
                found,
            });
        }
        if red.samples == 0 {
            return Err(IdentifyError::NoTrainingData {
                samples: 0,
                torques: 0,
            });
        }
        self.check()?;
        let (r, d) = red.r_d()?;
        // the identifiability analysis (an SVD) runs beside the solve
        let mut solved = std::thread::scope(|s| {
            let ident = s.spawn(|| Identifiability::of(&r, &layout.parameter_names()));
            let solved = self.solve_factored(&r, &d, red.samples);
            let identifiability = ident.join().unwrap_or(Err(IdentifyError::Factorisation {
                what: "the identifiability analysis (its thread panicked)",
            }))?;
            solved.map(|s| Solved {
                identifiability,
                ..s
            })
        })?;
        let rows = red.samples * layout.rows;
        (solved.identifiability).estimate(&r, &d, &solved.theta, rows)?;
        Ok(solved)
    }

    /// Solves on the factor `(R, d)` of `samples` samples; the
    /// identifiability report is left for the caller.
    fn solve_factored(
        &self,
        r: &Mat<f64>,
        d: &[f64],
        samples: usize,
    ) -> Result<Solved, IdentifyError> {
        let layout = &self.layout;
        let nb = layout.num_bodies();
        let ns = samples as f64;
        let t0 = std::time::Instant::now();
        let pullback = self.pullback_factors()?;
        let reg = Prior {
            weight: self.weight,
            mass_weight: self.mass_weight(),
            values: self.prior.as_slice(),
            pullback: pullback.as_deref(),
        };
        let direct = self.hooks.is_empty() && !self.entropic();
        if direct && self.bodies.iter().all(|b| b.level == Level::None) {
            return Ok(Solved {
                theta: solve_direct(&r, &d, ns, reg, nb)?,
                terms: layout.terms.clone(),
                bodies: layout.bodies.clone(),
                joints: layout.joints.clone(),
                status: Status::Solved,
                iterations: 0,
                solve_time_s: t0.elapsed().as_secs_f64(),
                identifiability: Identifiability::default(),
            });
        }
        let (mut prob, theta) = scaled_problem(&r, &d, ns, reg, nb, !self.entropic())?;
        let vars = self.vars(&theta);
        let bodies: Vec<BodyVars> = vars.bodies.iter().map(|(_, b)| b.clone()).collect();
        self.add_body_constraints(&mut prob, &bodies, &layout.bodies)?;
        if self.entropic() {
            self.add_entropic(&mut prob, &bodies, &layout.bodies)?;
        }
        self.friction_nonneg(&mut prob, &theta)?;
        for h in &self.hooks {
            h(&mut prob, &vars)?;
        }
        // the pullback's squares span the bodies' scales (Ĵ⁻¹ of a rotor is
        // 1e5 of a link's): their Gram matrix leaves the solver inaccurate,
        // their QR factor in one cone does not (tests/entropic.rs)
        let settings = match pullback.is_some() {
            true => (self.settings.clone())
                .least_squares(crate::conic::LeastSquaresForm::SecondOrderCone),
            false => self.settings.clone(),
        };
        let sol = prob.solve(&settings)?;
        match sol.status {
            s if s.is_solved() => Ok(Solved {
                theta: sol.eval_all(&theta)?,
                terms: layout.terms.clone(),
                bodies: layout.bodies.clone(),
                joints: layout.joints.clone(),
                status: sol.status,
                iterations: sol.iterations,
                solve_time_s: sol.setup_time_s + sol.solve_time_s,
                identifiability: Identifiability::default(),
            }),
            s if s.is_primal_infeasible() => Err(self.explain_infeasible(s)?),
            s => Err(IdentifyError::Solver(s)),
        }
    }

    /// Every friction coefficient ≥ 0 but an offset's.
    pub(super) fn friction_nonneg(
        &self,
        prob: &mut Problem,
        theta: &[AffExpr],
    ) -> Result<(), IdentifyError> {
        let (l, n) = (&self.layout, self.layout.joints.len());
        for (k, t) in l.terms.iter().enumerate() {
            if !t.signed() {
                let c0 = l.friction_start(k);
                prob.add_nonneg(theta[c0..c0 + n].to_vec())?;
            }
        }
        Ok(())
    }

    /// The hook's view of θ.
    pub(super) fn vars(&self, theta: &[AffExpr]) -> Vars {
        let layout = &self.layout;
        let nb = layout.num_bodies();
        Vars {
            bodies: (layout.bodies.clone())
                .into_iter()
                .enumerate()
                .map(|(b, name)| {
                    (
                        name,
                        BodyVars::from_exprs(std::array::from_fn(|k| theta[10 * b + k].clone())),
                    )
                })
                .collect(),
            joints: layout.joints.clone(),
            friction: theta[10 * nb..].to_vec(),
            terms: layout.terms.clone(),
        }
    }

    /// Each body's level: `I ⪰ εI`, `J ⪰ εI`, and `tr(JQ) ≥ 0` (+ the CoM LMI).
    pub(super) fn add_body_constraints(
        &self,
        prob: &mut Problem,
        bodies: &[BodyVars],
        names: &[String],
    ) -> Result<(), IdentifyError> {
        for ((spec, body), name) in self.bodies.iter().zip(bodies).zip(names) {
            let id = match spec.level {
                Level::None => continue,
                Level::Semi => prob.add_psd_eps(&body.spatial_inertia(), self.eps)?,
                Level::Consistent | Level::Ellipsoid => body.add_consistent_eps(prob, self.eps)?,
            };
            prob.set_name(id, &format!("{} LMI of body '{name}'", spec.level.as_str()))?;
            if let Some(e) = spec.ellipsoid {
                if spec.level == Level::Ellipsoid {
                    let c = prob.add_ge(body.trace_jq(&e), 0.0)?;
                    prob.set_name(c, &format!("tr(JQ) ≥ 0 of body '{name}'"))?;
                }
                if self.com_lmi {
                    body.add_com_in(prob, &e)?;
                }
            }
        }
        Ok(())
    }

    /// The objective's `w Σ_b d(J_b ‖ Ĵ_b)`; a prior body that is not
    /// strictly consistent is an error naming it.
    fn add_entropic(
        &self,
        prob: &mut Problem,
        bodies: &[BodyVars],
        names: &[String],
    ) -> Result<(), IdentifyError> {
        let mut total = AffExpr::zero();
        for (b, (body, name)) in bodies.iter().zip(names).enumerate() {
            // `check` has matched the prior to the bodies when the weight is on
            let prior = self
                .prior_body(b)
                .ok_or_else(|| IdentifyError::NoPrior { body: name.clone() })?;
            let term = add_entropic_divergence(prob, body, &prior).map_err(|e| match e {
                MomentsError::NotPositiveSemidefinite { min_eig } => {
                    IdentifyError::PriorNotConsistent {
                        body: name.clone(),
                        min_eig,
                    }
                }
                MomentsError::Conic(e) => IdentifyError::Conic(e),
                e => IdentifyError::Prior {
                    body: name.clone(),
                    source: e,
                },
            })?;
            total += term.divergence * self.weight;
        }
        prob.minimize(total);
        Ok(())
    }

    /// After an infeasible solve: the first body whose own constraint set is
    /// empty, else the status itself (the caller's constraints conflict).
    fn explain_infeasible(&self, status: Status) -> Result<IdentifyError, IdentifyError> {
        for (b, name) in self.layout.bodies.iter().enumerate() {
            let mut q = Problem::new();
            let v = BodyVars::new(&mut q, name);
            let alone = Identification {
                model: self.model,
                layout: self.layout.clone(),
                common: self.common,
                bodies: vec![self.bodies[b]],
                weight: 0.0,
                mass_weight: MassWeight::default(),
                prior: vec![],
                regularizer: Regularizer::Euclidean,
                joint_weighting: Default::default(),
                com_lmi: self.com_lmi,
                eps: self.eps,
                settings: self.settings.clone(),
                max_memory: self.max_memory,
                hooks: vec![],
                robot: None,
                structural_rank: std::sync::OnceLock::new(),
            };
            alone.add_body_constraints(&mut q, &[v], std::slice::from_ref(name))?;
            if q.solve(&self.settings)?.status.is_primal_infeasible() {
                return Ok(IdentifyError::InfeasibleBody { body: name.clone() });
            }
        }
        Ok(IdentifyError::Solver(status))
    }
}

/// The prior's terms of the objective: `w ‖π − π̂‖²` (Euclidean) or
/// `w Σ_b ‖Lᵀ_b (π_b − π̂_b)‖²` (pullback, `Lᵀ` per body from
/// [`super::pullback::factors`]), and the masses' `w_m Σ_b (m_b − m̂_b)²`.
#[derive(Clone, Copy)]
struct Prior<'a> {
    weight: f64,
    mass_weight: f64,
    values: &'a [f64],
    pullback: Option<&'a [SMatrix<f64, 10, 10>]>,
}

impl Prior<'_> {
    /// Whether any term is on.
    fn on(&self) -> bool {
        self.weight > 0.0 || self.mass_weight > 0.0
    }

    /// The weight of `(π_k − π̂_k)²` in the objective (k over 10 per body,
    /// the mass first): the masses' extra weight, plus `weight` when the
    /// regulariser is the Euclidean one.
    fn weight_of(&self, k: usize, euclidean: bool) -> f64 {
        let mass = if k % 10 == 0 { self.mass_weight } else { 0.0 };
        let euclidean = euclidean && self.pullback.is_none();
        mass + if euclidean { self.weight } else { 0.0 }
    }

    /// The pullback prior's rows `(√w Lᵀ_b[r, ·], √w Lᵀ_b[r, ·] π̂_b)`: body
    /// b's parameters' coefficients and the right-hand side, ten per body.
    fn pullback_rows(&self) -> Vec<(usize, [f64; 10], f64)> {
        let (Some(factors), true) = (self.pullback, self.weight > 0.0) else {
            return vec![];
        };
        let sw = self.weight.sqrt();
        (factors.iter().enumerate())
            .flat_map(|(b, lt)| {
                let pi = &self.values[10 * b..10 * b + 10];
                (0..10).map(move |r| {
                    let row: [f64; 10] = std::array::from_fn(|l| sw * lt[(r, l)]);
                    let rhs = (0..10).map(|l| row[l] * pi[l]).sum();
                    (b, row, rhs)
                })
            })
            .collect()
    }
}

/// The unconstrained level: `min ‖[R/√ns; √W E] θ − [d/√ns; √W π̂]‖²`
/// (`W` the [`Prior`]'s weights), minimum norm, by SVD (so noise-free data
/// are fitted to round-off).
fn solve_direct(
    r: &Mat<f64>,
    d: &[f64],
    ns: f64,
    reg: Prior,
    nb: usize,
) -> Result<Vec<f64>, IdentifyError> {
    let (p, prior) = (r.ncols(), reg.values);
    let extra = if reg.on() { 10 * nb } else { 0 };
    let pullback = reg.pullback_rows();
    let rows = r.nrows() + extra + pullback.len();
    let mut a = Mat::<f64>::zeros(rows.max(p), p);
    let mut b = Mat::<f64>::zeros(rows.max(p), 1);
    for i in 0..r.nrows() {
        for j in 0..p {
            a[(i, j)] = r[(i, j)] / ns.sqrt();
        }
        b[(i, 0)] = d[i] / ns.sqrt();
    }
    for k in 0..extra {
        let w = reg.weight_of(k, true).sqrt();
        a[(r.nrows() + k, k)] = w;
        b[(r.nrows() + k, 0)] = w * prior[k];
    }
    for (i, (body, row, rhs)) in pullback.iter().enumerate() {
        let at = r.nrows() + extra + i;
        (0..10).for_each(|l| a[(at, 10 * body + l)] = row[l]);
        b[(at, 0)] = *rhs;
    }
    let svd = a.svd().map_err(|_| IdentifyError::Factorisation {
        what: "SVD of the least-squares problem",
    })?;
    let s = svd.S().column_vector();
    let smax = (0..s.nrows()).map(|i| s[i]).fold(0.0, f64::max);
    let u = svd.U();
    let v = svd.V();
    let mut theta = vec![0.0; p];
    for k in 0..s.nrows() {
        if s[k] <= 1e-13 * smax {
            continue;
        }
        let c: f64 = (0..a.nrows()).map(|i| u[(i, k)] * b[(i, 0)]).sum::<f64>() / s[k];
        for j in 0..p {
            theta[j] += c * v[(j, k)];
        }
    }
    Ok(theta)
}

/// The constrained levels' SDP in scaled variables θ = D z (D = 1 / the
/// column norms of R, 1 for unexcited columns), with its objective (the
/// Euclidean prior's squares when `prior_squares`); returns the problem and
/// θ as expressions of z.
fn scaled_problem(
    r: &Mat<f64>,
    d: &[f64],
    ns: f64,
    reg: Prior,
    nb: usize,
    prior_squares: bool,
) -> Result<(Problem, Vec<AffExpr>), IdentifyError> {
    let prior = reg.values;
    let p = r.ncols();
    let dscale: Vec<f64> = (0..p)
        .map(|j| {
            let c = (0..r.nrows())
                .map(|i| r[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
                / ns.sqrt();
            if c > 1e-12 { 1.0 / c } else { 1.0 }
        })
        .collect();
    let mut prob = Problem::new();
    let z = prob.vector("z", p);
    let theta: Vec<AffExpr> = (0..p).map(|j| AffExpr::term(z[j], dscale[j])).collect();
    let residual_rows: Vec<AffExpr> = (0..r.nrows())
        .map(|i| {
            let mut e = AffExpr::constant(-d[i]);
            for j in 0..p {
                if r[(i, j)] != 0.0 {
                    e.add_term(z[j], r[(i, j)] * dscale[j]);
                }
            }
            e
        })
        .collect();
    if reg.on() {
        prob.add_squares(1.0 / ns, residual_rows);
        for k in 0..10 * nb {
            let w = reg.weight_of(k, prior_squares);
            if w > 0.0 {
                prob.add_square(w, theta[k].clone() - prior[k]);
            }
        }
        for (body, row, rhs) in reg.pullback_rows() {
            let mut e = AffExpr::constant(-rhs);
            (0..10).for_each(|l| e.axpy(row[l], &theta[10 * body + l]));
            prob.add_square(1.0, e);
        }
    } else {
        // Without regularisation, minimise the residual norm itself (same
        // minimiser): the solver's gap tolerance then bounds ‖r‖, not ‖r‖²,
        // so noise-free data are fitted to ~1e-9 instead of ~1e-5.
        let t = prob.scalar("residual_norm");
        prob.add_soc(
            t,
            residual_rows
                .into_iter()
                .map(|e| e * (1.0 / ns.sqrt()))
                .collect(),
        )?;
        prob.minimize(t);
    }
    Ok((prob, theta))
}
