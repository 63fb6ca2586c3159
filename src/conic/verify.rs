//! The check of a decomposed solve against the original problem.
//!
//! Clarabel solves a decomposed problem and maps its (x, z) back; this file
//! checks that pair against the undecomposed data `(P, q, A, b, K)` of
//! [`Compiled`]: s = b − Ax in K, z in K* (the PSD-completed dual), the
//! stationarity `Px + q + Aᵀz = 0` and the duality gap, each relative to the
//! data's scale. An infeasibility certificate is checked the same way.

use super::compile::Compiled;
use super::kkt::cone_violation;
use super::problem::ConeKind;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{SolverStatus, SupportedConeT};

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, x| a.max(x.abs()))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `y += M v` (`transpose`: `y += Mᵀ v`). Clarabel 0.11's own `gemv` and
/// `symv` on `CscMatrix` are crate-private, hence these two.
fn csc_mul(m: &CscMatrix<f64>, v: &[f64], y: &mut [f64], transpose: bool) {
    for c in 0..m.n {
        for k in m.colptr[c]..m.colptr[c + 1] {
            let r = m.rowval[k];
            if transpose {
                y[c] += m.nzval[k] * v[r];
            } else {
                y[r] += m.nzval[k] * v[c];
            }
        }
    }
}

/// `P x` for the stored upper triangle of a symmetric P.
fn sym_mul(p: &CscMatrix<f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for c in 0..p.n {
        for k in p.colptr[c]..p.colptr[c + 1] {
            let r = p.rowval[k];
            y[r] += p.nzval[k] * x[c];
            if r != c {
                y[c] += p.nzval[k] * x[r];
            }
        }
    }
    y
}

/// The layer's kind of a Clarabel cone and its rows; `None` for a cone this
/// layer never compiles (its rows cannot be checked).
fn kind(c: &SupportedConeT<f64>) -> Option<(ConeKind, usize)> {
    Some(match *c {
        SupportedConeT::ZeroConeT(k) => (ConeKind::Zero, k),
        SupportedConeT::NonnegativeConeT(k) => (ConeKind::Nonnegative, k),
        SupportedConeT::SecondOrderConeT(k) => (ConeKind::SecondOrder, k),
        SupportedConeT::PSDTriangleConeT(n) => (ConeKind::Psd { n }, n * (n + 1) / 2),
        SupportedConeT::ExponentialConeT() => (ConeKind::Exponential, 3),
        _ => return None,
    })
}

/// Largest cone violation of `v` (row-stacked over `cones`), or of the dual;
/// infinite when a cone cannot be checked.
fn violation(cones: &[SupportedConeT<f64>], v: &[f64], dual: bool) -> f64 {
    let mut start = 0;
    let mut worst = 0.0f64;
    for c in cones {
        let Some((k, len)) = kind(c) else {
            return f64::INFINITY;
        };
        let end = (start + len).min(v.len());
        worst = worst.max(cone_violation(k, &v[start..end], dual));
        start = end;
    }
    worst
}

fn fail(what: &str, value: f64, tol: f64) -> Result<(), String> {
    if value.is_finite() && value <= tol {
        Ok(())
    } else {
        Err(format!("{what} {value:.1e} > {tol:.0e}"))
    }
}

