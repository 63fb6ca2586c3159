//! Solver results: status, values, duals, statistics.

use super::expr::{AffExpr, Var};
use super::matexpr::MatExpr;
use super::problem::{ConeKind, ConstraintId, SymVar};
use nalgebra::DMatrix;
use serde::Serialize;

/// How the solver ended. Every Clarabel status maps to exactly one of these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Optimal within the tolerances.
    Solved,
    /// Optimal within Clarabel's reduced tolerances.
    SolvedInaccurately,
    /// A certificate that no x satisfies the constraints.
    PrimalInfeasible,
    /// As [`Status::PrimalInfeasible`], reduced accuracy.
    PrimalInfeasibleInaccurate,
    /// A certificate that the objective is unbounded below.
    DualInfeasible,
    /// As [`Status::DualInfeasible`], reduced accuracy.
    DualInfeasibleInaccurate,
    /// The iteration limit was reached.
    IterationLimit,
    /// The time limit was reached.
    TimeLimit,
    /// The solver hit a numerical error.
    NumericalError,
    /// The solver stopped making progress.
    InsufficientProgress,
    /// The solver did not run.
    NotSolved,
}

impl Status {
    /// Solved, accurately or not.
    pub fn is_solved(self) -> bool {
        matches!(self, Status::Solved | Status::SolvedInaccurately)
    }
    /// Primal infeasible, accurately or not.
    pub fn is_primal_infeasible(self) -> bool {
        matches!(
            self,
            Status::PrimalInfeasible | Status::PrimalInfeasibleInaccurate
        )
    }
    /// Dual infeasible (unbounded), accurately or not.
    pub fn is_dual_infeasible(self) -> bool {
        matches!(
            self,
            Status::DualInfeasible | Status::DualInfeasibleInaccurate
        )
    }
    /// A short lower-case name (`solved`, `primal_infeasible`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Solved => "solved",
            Status::SolvedInaccurately => "solved_inaccurately",
            Status::PrimalInfeasible => "primal_infeasible",
            Status::PrimalInfeasibleInaccurate => "primal_infeasible_inaccurate",
            Status::DualInfeasible => "dual_infeasible",
            Status::DualInfeasibleInaccurate => "dual_infeasible_inaccurate",
            Status::IterationLimit => "iteration_limit",
            Status::TimeLimit => "time_limit",
            Status::NumericalError => "numerical_error",
            Status::InsufficientProgress => "insufficient_progress",
            Status::NotSolved => "not_solved",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The dual of one constraint.
#[derive(Clone, Debug, PartialEq)]
pub enum Dual {
    /// One multiplier per row (equalities, inequalities, second-order cones).
    Vector(Vec<f64>),
    /// The full symmetric dual matrix Z of a PSD constraint (off-diagonals
    /// are Clarabel's `z/√2`).
    Matrix(DMatrix<f64>),
}

/// The result of a solve. Values are meaningful when
/// [`Status::is_solved`]; for an infeasible status the duals (primal
/// infeasibility) or x (dual infeasibility) hold Clarabel's certificate.
#[derive(Clone, Debug)]
pub struct Solution {
    /// How the solver ended.
    pub status: Status,
    /// Primal objective, in the problem's sense.
    pub primal_objective: f64,
    /// Dual objective, in the problem's sense.
    pub dual_objective: f64,
    pub(crate) x: Vec<f64>,
    pub(crate) raw_duals: Vec<Vec<f64>>,
    pub(crate) kinds: Vec<ConeKind>,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Clarabel's primal residual.
    pub primal_residual: f64,
    /// Clarabel's dual residual.
    pub dual_residual: f64,
    /// Compile + solver setup time, seconds.
    pub setup_time_s: f64,
    /// Interior-point solve time, seconds.
    pub solve_time_s: f64,
}

impl Solution {
    /// The primal point x (one entry per scalar variable).
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// Value of a scalar variable.
    pub fn value(&self, v: Var) -> f64 {
        self.x[v.0]
    }

    /// Values of several variables.
    pub fn values(&self, vs: &[Var]) -> Vec<f64> {
        vs.iter().map(|&v| self.x[v.0]).collect()
    }

    /// Value of an affine expression.
    pub fn eval(&self, e: &AffExpr) -> f64 {
        e.eval(&self.x)
    }

    /// Value of a matrix expression.
    pub fn eval_mat(&self, m: &MatExpr) -> DMatrix<f64> {
        m.eval(&self.x)
    }

    /// Value of a symmetric matrix variable.
    pub fn sym_value(&self, s: &SymVar) -> DMatrix<f64> {
        self.eval_mat(&s.expr())
    }

    /// The dual of a constraint (see [`Dual`]); `None` for a foreign id.
    pub fn dual(&self, id: ConstraintId) -> Option<Dual> {
        let z = self.raw_duals.get(id.0)?;
        Some(match self.kinds[id.0] {
            ConeKind::Psd { n } => Dual::Matrix(svec_to_mat(z, n)),
            _ => Dual::Vector(z.clone()),
        })
    }

    /// The raw dual entries of a constraint in row order (PSD: √2-scaled svec).
    pub fn raw_dual(&self, id: ConstraintId) -> Option<&[f64]> {
        self.raw_duals.get(id.0).map(Vec::as_slice)
    }
}

/// Clarabel's scaled upper-triangle vector back to a full symmetric matrix:
/// entry `(i, j)`, `i ≤ j`, is at `j(j+1)/2 + i`, off-diagonals divided by √2.
pub fn svec_to_mat(z: &[f64], n: usize) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(n, n);
    for j in 0..n {
        for i in 0..=j {
            let v = z[j * (j + 1) / 2 + i];
            if i == j {
                m[(i, i)] = v;
            } else {
                m[(i, j)] = v / std::f64::consts::SQRT_2;
                m[(j, i)] = m[(i, j)];
            }
        }
    }
    m
}
