//! A generic optimality check for any solved [`Problem`].
//!
//! With the constraints `sᵢ(x) ∈ Kᵢ` and duals `zᵢ ∈ Kᵢ*` (all cones used
//! here are self-dual, the zero cone's dual is free), a point is optimal
//! when it is primal feasible, dual feasible, complementary
//! (`Σ ⟨sᵢ(x), zᵢ⟩ = 0`) and stationary (`∇f(x) = Σᵢ Dsᵢᵀ zᵢ`).

use super::problem::{ConeKind, Problem, Sense};
use super::solution::{Solution, svec_to_mat};

/// Residuals of the optimality conditions, all absolute and ≥ 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KktReport {
    /// Largest cone violation of `s(x)`.
    pub primal_infeasibility: f64,
    /// Largest cone violation of z (dual cone membership).
    pub dual_infeasibility: f64,
    /// `|Σ ⟨sᵢ(x), zᵢ⟩|`.
    pub complementarity: f64,
    /// `‖∇f(x) − Σ Dsᵢᵀ zᵢ‖∞` (for the minimised objective).
    pub stationarity: f64,
}

impl KktReport {
    /// The largest of the four residuals.
    pub fn max(&self) -> f64 {
        self.primal_infeasibility
            .max(self.dual_infeasibility)
            .max(self.complementarity)
            .max(self.stationarity)
    }
}

/// Distance of `v` outside the cone (0 inside).
pub(crate) fn cone_violation(kind: ConeKind, v: &[f64], dual: bool) -> f64 {
    match kind {
        ConeKind::Zero => {
            if dual {
                0.0
            } else {
                v.iter().fold(0.0, |a, x| a.max(x.abs()))
            }
        }
        ConeKind::Nonnegative => v.iter().fold(0.0, |a, &x| a.max(-x)),
        ConeKind::SecondOrder => {
            let t = v.first().copied().unwrap_or(0.0);
            let r = v.iter().skip(1).map(|x| x * x).sum::<f64>().sqrt();
            (r - t).max(0.0)
        }
        ConeKind::Psd { n } => {
            if n == 0 {
                return 0.0;
            }
            let m = svec_to_mat(v, n);
            let lmin = m.symmetric_eigenvalues().min();
            (-lmin).max(0.0)
        }
    }
}

/// Checks the optimality conditions of `sol` for `problem`.
pub fn check_optimality(problem: &Problem, sol: &Solution) -> KktReport {
    let x = sol.x();
    let sign = if problem.sense == Sense::Maximize {
        -1.0
    } else {
        1.0
    };
    // ∇f for the minimised objective
    let mut grad = vec![0.0; problem.nvars];
    for &(v, a) in &problem.linear.terms {
        let i = v.index();
        grad[i] += sign * a;
    }
    for (w, e) in &problem.squares {
        let r = e.eval(x);
        for &(v, a) in &e.terms {
            let i = v.index();
            grad[i] += 2.0 * w * r * a;
        }
    }
    let (mut pinf, mut dinf, mut comp) = (0.0f64, 0.0f64, 0.0f64);
    for (k, c) in problem.constraints.iter().enumerate() {
        let s: Vec<f64> = c.rows.iter().map(|e| e.eval(x)).collect();
        let z = &sol.raw_duals[k];
        pinf = pinf.max(cone_violation(c.kind, &s, false));
        dinf = dinf.max(cone_violation(c.kind, z, true));
        comp += s.iter().zip(z).map(|(a, b)| a * b).sum::<f64>();
        for (e, &zr) in c.rows.iter().zip(z) {
            for &(v, a) in &e.terms {
                let i = v.index();
                grad[i] -= zr * a;
            }
        }
    }
    KktReport {
        primal_infeasibility: pinf,
        dual_infeasibility: dinf,
        complementarity: comp.abs(),
        stationarity: grad.iter().fold(0.0, |a, g| a.max(g.abs())),
    }
}
