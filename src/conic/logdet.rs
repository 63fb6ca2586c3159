//! Atoms on the exponential cone: `log`, relative entropy and `log det`.
//!
//! Each is a hypograph (or epigraph) written with [`Problem::add_exp_cone`]
//! and, for `log det`, one PSD block, so a problem that maximises a `log`
//! or `log det` (or minimises a relative entropy) stays one conic program.
//!
//! ```
//! use momentlmi::conic::{Problem, Settings};
//! // max log det X  s.t. diag(X) = (1, 2): X = diag(1, 2), log det = ln 2
//! let mut p = Problem::new();
//! let x = p.symmetric("X", 2);
//! let t = p.scalar("t");
//! p.add_logdet_ge(&x, t)?;
//! p.add_eq(x[(0, 0)], 1.0)?;
//! p.add_eq(x[(1, 1)], 2.0)?;
//! p.maximize(t);
//! let sol = p.solve(&Settings::default())?.solved()?;
//! assert!((sol.value(t)? - 2f64.ln()).abs() < 1e-6);
//! # Ok::<(), momentlmi::conic::ConicError>(())
//! ```

use super::error::ConicError;
use super::expr::{AffExpr, Var};
use super::matexpr::MatExpr;
use super::problem::{ConstraintId, Problem};

/// The constraints behind `t ≤ log det X` ([`Problem::add_logdet_ge`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LogDet {
    /// `[[X, Z], [Zᵀ, Diag(Z)]] ⪰ 0` (2n × 2n), Z lower triangular.
    pub psd: ConstraintId,
    /// `uᵢ ≤ log Zᵢᵢ`, one exponential cone per diagonal entry.
    pub logs: Vec<ConstraintId>,
    /// `t ≤ Σ uᵢ`.
    pub bound: ConstraintId,
    /// The auxiliary variables `uᵢ` (one per diagonal entry).
    pub u: Vec<Var>,
}

impl Problem {
    /// `t ≤ log x` (so `x > 0`), as `(t, 1, x) ∈ K_exp`.
    pub fn add_log_ge(
        &mut self,
        x: impl Into<AffExpr>,
        t: impl Into<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let id = self.add_exp_cone(t, 1.0, x)?;
        self.label(id, "t ≤ log x")
    }

    /// `x·log(x / y) ≤ t` (relative entropy, jointly convex in x and y), as
    /// `(−t, x, y) ∈ K_exp`.
    pub fn add_rel_entropy_le(
        &mut self,
        x: impl Into<AffExpr>,
        y: impl Into<AffExpr>,
        t: impl Into<AffExpr>,
    ) -> Result<ConstraintId, ConicError> {
        let id = self.add_exp_cone(-t.into(), x, y)?;
        self.label(id, "x log(x/y) ≤ t")
    }

    /// `t ≤ log det X` for a symmetric affine `n × n` X (so X ≻ 0): with Z
    /// lower triangular, `[[X, Z], [Zᵀ, Diag(Z)]] ⪰ 0` gives
    /// `det X ≥ Πᵢ Zᵢᵢ`, with equality at the Cholesky-like factor, and
    /// `t ≤ Σᵢ log Zᵢᵢ` (Ben-Tal & Nemirovski, *Lectures on Modern Convex
    /// Optimization*, §4.2). Adds `n(n+1)/2 + n` variables, one `2n × 2n`
    /// PSD block and n exponential cones. Maximising t (or minimising a
    /// multiple of −t) makes it tight.
    pub fn add_logdet_ge(
        &mut self,
        x: impl Into<MatExpr>,
        t: impl Into<AffExpr>,
    ) -> Result<LogDet, ConicError> {
        let x = x.into();
        let n = x.nrows();
        if n == 0 || x.ncols() != n {
            return Err(ConicError::DimensionMismatch {
                what: "log det".into(),
                expected: "a non-empty square matrix".into(),
                found: format!("{}×{}", x.nrows(), x.ncols()),
            });
        }
        let k = self.num_constraints();
        let z: Vec<Vec<Option<Var>>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| (j <= i).then(|| self.scalar(&format!("logdet#{k}.Z[{i},{j}]"))))
                    .collect()
            })
            .collect();
        let zexpr = |i: usize, j: usize| z[i][j].map_or_else(AffExpr::zero, AffExpr::from);
        let block = MatExpr::from_fn(2 * n, 2 * n, |r, c| match (r < n, c < n) {
            (true, true) => x[(r, c)].clone(),
            (true, false) => zexpr(r, c - n),
            (false, true) => zexpr(c, r - n),
            (false, false) if r == c => zexpr(r - n, r - n),
            (false, false) => AffExpr::zero(),
        });
        let psd = self.add_psd(block)?;
        self.label(psd, "log det: [[X, Z], [Zᵀ, Diag Z]] ⪰ 0")?;
        let u = self.vector(&format!("logdet#{k}.u"), n);
        let logs = (0..n)
            .map(|i| self.add_log_ge(zexpr(i, i), u[i]))
            .collect::<Result<Vec<_>, _>>()?;
        let bound = self.add_le(t, u.iter().map(|&v| AffExpr::from(v)).sum::<AffExpr>())?;
        self.label(bound, "log det: t ≤ Σ log Zᵢᵢ")?;
        Ok(LogDet {
            psd,
            logs,
            bound,
            u,
        })
    }

    /// Names a constraint `constraint #k (what)` and returns it.
    fn label(&mut self, id: ConstraintId, what: &str) -> Result<ConstraintId, ConicError> {
        let name = format!("constraint #{} ({what})", id.index);
        self.set_name(id, &name)?;
        Ok(id)
    }
}
