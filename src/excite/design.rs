//! Convex experiment design: how much of the time to spend on each of a
//! pool of candidate motions. With `Fᵢ` the information matrix of motion i
//! (per unit time), the design `w` (Σ wᵢ = 1, w ≥ 0) has information
//! `F(w) = Σ wᵢ Fᵢ`; D-optimal maximises `log det F(w)`, E-optimal its
//! smallest eigenvalue (Boyd & Vandenberghe, *Convex Optimization*, §7.5),
//! each one conic program through [`crate::conic`].

use super::error::ExciteError;
use crate::conic::{AffExpr, MatExpr, Problem, Settings};
use faer::Mat;
use serde::Serialize;

/// What a design maximises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// `log det F` (D-optimal).
    D,
    /// `λ_min(F)` (E-optimal).
    E,
    /// `−log cond F` (the condition number of the information matrix).
    Cond,
}

impl Criterion {
    /// `d`, `e` or `cond`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "d" => Some(Self::D),
            "e" => Some(Self::E),
            "cond" => Some(Self::Cond),
            _ => None,
        }
    }
}

/// The optimal design over a pool.
#[derive(Clone, Debug, Serialize)]
pub struct PoolDesign {
    /// The weight of each candidate (Σ = 1).
    pub weights: Vec<f64>,
    /// The criterion at the optimum: `log det F(w)` (D) or `λ_min F(w)`
    /// (E and cond, which a convex design bounds through λ_min).
    pub optimum: f64,
}

/// The D- (log det) or E-optimal (λ_min) weights over `pool` (each a
/// symmetric k × k information matrix, k ≥ 1, the same for all).
pub fn optimal_weights(pool: &[Mat<f64>], criterion: Criterion) -> Result<PoolDesign, ExciteError> {
    let k = pool.first().map_or(0, |f| f.nrows());
    if pool.is_empty() || k == 0 || pool.iter().any(|f| f.nrows() != k || f.ncols() != k) {
        return Err(ExciteError::Pool {
            problem: "needs at least one candidate, each a square information matrix of one size",
        });
    }
    check_size(k, pool.len(), criterion)?;
    let mut p = Problem::new();
    let w = p.vector("w", pool.len());
    p.add_nonneg(w.iter().map(|&v| AffExpr::term(v, 1.0)).collect::<Vec<_>>())?;
    p.add_eq(
        w.iter().map(|&v| AffExpr::term(v, 1.0)).sum::<AffExpr>(),
        1.0,
    )?;
    let f = MatExpr::from_fn(k, k, |i, j| {
        (pool.iter().zip(&w))
            .map(|(fi, &v)| AffExpr::term(v, 0.5 * (fi[(i, j)] + fi[(j, i)])))
            .sum()
    });
    let t = p.scalar("t");
    match criterion {
        Criterion::D => {
            p.add_logdet_ge(f, t)?;
        }
        Criterion::E | Criterion::Cond => {
            let shifted = MatExpr::from_fn(k, k, |i, j| {
                let mut e = f[(i, j)].clone();
                if i == j {
                    e += AffExpr::term(t, -1.0);
                }
                e
            });
            p.add_psd(shifted)?;
        }
    }
    p.maximize(t);
    let settings = Settings::default()
        .tol_gap_abs(1e-9)
        .tol_gap_rel(1e-9)
        .tol_feas(1e-9);
    let sol = p.solve(&settings)?;
    if !sol.status.is_solved() {
        return Err(ExciteError::Solver(sol.status));
    }
    Ok(PoolDesign {
        weights: sol.values(&w)?.iter().map(|v| v.max(0.0)).collect(),
        optimum: sol.value(t)?,
    })
}

/// The most memory the design's conic problem may plan for: Clarabel keeps
/// a PSD block of svec size s as a dense s × s part of its KKT matrix, its
/// factor and their workspaces: ≈ 64 s² bytes (measured: 6.4 GB for the
/// 2 × 70 block of a 9-joint Panda, s = 9,870).
pub const MAX_DESIGN_BYTES: f64 = 4e9;

