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

use super::reduce::Reduced;
use crate::conic::{AffExpr, Problem, Settings, Status};
use crate::dynamics::Model;
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

/// Options of [`solve_identification`].
#[derive(Clone, Debug)]
pub struct IdentifyOptions {
    /// Constraint level for every body.
    pub level: Level,
    /// Regularisation weight `w_π` toward the prior (0: off).
    pub weight: f64,
    /// Prior π̂ (10 per body, links then rotors).
    pub prior: Vec<f64>,
    /// Bounding ellipsoid per body (needed for [`Level::Ellipsoid`] and the CoM LMI).
    pub ellipsoids: Option<Vec<Ellipsoid>>,
    /// Add the CoM-in-ellipsoid LMI (22).
    pub com_lmi: bool,
    /// Margin ε of the strict LMIs (0: `⪰ 0`).
    pub eps: f64,
}

impl IdentifyOptions {
    /// The built-in `cheetah3-leg` set-up: the box CAD model as prior,
    /// its bounding ellipsoids, no CoM LMI, `⪰ 0` LMIs.
    pub fn cheetah3(level: Level, weight: f64) -> Self {
        use crate::dynamics::cheetah3;
        let prior = cheetah3::model_with(&cheetah3::cad_params())
            .map(|m| m.params())
            .unwrap_or_default();
        Self {
            level,
            weight,
            prior,
            ellipsoids: Some(cheetah3::ellipsoids().to_vec()),
            com_lmi: false,
            eps: 0.0,
        }
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

/// What can go wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// Bad options or data.
    #[error("{0}")]
    Invalid(String),
    /// A body whose constraint set is empty.
    #[error("the constraint set of body '{body}' is infeasible")]
    InfeasibleBody {
        /// The body.
        body: String,
    },
    /// The solver failed.
    #[error("the solver ended with status {0}")]
    Solver(Status),
    /// The conic layer failed.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
    /// Data problems.
    #[error(transparent)]
    Data(#[from] crate::data::DataError),
    /// Model problems.
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
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
fn identifiability(r: &Mat<f64>, names: &[String]) -> (usize, Vec<String>) {
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
    let Ok(svd) = rs.svd() else {
        return (0, vec![]);
    };
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
    (rank, dirs)
}

/// Solves (25) on reduced data.
pub fn solve_identification(
    model: &Model,
    red: &Reduced,
    opts: &IdentifyOptions,
) -> Result<Solved, IdentifyError> {
    let nb = model.num_bodies();
    let n = model.dof();
    let p = 10 * nb + 2 * n;
    if red.p != p {
        return Err(IdentifyError::Invalid(format!(
            "reduced data have {} columns, the model needs {p}",
            red.p
        )));
    }
    if red.samples == 0 {
        return Err(IdentifyError::Invalid("no training samples".into()));
    }
    if !(opts.weight >= 0.0 && opts.weight.is_finite())
        || (opts.weight > 0.0 && opts.prior.len() != 10 * nb)
    {
        return Err(IdentifyError::Invalid(format!(
            "the weight must be ≥ 0 with a prior of {} numbers",
            10 * nb
        )));
    }
    let needs_e = opts.level == Level::Ellipsoid || (opts.com_lmi && opts.level != Level::None);
    if needs_e && opts.ellipsoids.as_ref().is_none_or(|e| e.len() != nb) {
        return Err(IdentifyError::Invalid(format!(
            "the ellipsoid level needs one bounding ellipsoid per body ({nb})"
        )));
    }
    let names = parameter_names(model);
    let r = red.r();
    let d = red.d();
    let (rank, unidentifiable) = identifiability(&r, &names);
    let ns = red.samples as f64;
    let t0 = std::time::Instant::now();
    if opts.level == Level::None {
        // direct: min ‖[R/√ns; √w E] θ − [d/√ns; √w π̂]‖², min-norm via SVD
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
        let svd = a
            .svd()
            .map_err(|_| IdentifyError::Invalid("SVD did not converge".into()))?;
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
        return Ok(Solved {
            theta,
            status: Status::Solved,
            iterations: 0,
            solve_time_s: t0.elapsed().as_secs_f64(),
            unidentifiable,
            rank,
        });
    }
    // scaled variables θ = D z, D = 1 / column norms of R (1 for unexcited columns)
    let colnorm: Vec<f64> = (0..p)
        .map(|j| {
            (0..r.nrows())
                .map(|i| r[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
                / ns.sqrt()
        })
        .collect();
    let dscale: Vec<f64> = colnorm
        .iter()
        .map(|&c| if c > 1e-12 { 1.0 / c } else { 1.0 })
        .collect();
    let mut prob = Problem::new();
    let z = prob.vector("z", p);
    let theta_expr: Vec<AffExpr> = (0..p).map(|j| AffExpr::term(z[j], dscale[j])).collect();
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
            prob.add_square(opts.weight, theta_expr[k].clone() - opts.prior[k]);
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
    let bodies: Vec<BodyVars> = (0..nb)
        .map(|b| BodyVars::from_exprs(std::array::from_fn(|k| theta_expr[10 * b + k].clone())))
        .collect();
    add_body_constraints(&mut prob, &bodies, opts, &model.body_names())?;
    prob.add_nonneg(theta_expr[10 * nb..].to_vec())?;
    let settings = Settings::default()
        .tol_gap_abs(1e-9)
        .tol_gap_rel(1e-9)
        .tol_feas(1e-9)
        .max_iter(300);
    let sol = prob.solve(&settings)?;
    match sol.status {
        s if s.is_solved() => {
            let theta = (0..p).map(|j| sol.eval(&theta_expr[j])).collect();
            Ok(Solved {
                theta,
                status: sol.status,
                iterations: sol.iterations,
                solve_time_s: sol.setup_time_s + sol.solve_time_s,
                unidentifiable,
                rank,
            })
        }
        s if s.is_primal_infeasible() => {
            // find the body whose own constraint set is empty
            for (b, name) in model.body_names().iter().enumerate() {
                let mut q = Problem::new();
                let v = BodyVars::new(&mut q, name);
                let mut o = opts.clone();
                o.ellipsoids = opts.ellipsoids.as_ref().map(|e| vec![e[b]]);
                add_body_constraints(&mut q, &[v], &o, std::slice::from_ref(name))?;
                if q.solve(&Settings::default())?.status.is_primal_infeasible() {
                    return Err(IdentifyError::InfeasibleBody { body: name.clone() });
                }
            }
            Err(IdentifyError::Solver(s))
        }
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
        );
        if let Some(e) = opts.ellipsoids.as_ref().map(|e| e[b]) {
            if opts.level == Level::Ellipsoid {
                let c = prob.add_ge(body.trace_jq(&e), 0.0)?;
                prob.set_name(c, &format!("tr(JQ) ≥ 0 of body '{}'", names[b]));
            }
            if opts.com_lmi {
                prob.add_psd(&body.com_lmi(&e))?;
            }
        }
    }
    Ok(())
}
