//! Solver results: status, values, duals, statistics.

use super::error::ConicError;
use super::expr::{AffExpr, Var};
use super::matexpr::MatExpr;
use super::problem::{ConeKind, ConstraintId, Lineage, Sense, SymVar};
use super::status::Status;
use nalgebra::DMatrix;
use serde::Serialize;

/// What became of Clarabel's chordal decomposition in a solve
/// (see [`Decomposition`](super::Decomposition)).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case", tag = "decomposition", content = "reason")]
pub enum DecompositionOutcome {
    /// Decomposed, and the result passed the check against the original
    /// problem.
    Used,
    /// Decomposed on request without a check.
    Unchecked,
    /// The decomposed result failed the check (the reason says which
    /// residual); this result was solved again without decomposition.
    FellBack(String),
    /// Not decomposed: turned off, or no PSD cone had a pattern Clarabel
    /// splits.
    Off,
}

impl DecompositionOutcome {
    /// `used`, `unchecked`, `fell_back` or `off`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Used => "used",
            Self::Unchecked => "unchecked",
            Self::FellBack(_) => "fell_back",
            Self::Off => "off",
        }
    }
}

impl std::fmt::Display for DecompositionOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::FellBack(r) => write!(f, "fell_back ({r})"),
            o => f.write_str(o.as_str()),
        }
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

/// The result of a solve.
///
/// Values ([`value`](Self::value), [`eval`](Self::eval), …) are read only
/// when the status is solved (accurately or not); otherwise they are
/// [`ConicError::NotSolved`]. Duals are also read after a primal-infeasible
/// status (they hold Clarabel's certificate); [`x`](Self::x) is always the
/// raw primal vector (after a dual-infeasible status, the certificate).
/// [`solved`](Self::solved) turns any other status into an error in one call.
///
/// **Dual sign convention.** For a constraint `s(x) ∈ K` the dual is
/// `z ∈ K*` (≥ 0 for an inequality, PSD for an LMI) with `∇f(x) = Σ Ds(x)ᵀ z`
/// for the *minimised* objective f — under [`maximize`](super::Problem::maximize)
/// that is the negated objective, so an equality's dual comes back with the
/// opposite sign of its shadow price. [`sensitivity`](Self::sensitivity)
/// gives the shadow price in the user's sense for either direction.
/// Handles of another problem are [`ConicError::ForeignHandle`]; no method
/// panics on any handle.
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
    pub(crate) names: Vec<String>,
    /// Per constraint: its rows are `rhs − lhs` (a `≤`), not `lhs − rhs`.
    pub(crate) flipped: Vec<bool>,
    pub(crate) lineage: Lineage,
    pub(crate) sense: Sense,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Clarabel's primal residual.
    pub primal_residual: f64,
    /// Clarabel's dual residual.
    pub dual_residual: f64,
    /// Compile + solver setup time, seconds (after a fall-back: both
    /// setups).
    pub setup_time_s: f64,
    /// Interior-point solve time, seconds, without the setup (with a
    /// verified decomposition: and the check; after a fall-back: both
    /// solves and the check).
    pub solve_time_s: f64,
    /// Whether the chordal decomposition was used.
    pub decomposition: DecompositionOutcome,
}

impl Solution {
    /// The solution if its status is solved (accurately or not), else
    /// [`ConicError::NotSolved`] with the status.
    pub fn solved(self) -> Result<Self, ConicError> {
        if self.status.is_solved() {
            Ok(self)
        } else {
            Err(ConicError::NotSolved {
                status: self.status,
                what: "solution",
            })
        }
    }

    /// The direction the problem was optimised in.
    pub fn sense(&self) -> Sense {
        self.sense
    }

