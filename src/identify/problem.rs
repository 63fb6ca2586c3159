//! The identification problem (25) of the paper, built with `conic`:
//!
//! ```text
//! minimise    (1/n_s) Σ ‖Y π + B q̇ + B_c sign(q̇) − τ‖² + w_π ‖π − π̂‖²
//! subject to  per body, the chosen level: none | I(π) ⪰ εI | J(π) ⪰ εI
//!             | J(π) ⪰ εI and tr(J(π) Q) ≥ 0   [and the CoM LMI (22)],
//!             B ⪰ 0, B_c ⪰ 0 (diagonal, i.e. elementwise ≥ 0)
//! ```
//!
//! with the data entering only through the reduced factor `R, d`
//! ([`super::reduce`]). The unconstrained level is solved directly (SVD, no
//! interior point), so noise-free data are fitted to round-off. For the
//! constrained levels the variables are scaled by the column norms of R so
//! that every direction the data see has unit size, which keeps Clarabel's
//! tolerances from being what limits the fit.

use super::error::IdentifyError;
use super::reduce::Reduced;
use crate::conic::{AffExpr, Problem, Settings, Status};
use crate::dynamics::{Model, RobotDescription};
use crate::moments::{Ellipsoid, lmi::BodyVars};
use faer::Mat;
use serde::Serialize;

/// Per-body constraint level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    /// Ordinary least squares.
    None,
    /// Physical semi-consistency `I(π) ⪰ εI` (Theorem 1).
    Semi,
    /// Full consistency `J(π) ⪰ εI` (Theorem 3).
    Consistent,
    /// Consistency and density realizability in the body's ellipsoid (Theorem 4).
    Ellipsoid,
}

impl Level {
    /// From the CLI name.
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "none" => Level::None,
            "semi" => Level::Semi,
            "consistent" => Level::Consistent,
            "ellipsoid" => Level::Ellipsoid,
            _ => return None,
        })
    }

    /// The CLI name.
    pub fn as_str(self) -> &'static str {
        match self {
            Level::None => "none",
            Level::Semi => "semi",
            Level::Consistent => "consistent",
            Level::Ellipsoid => "ellipsoid",
        }
    }
}

/// Options of [`solve_identification`], validated at construction; what
/// depends on the model (the prior's and the ellipsoids' lengths) is checked
/// against it when solving.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    level: Level,
    weight: f64,
    prior: Vec<f64>,
    ellipsoids: Option<Vec<Ellipsoid>>,
    com_lmi: bool,
    eps: f64,
    settings: Settings,
}

/// The solver settings of the constrained levels: tolerances 1e-9, at most
/// 300 iterations.
pub fn default_settings() -> Settings {
    Settings::default()
        .tol_gap_abs(1e-9)
        .tol_gap_rel(1e-9)
        .tol_feas(1e-9)
        .max_iter(300)
}

impl IdentifyOptions {
    /// `level` for every body, no regularisation, no ellipsoids, no CoM
    /// LMI, `⪰ 0` LMIs.
    pub fn new(level: Level) -> Self {
        Self {
            level,
            weight: 0.0,
            prior: vec![],
            ellipsoids: None,
            com_lmi: false,
            eps: 0.0,
            settings: default_settings(),
        }
    }

    /// A robot's set-up: its CAD prior with weight `weight`, and its bounding
    /// ellipsoids when every body has exactly one (required, and an error
    /// naming the body otherwise, for [`Level::Ellipsoid`]).
    pub fn for_robot(
        robot: &RobotDescription,
        level: Level,
        weight: f64,
    ) -> Result<Self, IdentifyError> {
        let opts = Self::new(level).with_prior(weight, robot.prior_vector())?;
        match robot.single_ellipsoids() {
            Ok(e) => Ok(opts.with_ellipsoids(e)),
            Err(e) if level == Level::Ellipsoid => Err(e.into()),
            Err(_) => Ok(opts),
        }
    }

