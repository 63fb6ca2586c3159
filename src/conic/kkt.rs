//! A generic optimality check for any solved [`Problem`].
//!
//! With the constraints `sᵢ(x) ∈ Kᵢ` and duals `zᵢ ∈ Kᵢ*` (the orthant,
//! second-order and PSD cones are self-dual, the zero cone's dual is free,
//! the exponential cone is not: its dual K_exp* is checked as such), a point
//! is optimal
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
        ConeKind::Exponential => match v {
            [x, y, z] if dual => exp_dual_violation(*x, *y, *z),
            [x, y, z] => exp_violation(*x, *y, *z),
            _ => f64::INFINITY,
        },
    }
}

/// How far `(x, y, z)` is outside `K_exp = cl{y > 0, y e^{x/y} ≤ z}`: in the
/// interior region the excess `x − y ln(z/y)` of the hypograph form, else the
/// distance to the face `{x ≤ 0, y = 0, z ≥ 0}` (0 exactly on the cone).
fn exp_violation(x: f64, y: f64, z: f64) -> f64 {
    if y > 0.0 && z > 0.0 {
        (x - y * (z / y).ln()).max(0.0)
    } else {
        y.abs().max(x).max(-z).max(0.0)
    }
}

/// How far `(u, v, w)` is outside `K_exp* = cl{u < 0, −u e^{v/u} ≤ e w}`,
/// i.e. `v ≥ u (1 + ln(w / −u))`; on the face `{u = 0, v ≥ 0, w ≥ 0}` the
/// distance to it.
fn exp_dual_violation(u: f64, v: f64, w: f64) -> f64 {
    if u < 0.0 && w > 0.0 {
        (u * (1.0 + (w / -u).ln()) - v).max(0.0)
    } else {
        u.abs().max(-v).max(-w).max(0.0)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponential_cone_membership() {
        let e = std::f64::consts::E;
        // inside, on the boundary, on the closure's face
        for v in [
            [0.0, 1.0, 1.5],
            [1.0, 1.0, e],
            [-3.0, 0.0, 2.0],
            [0.0, 0.0, 0.0],
        ] {
            assert!(exp_violation(v[0], v[1], v[2]) < 1e-15, "{v:?}");
        }
        // outside: above the boundary, negative y, positive x on the face
        assert!((exp_violation(2.0, 1.0, e) - 1.0).abs() < 1e-12);
        assert!(exp_violation(0.0, -1.0, 1.0) >= 1.0);
        assert!(exp_violation(0.5, 0.0, 1.0) >= 0.5);
        // the dual: (−1, 0, 1/e) is on its boundary (−u e^{v/u} = 1 = e w)
        assert!(exp_dual_violation(-1.0, 0.0, 1.0 / e) < 1e-15);
        assert!(exp_dual_violation(0.0, 1.0, 1.0) < 1e-15);
        assert!(exp_dual_violation(-1.0, -0.5, 1.0 / e) > 0.4);
        assert!(exp_dual_violation(1.0, 1.0, 1.0) >= 1.0);
        // the cones are dual: ⟨s, z⟩ ≥ 0 on samples of both
        for (s, z) in [
            ([1.0, 1.0, e], [-1.0, 0.0, 1.0 / e]),
            ([-1.0, 2.0, 2.0], [-0.5, 1.0, 3.0]),
        ] {
            assert!(exp_violation(s[0], s[1], s[2]) < 1e-12);
            assert!(exp_dual_violation(z[0], z[1], z[2]) < 1e-12);
            assert!(s.iter().zip(&z).map(|(a, b)| a * b).sum::<f64>() >= -1e-12);
        }
        assert!(cone_violation(ConeKind::Exponential, &[1.0, 2.0], false).is_infinite());
    }
}