    /// The raw primal point x (one entry per scalar variable), whatever the
    /// status.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    fn values_ok(&self) -> Result<(), ConicError> {
        if self.status.is_solved() {
            Ok(())
        } else {
            Err(ConicError::NotSolved {
                status: self.status,
                what: "primal value",
            })
        }
    }

    /// `v`'s column, or why it has none in this solution.
    fn column(&self, v: Var) -> Result<usize, ConicError> {
        if self.lineage.owns_var(v, self.x.len()) {
            Ok(v.index())
        } else if self.lineage.is_newer_var(v, self.x.len()) {
            Err(ConicError::Stale {
                what: format!("variable #{}", v.index()),
            })
        } else {
            Err(ConicError::ForeignHandle {
                what: format!("variable #{}", v.index()),
            })
        }
    }

    fn owned(&self, e: &AffExpr) -> Result<(), ConicError> {
        for v in e.vars() {
            self.column(v)?;
        }
        Ok(())
    }

    /// Value of a scalar variable.
    pub fn value(&self, v: Var) -> Result<f64, ConicError> {
        self.values_ok()?;
        Ok(self.x[self.column(v)?])
    }

    /// Values of several variables.
    pub fn values(&self, vs: &[Var]) -> Result<Vec<f64>, ConicError> {
        vs.iter().map(|&v| self.value(v)).collect()
    }

    /// Value of an affine expression.
    pub fn eval(&self, e: &AffExpr) -> Result<f64, ConicError> {
        self.values_ok()?;
        self.owned(e)?;
        Ok(e.eval(&self.x))
    }

    /// Values of affine expressions.
    pub fn eval_all<'a>(
        &self,
        es: impl IntoIterator<Item = &'a AffExpr>,
    ) -> Result<Vec<f64>, ConicError> {
        es.into_iter().map(|e| self.eval(e)).collect()
    }

    /// Value of a matrix expression.
    pub fn eval_mat(&self, m: &MatExpr) -> Result<DMatrix<f64>, ConicError> {
        self.values_ok()?;
        for e in m.entries() {
            self.owned(e)?;
        }
        Ok(m.eval(&self.x))
    }

    /// Value of a symmetric matrix variable.
    pub fn sym_value(&self, s: &SymVar) -> Result<DMatrix<f64>, ConicError> {
        self.eval_mat(&s.expr())
    }

    /// The raw dual of this solution's constraint `id`.
    fn z(&self, id: ConstraintId) -> Result<&[f64], ConicError> {
        if !(self.status.is_solved() || self.status.is_primal_infeasible()) {
            return Err(ConicError::NotSolved {
                status: self.status,
                what: "dual",
            });
        }
        let what = format!("constraint handle #{}", id.index);
        if self.lineage.owns_constraint(id, self.raw_duals.len()) {
            Ok(&self.raw_duals[id.index])
        } else if id.problem == self.lineage.id {
            Err(ConicError::Stale { what })
        } else {
            Err(ConicError::ForeignHandle { what })
        }
    }

    /// The dual of a constraint (see [`Dual`] and the sign convention above).
    pub fn dual(&self, id: ConstraintId) -> Result<Dual, ConicError> {
        let z = self.z(id)?;
        Ok(match self.kinds[id.index] {
            ConeKind::Psd { n } => Dual::Matrix(svec_to_mat(z, n)),
            _ => Dual::Vector(z.to_vec()),
        })
    }

    /// The dual of a one-row constraint (`=`, `≤`, `≥` between scalars).
    pub fn dual_scalar(&self, id: ConstraintId) -> Result<f64, ConicError> {
        let z = self.z(id)?;
        match (self.kinds[id.index], z) {
            (ConeKind::Zero | ConeKind::Nonnegative, [v]) => Ok(*v),
            (k, z) => Err(self.kind_error(id, "a scalar", k, z.len())),
        }
    }

    /// The duals of a constraint of rows (equalities, inequalities, a
    /// second-order cone), one per row.
    pub fn dual_vector(&self, id: ConstraintId) -> Result<Vec<f64>, ConicError> {
        let z = self.z(id)?;
        match self.kinds[id.index] {
            ConeKind::Psd { .. } => {
                Err(self.kind_error(id, "a vector", self.kinds[id.index], z.len()))
            }
            _ => Ok(z.to_vec()),
        }
    }

    /// The dual matrix Z ⪰ 0 of an LMI.
    pub fn dual_matrix(&self, id: ConstraintId) -> Result<DMatrix<f64>, ConicError> {
        let z = self.z(id)?;
        match self.kinds[id.index] {
            ConeKind::Psd { n } => Ok(svec_to_mat(z, n)),
            k => Err(self.kind_error(id, "a matrix", k, z.len())),
        }
    }

    /// The shadow price of a one-row constraint in the user's sense: the
    /// rate at which the optimal objective (minimised or maximised) changes
    /// when the constraint's right-hand side grows (for `lhs ≥ rhs`,
    /// `lhs ≤ rhs`, `lhs = rhs`).
    pub fn sensitivity(&self, id: ConstraintId) -> Result<f64, ConicError> {
        let z = self.dual_scalar(id)?;
        // s = lhs − rhs (=, ≥) has ∂p*/∂rhs = z for the minimisation; s = rhs − lhs (≤) has −z
        let le = self.flipped[id.index];
        let sign = match self.sense {
            Sense::Minimize => 1.0,
            Sense::Maximize => -1.0,
        };
        Ok(if le { -sign * z } else { sign * z })
    }

    /// The raw dual entries of a constraint in row order (PSD: √2-scaled svec).
    pub fn raw_dual(&self, id: ConstraintId) -> Result<&[f64], ConicError> {
        self.z(id)
    }

    fn kind_error(
        &self,
        id: ConstraintId,
        asked: &'static str,
        k: ConeKind,
        rows: usize,
    ) -> ConicError {
        ConicError::DualKind {
            constraint: self.names[id.index].clone(),
            asked,
            found: match k {
                ConeKind::Psd { n } => format!("a {n}×{n} matrix"),
                _ => format!("{rows} multiplier(s)"),
            },
        }
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