    /// Regularisation `w ‖π − π̂‖²` toward `prior` (10 per body, links then
    /// rotors); `w` ≥ 0 and finite (0: off), the prior finite.
    pub fn with_prior(mut self, weight: f64, prior: Vec<f64>) -> Result<Self, IdentifyError> {
        if !(weight >= 0.0 && weight.is_finite()) {
            return Err(IdentifyError::Option {
                option: "weight",
                message: format!("must be ≥ 0 and finite, got {weight}"),
            });
        }
        if let Some(k) = prior.iter().position(|x| !x.is_finite()) {
            return Err(IdentifyError::Option {
                option: "prior",
                message: format!("entry {k} is not finite ({})", prior[k]),
            });
        }
        self.weight = weight;
        self.prior = prior;
        Ok(self)
    }

    /// One bounding ellipsoid per body (the ellipsoid level and the CoM LMI).
    pub fn with_ellipsoids(mut self, ellipsoids: Vec<Ellipsoid>) -> Self {
        self.ellipsoids = Some(ellipsoids);
        self
    }

    /// Adds the CoM-in-ellipsoid LMI (22) (needs ellipsoids).
    pub fn with_com_lmi(mut self, on: bool) -> Self {
        self.com_lmi = on;
        self
    }

    /// Margin ε of the strict LMIs `⪰ εI` (≥ 0, finite).
    pub fn with_eps(mut self, eps: f64) -> Result<Self, IdentifyError> {
        if !(eps >= 0.0 && eps.is_finite()) {
            return Err(IdentifyError::Option {
                option: "eps",
                message: format!("must be ≥ 0 and finite, got {eps}"),
            });
        }
        self.eps = eps;
        Ok(self)
    }

    /// The solver settings of the constrained levels (default
    /// [`default_settings`]); validated here.
    pub fn with_settings(mut self, settings: Settings) -> Result<Self, IdentifyError> {
        settings.validate()?;
        self.settings = settings;
        Ok(self)
    }

    /// The constraint level.
    pub fn level(&self) -> Level {
        self.level
    }

    /// The regularisation weight.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// The prior (10 per body).
    pub fn prior(&self) -> &[f64] {
        &self.prior
    }

    /// The ellipsoids, if given.
    pub fn ellipsoids(&self) -> Option<&[Ellipsoid]> {
        self.ellipsoids.as_deref()
    }

    /// Checks the model-dependent lengths.
    fn check(&self, nb: usize) -> Result<(), IdentifyError> {
        if self.weight > 0.0 && self.prior.len() != 10 * nb {
            return Err(IdentifyError::Option {
                option: "prior",
                message: format!(
                    "{} numbers for {nb} bodies (10 per body) with weight {}",
                    self.prior.len(),
                    self.weight
                ),
            });
        }
        let needs_e = self.level == Level::Ellipsoid || (self.com_lmi && self.level != Level::None);
        let wrong_len = self.ellipsoids.as_ref().is_some_and(|e| e.len() != nb);
        if wrong_len || (needs_e && self.ellipsoids.is_none()) {
            return Err(IdentifyError::Option {
                option: "ellipsoids",
                message: format!(
                    "{} bounding ellipsoids for {nb} bodies; give one per body{}",
                    self.ellipsoids.as_ref().map_or(0, |e| e.len()),
                    if needs_e {
                        format!(" (the {} level needs them)", self.level.as_str())
                    } else {
                        String::new()
                    }
                ),
            });
        }
        Ok(())
    }
}

/// The solver's answer.
#[derive(Clone, Debug)]
pub struct Solved {
    /// θ = [π (links, rotors) | viscous | Coulomb].
    pub theta: Vec<f64>,
    /// Solver status (`solved` for the direct least squares).
    pub status: Status,
    /// Interior-point iterations (0 for the direct solve).
    pub iterations: u32,
    /// Solve time (s).
    pub solve_time_s: f64,
    /// Parameter directions the data do not excite (named by their largest components).
    pub unidentifiable: Vec<String>,
    /// Numerical rank of the reduced regressor.
    pub rank: usize,
}