/// Refuses a design over `candidates` motions of `k` base parameters that
/// would pass [`MAX_DESIGN_BYTES`]: its PSD block (log det needs a 2k × 2k
/// one, λ_min a k × k one), and per candidate its k × k information matrix
/// and its svec(k) coefficients in the constraint matrix (value and index).
/// Checked before the candidates are made.
pub(super) fn check_size(
    k: usize,
    candidates: usize,
    criterion: Criterion,
) -> Result<(), ExciteError> {
    let n = if criterion == Criterion::D { 2 * k } else { k } as f64;
    let svec = n * (n + 1.0) / 2.0;
    let kf = k as f64;
    let per_candidate = 8.0 * kf * kf + 16.0 * kf * (kf + 1.0) / 2.0;
    let bytes = 64.0 * svec * svec + candidates as f64 * per_candidate;
    if bytes > MAX_DESIGN_BYTES {
        return Err(ExciteError::TooLarge {
            parameters: k,
            candidates,
            gib: bytes / f64::from(1u32 << 30),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The information of one observation of y = Σ cⱼ xʲ at x.
    fn info(x: f64, degree: usize) -> Mat<f64> {
        let f: Vec<f64> = (0..=degree).map(|j| x.powi(j as i32)).collect();
        Mat::from_fn(degree + 1, degree + 1, |i, j| f[i] * f[j])
    }

    #[test]
    fn d_optimal_designs_of_polynomials_are_the_known_ones() {
        let xs = [-1.0, -0.5, 0.0, 0.5, 1.0];
        // a line: half at each end
        let line: Vec<_> = xs.iter().map(|&x| info(x, 1)).collect();
        let d = optimal_weights(&line, Criterion::D).unwrap();
        let want = [0.5, 0.0, 0.0, 0.0, 0.5];
        for (w, v) in d.weights.iter().zip(want) {
            assert!((w - v).abs() < 1e-5, "{:?}", d.weights);
        }
        // log det [[1, 0], [0, 1]] = 0
        assert!(d.optimum.abs() < 1e-6, "{}", d.optimum);
        // a quadratic: a third at −1, 0, 1 (det = 4/27)
        let quad: Vec<_> = xs.iter().map(|&x| info(x, 2)).collect();
        let d = optimal_weights(&quad, Criterion::D).unwrap();
        let want = [1.0 / 3.0, 0.0, 1.0 / 3.0, 0.0, 1.0 / 3.0];
        for (w, v) in d.weights.iter().zip(want) {
            assert!((w - v).abs() < 1e-5, "{:?}", d.weights);
        }
        assert!((d.optimum - (4.0f64 / 27.0).ln()).abs() < 1e-6);
    }

    #[test]
    fn e_optimal_weights_balance_two_directions() {
        // diag(1, 0) and diag(0, 4): λ_min of w₁ diag(1,0) + w₂ diag(0,4) is
        // largest at w = (0.8, 0.2), where it is 0.8
        let a = Mat::from_fn(2, 2, |i, j| if i == j && i == 0 { 1.0 } else { 0.0 });
        let b = Mat::from_fn(2, 2, |i, j| if i == j && i == 1 { 4.0 } else { 0.0 });
        let d = optimal_weights(&[a, b], Criterion::E).unwrap();
        assert!(
            (d.weights[0] - 0.8).abs() < 1e-5 && (d.optimum - 0.8).abs() < 1e-5,
            "{d:?}"
        );
        assert!(optimal_weights(&[], Criterion::D).is_err());
        // 70 base parameters: log det would need a 140 × 140 block (≈ 6 GB)
        let big = Mat::<f64>::identity(70, 70);
        let e = optimal_weights(std::slice::from_ref(&big), Criterion::D).unwrap_err();
        assert!(e.to_string().contains("70 base parameters"), "{e}");
    }
}