impl Compiled {
    /// Checks a decomposed solve's full `x` and `z` (Clarabel's dimensions)
    /// for its status; `Err` names the residual that failed.
    pub(crate) fn verify(&self, status: SolverStatus, x: &[f64], z: &[f64]) -> Result<(), String> {
        let tol = self.settings.decomposition_check_tol;
        let mut atz = vec![0.0; self.q.len()];
        csc_mul(&self.a, z, &mut atz, true);
        let mut ax = vec![0.0; self.b.len()];
        csc_mul(&self.a, x, &mut ax, false);
        let zscale = 1.0 + inf_norm(z);
        match status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                let s: Vec<f64> = self.b.iter().zip(&ax).map(|(b, a)| b - a).collect();
                let px = sym_mul(&self.p, x);
                let (xpx, qx, bz) = (dot(&px, x), dot(&self.q, x), dot(&self.b, z));
                let stat: Vec<f64> = (0..x.len()).map(|i| px[i] + self.q[i] + atz[i]).collect();
                let scale_d = 1.0 + inf_norm(&self.q).max(inf_norm(&px)).max(inf_norm(&atz));
                let (pobj, dobj) = (0.5 * xpx + qx, -0.5 * xpx - bz);
                fail(
                    "primal cone violation",
                    violation(&self.cones, &s, false) / (1.0 + inf_norm(&self.b)),
                    tol,
                )?;
                fail(
                    "dual cone violation",
                    violation(&self.cones, z, true) / zscale,
                    tol,
                )?;
                fail("stationarity", inf_norm(&stat) / scale_d, tol)?;
                fail(
                    "duality gap",
                    (pobj - dobj).abs() / (1.0 + pobj.abs().max(dobj.abs())),
                    tol,
                )
            }
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                // a certificate: Aᵀz = 0, bᵀz < 0, z ∈ K*
                let bz = dot(&self.b, z);
                if !(bz < 0.0) {
                    return Err(format!("infeasibility certificate has bᵀz = {bz:.1e} ≥ 0"));
                }
                fail(
                    "certificate dual cone violation",
                    violation(&self.cones, z, true) / zscale,
                    tol,
                )?;
                fail("certificate ‖Aᵀz‖/|bᵀz|", inf_norm(&atz) / bz.abs(), tol)
            }
            SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => {
                // a certificate: Px = 0, −Ax ∈ K, qᵀx < 0
                let qx = dot(&self.q, x);
                if !(qx < 0.0) {
                    return Err(format!("unboundedness certificate has qᵀx = {qx:.1e} ≥ 0"));
                }
                let s: Vec<f64> = ax.iter().map(|a| -a).collect();
                fail(
                    "certificate cone violation / |qᵀx|",
                    violation(&self.cones, &s, false) / qx.abs(),
                    tol,
                )?;
                fail(
                    "certificate ‖Px‖/|qᵀx|",
                    inf_norm(&sym_mul(&self.p, x)) / qx.abs(),
                    tol,
                )
            }
            other => Err(format!("the decomposed solve ended {other:?}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{MatExpr, Problem, Settings};
    use clarabel::solver::SolverStatus;
    use nalgebra::DMatrix;

    /// λmax(A) = min t s.t. tI − A ⪰ 0; optimum t = 3 with dual the
    /// projector on A's top eigenvector (1, 1)/√2.
    fn lambda_max() -> super::Compiled {
        let a = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let mut p = Problem::new();
        let t = p.scalar("t");
        p.add_psd(MatExpr::scaled_identity(2, t) - MatExpr::constant(&a))
            .expect("psd");
        p.minimize(t);
        p.compile(&Settings::default()).expect("compiles")
    }

    #[test]
    fn the_check_accepts_the_optimum_and_names_what_is_wrong_otherwise() {
        let c = lambda_max();
        // svec of Z = ½[[1, 1], [1, 1]]: (z00, √2 z01, z11)
        let s2 = std::f64::consts::SQRT_2;
        let z = [0.5, s2 * 0.5, 0.5];
        assert_eq!(c.verify(SolverStatus::Solved, &[3.0], &z), Ok(()));
        // a better-looking t is not feasible
        let e = c.verify(SolverStatus::Solved, &[2.5], &z).unwrap_err();
        assert!(e.contains("primal cone"), "{e}");
        // a dual that is not PSD (the completion Clarabel 0.11 returns on
        // control1 fails this way)
        let e = c
            .verify(SolverStatus::Solved, &[3.0], &[0.5, s2 * 0.8, 0.5])
            .unwrap_err();
        assert!(e.contains("dual cone"), "{e}");
        // a PSD dual of the wrong trace breaks stationarity
        let e = c
            .verify(SolverStatus::Solved, &[3.0], &[1.0, s2, 1.0])
            .unwrap_err();
        assert!(e.contains("stationarity"), "{e}");
        // a feasible t above the optimum with a valid dual leaves a gap
        let e = c.verify(SolverStatus::Solved, &[3.5], &z).unwrap_err();
        assert!(e.contains("duality gap"), "{e}");
        let e = c
            .verify(SolverStatus::MaxIterations, &[3.0], &z)
            .unwrap_err();
        assert!(e.contains("MaxIterations"), "{e}");
    }
}