/// Parameter names: `<body>.<m|hx|…>`, `viscous.<joint>`, `coulomb.<joint>`.
pub fn parameter_names(model: &Model) -> Vec<String> {
    const P: [&str; 10] = [
        "m", "hx", "hy", "hz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz",
    ];
    let mut v: Vec<String> = model
        .body_names()
        .iter()
        .flat_map(|b| P.iter().map(move |p| format!("{b}.{p}")))
        .collect();
    v.extend(model.joint_names().iter().map(|j| format!("viscous.{j}")));
    v.extend(model.joint_names().iter().map(|j| format!("coulomb.{j}")));
    v
}

/// Rank and unexcited directions of R (columns scaled to unit norm).
fn identifiability(r: &Mat<f64>, names: &[String]) -> Result<(usize, Vec<String>), IdentifyError> {
    let p = r.ncols();
    let scale: Vec<f64> = (0..p)
        .map(|j| {
            (0..r.nrows())
                .map(|i| r[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let mut rs = Mat::<f64>::zeros(r.nrows().max(p), p);
    for j in 0..p {
        let s = if scale[j] > 0.0 { 1.0 / scale[j] } else { 0.0 };
        for i in 0..r.nrows() {
            rs[(i, j)] = r[(i, j)] * s;
        }
    }
    let svd = rs.svd().map_err(|_| IdentifyError::Factorisation {
        what: "SVD of the reduced regressor (identifiability)",
    })?;
    let s = svd.S().column_vector();
    let smax = (0..s.nrows()).map(|i| s[i]).fold(0.0, f64::max);
    let tol = 1e-8 * smax.max(f64::MIN_POSITIVE);
    let rank = (0..s.nrows()).filter(|&i| s[i] > tol).count();
    let v = svd.V();
    let mut dirs = Vec::new();
    for k in 0..p {
        if k < s.nrows() && s[k] > tol {
            continue;
        }
        let mut comp: Vec<(usize, f64)> = (0..p).map(|j| (j, v[(j, k)])).collect();
        comp.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        let terms: Vec<String> = comp
            .iter()
            .take(3)
            .filter(|c| c.1.abs() > 0.05)
            .map(|&(j, c)| format!("{c:+.2}·{}", names[j]))
            .collect();
        dirs.push(terms.join(" "));
    }
    Ok((rank, dirs))
}

/// The unconstrained level: `min ‖[R/√ns; √w E] θ − [d/√ns; √w π̂]‖²`,
/// minimum norm, by SVD (so noise-free data are fitted to round-off).
fn solve_direct(
    r: &Mat<f64>,
    d: &[f64],
    ns: f64,
    opts: &IdentifyOptions,
    nb: usize,
) -> Result<Vec<f64>, IdentifyError> {
    let p = r.ncols();
    let w = opts.weight;
    let extra = if w > 0.0 { 10 * nb } else { 0 };
    let rows = r.nrows() + extra;
    let mut a = Mat::<f64>::zeros(rows.max(p), p);
    let mut b = Mat::<f64>::zeros(rows.max(p), 1);
    for i in 0..r.nrows() {
        for j in 0..p {
            a[(i, j)] = r[(i, j)] / ns.sqrt();
        }
        b[(i, 0)] = d[i] / ns.sqrt();
    }
    for k in 0..extra {
        a[(r.nrows() + k, k)] = w.sqrt();
        b[(r.nrows() + k, 0)] = w.sqrt() * opts.prior[k];
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
/// column norms of R, 1 for unexcited columns), with its objective; returns
/// the problem and θ as expressions of z.
fn scaled_problem(
    r: &Mat<f64>,
    d: &[f64],
    ns: f64,
    opts: &IdentifyOptions,
    nb: usize,
) -> Result<(Problem, Vec<AffExpr>), IdentifyError> {
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
    if opts.weight > 0.0 {
        prob.add_squares(1.0 / ns, residual_rows);
        for k in 0..10 * nb {
            prob.add_square(opts.weight, theta[k].clone() - opts.prior[k]);
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

/// After an infeasible solve: the first body whose own constraint set is
/// empty, else the status itself.
fn explain_infeasible(
    model: &Model,
    opts: &IdentifyOptions,
    status: Status,
) -> Result<IdentifyError, IdentifyError> {
    for (b, name) in model.body_names().iter().enumerate() {
        let mut q = Problem::new();
        let v = BodyVars::new(&mut q, name);
        let mut o = opts.clone();
        o.ellipsoids = opts.ellipsoids.as_ref().map(|e| vec![e[b]]);
        add_body_constraints(&mut q, &[v], &o, std::slice::from_ref(name))?;
        if q.solve(&opts.settings)?.status.is_primal_infeasible() {
            return Ok(IdentifyError::InfeasibleBody { body: name.clone() });
        }
    }
    Ok(IdentifyError::Solver(status))
}

/// Solves (25) on reduced data.
pub fn solve_identification(
    model: &Model,
    red: &Reduced,
    opts: &IdentifyOptions,
) -> Result<Solved, IdentifyError> {
    let nb = model.num_bodies();
    let p = 10 * nb + 2 * model.dof();
    if red.p != p {
        return Err(IdentifyError::Columns {
            expected: p,
            found: red.p,
        });
    }
    if red.samples == 0 {
        return Err(IdentifyError::NoTrainingData {
            samples: 0,
            torques: 0,
        });
    }
    opts.check(nb)?;
    let (r, d) = red.r_d()?;
    let (rank, unidentifiable) = identifiability(&r, &parameter_names(model))?;
    let ns = red.samples as f64;
    let t0 = std::time::Instant::now();
    if opts.level == Level::None {
        return Ok(Solved {
            theta: solve_direct(&r, &d, ns, opts, nb)?,
            status: Status::Solved,
            iterations: 0,
            solve_time_s: t0.elapsed().as_secs_f64(),
            unidentifiable,
            rank,
        });
    }
    let (mut prob, theta_expr) = scaled_problem(&r, &d, ns, opts, nb)?;
    let bodies: Vec<BodyVars> = (0..nb)
        .map(|b| BodyVars::from_exprs(std::array::from_fn(|k| theta_expr[10 * b + k].clone())))
        .collect();
    add_body_constraints(&mut prob, &bodies, opts, &model.body_names())?;
    prob.add_nonneg(theta_expr[10 * nb..].to_vec())?; // B ⪰ 0, B_c ⪰ 0
    let sol = prob.solve(&opts.settings)?;
    match sol.status {
        s if s.is_solved() => Ok(Solved {
            theta: sol.eval_all(&theta_expr)?,
            status: sol.status,
            iterations: sol.iterations,
            solve_time_s: sol.setup_time_s + sol.solve_time_s,
            unidentifiable,
            rank,
        }),
        s if s.is_primal_infeasible() => Err(explain_infeasible(model, opts, s)?),
        s => Err(IdentifyError::Solver(s)),
    }
}

fn add_body_constraints(
    prob: &mut Problem,
    bodies: &[BodyVars],
    opts: &IdentifyOptions,
    names: &[String],
) -> Result<(), IdentifyError> {
    for (b, body) in bodies.iter().enumerate() {
        let id = match opts.level {
            Level::None => continue,
            Level::Semi => prob.add_psd_eps(&body.spatial_inertia(), opts.eps)?,
            Level::Consistent | Level::Ellipsoid => {
                prob.add_psd_eps(&body.pseudo_inertia(), opts.eps)?
            }
        };
        prob.set_name(
            id,
            &format!("{} LMI of body '{}'", opts.level.as_str(), names[b]),
        )?;
        if let Some(e) = opts.ellipsoids.as_ref().map(|e| e[b]) {
            if opts.level == Level::Ellipsoid {
                let c = prob.add_ge(body.trace_jq(&e), 0.0)?;
                prob.set_name(c, &format!("tr(JQ) ≥ 0 of body '{}'", names[b]))?;
            }
            if opts.com_lmi {
                prob.add_psd(&body.com_lmi(&e))?;
            }
        }
    }
    Ok(())
}
