//! A friction law's held-out errors from the choice's sums
//! ([`super::friction_choice`]): per fold, the least-squares fit of the
//! links' parameters and the law's coefficients on the other folds, with
//! the prior's term at each weight, scored on the fold by its quadratic
//! form.
//!
//! The law's unknowns are eliminated once per fold (a Schur complement),
//! so a weight only changes the links' `pb × pb` system; whitened by the
//! prior's metric (the identity for a Euclidean prior), where the weight
//! shifts that system's diagonal, one tridiagonal reduction serves every
//! weight.

use super::choice_pass::Sums;
use super::error::IdentifyError;
use nalgebra::{DMatrix, DVector, SMatrix};

/// The prior's term of the objective as the Gram solves see it:
/// `w Σ_b (π_b − π̂_b)ᵀ M_b (π_b − π̂_b) + w_m Σ_b (m_b − m̂_b)²`, `M_b = I`
/// (Euclidean) or the entropic divergence's second-order term at the
/// prior (entropic; `friction_choice`'s `entropic_metric`).
pub struct PriorTerm<'a> {
    /// 10 per body, or empty (no prior).
    pub values: &'a [f64],
    /// `M_b` per body.
    pub metric: Vec<SMatrix<f64, 10, 10>>,
    /// The masses' extra weight.
    pub mass_weight: f64,
}

/// Per weight, fold and joint, the held-out sum of squares of `law`
/// (indices of the pass's bases) fitted on the other folds' `sums` (joint
/// j's links' columns `cols[j]`, `pb` links' parameters in all).
pub(crate) fn law_sse(
    law: &[usize],
    sums: &[Vec<Sums>],
    cols: &[Vec<usize>],
    (pb, prior, weights): (usize, &PriorTerm, &[f64]),
) -> Result<Vec<Vec<Vec<f64>>>, IdentifyError> {
    let (n, k) = (cols.len(), sums.len());
    let p = pb + law.len() * n;
    let map = unknowns(law, cols, pb);
    let rows: Vec<usize> = sums.iter().map(|s| s[0].rows).collect();
    let mut sse = vec![vec![vec![0.0; n]; k]; weights.len()];
    let failed = || IdentifyError::Factorisation {
        what: "Cholesky factorisation of a friction law's Gram matrix",
    };
    let folds = gathered(sums, &map);
    for (f, normal) in normal_equations(&folds, &rows, &map, p)
        .into_iter()
        .enumerate()
    {
        let normal = Eliminated::new(normal, pb).ok_or_else(failed)?;
        let thetas = normal.solve_all(prior, weights).ok_or_else(failed)?;
        for (w, per_joint) in heldout_sse(&thetas, &folds[f], &map)
            .into_iter()
            .enumerate()
        {
            sse[w][f] = per_joint;
        }
    }
    Ok(sse)
}

/// Joint j's compact index → global unknown, for `law`'s columns (the
/// links' `pb` parameters first, then the law's, term-major).
fn unknowns(law: &[usize], cols: &[Vec<usize>], pb: usize) -> Vec<Vec<(usize, usize)>> {
    let n = cols.len();
    (0..n)
        .map(|j| {
            let l = cols[j].len();
            let mut m: Vec<(usize, usize)> =
                cols[j].iter().enumerate().map(|(a, &c)| (a, c)).collect();
            m.extend(
                law.iter()
                    .enumerate()
                    .map(|(s, &t)| (l + t, pb + s * n + j)),
            );
            m
        })
        .collect()
}

/// One fold's and joint's sums for a law's unknowns (`map[j]`'s order):
/// `(G, b, c)`.
type Gathered = (DMatrix<f64>, DVector<f64>, f64);

/// Each fold's and joint's sums gathered for the unknowns of `map`.
fn gathered(sums: &[Vec<Sums>], map: &[Vec<(usize, usize)>]) -> Vec<Vec<Gathered>> {
    (sums.iter())
        .map(|fold| {
            (fold.iter().zip(map))
                .map(|(s, m)| {
                    let g = DMatrix::from_fn(m.len(), m.len(), |r, c| s.g[(m[r].0, m[c].0)]);
                    (g, DVector::from_fn(m.len(), |r, _| s.b[m[r].0]), s.c)
                })
                .collect()
        })
        .collect()
}

/// `Σ_j` of one fold's gathered sums `fold`, in the `p` unknowns.
fn scattered_fold(
    fold: &[Gathered],
    map: &[Vec<(usize, usize)>],
    p: usize,
) -> (DMatrix<f64>, DVector<f64>) {
    let (mut g, mut b) = (DMatrix::<f64>::zeros(p, p), DVector::<f64>::zeros(p));
    for ((gj, bj, _), m) in fold.iter().zip(map) {
        for (r, &(_, gr)) in m.iter().enumerate() {
            b[gr] += bj[r];
            (m.iter().enumerate()).for_each(|(c, &(_, gc))| g[(gr, gc)] += gj[(r, c)]);
        }
    }
    (g, b)
}

/// The normal equations `(G, b)` of every fold but each (each scaled by
/// the samples, as the objective is), for the unknowns of `map`.
fn normal_equations(
    folds: &[Vec<Gathered>],
    rows: &[usize],
    map: &[Vec<(usize, usize)>],
    p: usize,
) -> Vec<(DMatrix<f64>, DVector<f64>)> {
    let own: Vec<_> = folds.iter().map(|f| scattered_fold(f, map, p)).collect();
    let g: DMatrix<f64> = own.iter().fold(DMatrix::zeros(p, p), |a, o| a + &o.0);
    let b: DVector<f64> = own.iter().fold(DVector::zeros(p), |a, o| a + &o.1);
    let total: usize = rows.iter().sum();
    (own.iter().zip(rows))
        .map(|(o, &r)| {
            let scale = 1.0 / (total - r).max(1) as f64;
            ((&g - &o.0) * scale, (&b - &o.1) * scale)
        })
        .collect()
}

/// `(G, b)` with the prior's term at `weight` added (the first unknowns,
/// 10 per body of the prior, are the links').
fn with_prior(
    (mut g, mut b): (DMatrix<f64>, DVector<f64>),
    prior: &PriorTerm,
    weight: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    for (body, m) in prior.metric.iter().enumerate() {
        let o = 10 * body;
        let mut wm = m * weight;
        wm[(0, 0)] += prior.mass_weight;
        let pi = nalgebra::SVector::<f64, 10>::from_column_slice(&prior.values[o..o + 10]);
        let rhs = wm * pi;
        for k in 0..10 {
            b[o + k] += rhs[k];
            (0..10).for_each(|l| g[(o + k, o + l)] += wm[(k, l)]);
        }
    }
    (g, b)
}

/// A fold's normal equations `[[A, Bᵀ], [B, C]] [θ_a; θ_f] = [b_a; b_f]`
/// (θ_a the links' `pb` unknowns, θ_f the law's) with a ridge of 1e-10 of
/// G's mean diagonal, the law's unknowns eliminated once: only the links'
/// `S = A − Bᵀ C⁻¹ B` gets the prior, so each weight factors a pb × pb
/// matrix, and `θ_f = C⁻¹ b_f − C⁻¹ B θ_a`.
struct Eliminated {
    s: DMatrix<f64>,
    r: DVector<f64>,
    /// `C⁻¹ B`.
    x: DMatrix<f64>,
    /// `C⁻¹ b_f`.
    y: DVector<f64>,
}

impl Eliminated {
    fn new((g, b): (DMatrix<f64>, DVector<f64>), pb: usize) -> Option<Self> {
        let (p, f) = (g.nrows(), g.nrows() - pb);
        let ridge = 1e-10 * (g.trace() / p as f64).max(f64::MIN_POSITIVE);
        let mut c = g.view((pb, pb), (f, f)).clone_owned();
        (0..f).for_each(|i| c[(i, i)] += ridge);
        let c = c.cholesky()?;
        let bm = g.view((pb, 0), (f, pb));
        let (x, y) = (c.solve(&bm), c.solve(&b.rows(pb, f)));
        let mut s = g.view((0, 0), (pb, pb)) - bm.transpose() * &x;
        (0..pb).for_each(|i| s[(i, i)] += ridge);
        let r = b.rows(0, pb) - bm.transpose() * &y;
        Some(Self { s, r, x, y })
    }

    /// The solution with the prior at each of `weights`: with a Euclidean
    /// prior and several weights, from one tridiagonal reduction of the
    /// links' system (the weight only shifts its diagonal:
    /// [`Self::shifted`]), else a Cholesky factorisation per weight.
    fn solve_all(&self, prior: &PriorTerm, weights: &[f64]) -> Option<Vec<DVector<f64>>> {
        if weights.len() > 1 && prior.values.len() == self.s.nrows() {
            return self.shifted(prior, weights);
        }
        (weights.iter())
            .map(|&w| {
                let (h, rhs) = with_prior((self.s.clone(), self.r.clone()), prior, w);
                Some(self.with_friction(h.cholesky()?.solve(&rhs)))
            })
            .collect()
    }

    /// `(S₀ + w M) θ_a = r₀ + w M π̂` for each weight (`M` the prior's
    /// block-diagonal metric, `S₀, r₀` with the masses' weight in): with
    /// `M = L Lᵀ` and `θ_a = L⁻ᵀ u` it is `(L⁻¹ S₀ L⁻ᵀ + w I) u = L⁻¹ r₀ + w
    /// Lᵀ π̂`; that matrix is `Q T Qᵀ` (T tridiagonal) once, then each weight
    /// an LDLᵀ solve of `T + w I` and products with Q and L⁻ᵀ.
    fn shifted(&self, prior: &PriorTerm, weights: &[f64]) -> Option<Vec<DVector<f64>>> {
        let (s0, r0) = with_prior((self.s.clone(), self.r.clone()), prior, 0.0);
        let n = s0.nrows();
        let mut l_inv = DMatrix::<f64>::zeros(n, n);
        let mut lt_pi = DVector::<f64>::zeros(n);
        for (b, m) in prior.metric.iter().enumerate() {
            let l = m.cholesky()?.l();
            let o = 10 * b;
            l_inv
                .view_mut((o, o), (10, 10))
                .copy_from(&l.try_inverse()?);
            let pi = nalgebra::SVector::<f64, 10>::from_column_slice(&prior.values[o..o + 10]);
            lt_pi.rows_mut(o, 10).copy_from(&(l.transpose() * pi));
        }
        let whitened = &l_inv * s0 * l_inv.transpose();
        let (q, d, e) = nalgebra::linalg::SymmetricTridiagonal::new(whitened).unpack();
        let (qr, qp) = (q.tr_mul(&(&l_inv * r0)), q.tr_mul(&lt_pi));
        let back = l_inv.transpose() * &q;
        (weights.iter())
            .map(|&w| {
                let z = tridiagonal_solve(&d, &e, w, &(&qr + &qp * w))?;
                Some(self.with_friction(&back * z))
            })
            .collect()
    }

    /// `[θ_a; θ_f]`.
    fn with_friction(&self, a: DVector<f64>) -> DVector<f64> {
        let f = &self.y - &self.x * &a;
        DVector::from_iterator(a.len() + f.len(), a.iter().chain(f.iter()).copied())
    }
}

/// `(T + w I)⁻¹ b`, T symmetric tridiagonal (diagonal `d`, off-diagonal
/// `e`), by its LDLᵀ factorisation; `None` when a pivot is not positive
/// (not positive definite).
fn tridiagonal_solve(
    d: &DVector<f64>,
    e: &DVector<f64>,
    w: f64,
    b: &DVector<f64>,
) -> Option<DVector<f64>> {
    let n = d.len();
    let (mut piv, mut l, mut y) = (vec![0.0; n], vec![0.0; n], b.clone());
    for i in 0..n {
        if i > 0 {
            l[i] = e[i - 1] / piv[i - 1];
            y[i] -= l[i] * y[i - 1];
        }
        piv[i] = d[i] + w - if i > 0 { l[i] * e[i - 1] } else { 0.0 };
        if piv[i].is_nan() || piv[i] <= 0.0 {
            return None;
        }
    }
    for i in (0..n).rev() {
        y[i] /= piv[i];
        if i + 1 < n {
            y[i] -= l[i + 1] * y[i + 1];
        }
    }
    Some(y)
}

/// Held-out sums of squares of each of `thetas` (per weight) per joint on
/// one fold's gathered sums: `θᵀGθ − 2 θᵀb + c`, the weights' θ as the
/// columns of one matrix.
fn heldout_sse(
    thetas: &[DVector<f64>],
    fold: &[Gathered],
    map: &[Vec<(usize, usize)>],
) -> Vec<Vec<f64>> {
    let per_joint: Vec<Vec<f64>> = (fold.iter().zip(map))
        .map(|((g, b, c), m)| {
            let th = DMatrix::from_fn(m.len(), thetas.len(), |r, w| thetas[w][m[r].1]);
            let gth = g * &th;
            (0..thetas.len())
                .map(|w| {
                    let (t, gt) = (th.column(w), gth.column(w));
                    (t.dot(&gt) - 2.0 * t.dot(b) + c).max(0.0)
                })
                .collect()
        })
        .collect();
    (0..thetas.len())
        .map(|w| per_joint.iter().map(|j| j[w]).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{Eliminated, PriorTerm};
    use nalgebra::{DMatrix, DVector, SMatrix};

    /// A Euclidean prior's weights from one tridiagonal reduction give the
    /// Cholesky solve of the whole system at each weight, for the identity
    /// metric (Euclidean) and for a pullback-like one (not the identity:
    /// whitened by its Cholesky factor first).
    #[test]
    fn every_weight_from_one_reduction_equals_a_solve_per_weight() {
        let (pb, f) = (20, 6);
        let p = pb + f;
        // a Gram matrix of pseudo-random rows (an LCG's)
        let mut x: u64 = 12345;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let a = DMatrix::from_fn(2 * p, p, |_, _| next());
        let mut g = a.transpose() * &a;
        (0..pb).for_each(|i| g[(i, i)] *= 1.0 + 1e-3 * i as f64);
        let b = DVector::from_fn(p, |i, _| (i as f64 * 0.3).cos());
        let values: Vec<f64> = (0..pb).map(|i| 0.1 * i as f64 - 0.5).collect();
        let weights = [1e-6, 1e-3, 0.1, 1.0];
        let skew = SMatrix::<f64, 10, 10>::from_fn(|i, j| if i == j { 2.0 } else { 0.1 });
        for metric in [SMatrix::identity(), skew] {
            let prior = PriorTerm {
                values: &values,
                metric: vec![metric; pb / 10],
                mass_weight: 0.3,
            };
            let got = Eliminated::new((g.clone(), b.clone()), pb)
                .unwrap()
                .solve_all(&prior, &weights)
                .unwrap();
            for (w, theta) in weights.iter().zip(&got) {
                let ridge = 1e-10 * g.trace() / p as f64;
                let mut h = g.clone();
                (0..p).for_each(|i| h[(i, i)] += ridge);
                let (h, rhs) = super::with_prior((h, b.clone()), &prior, *w);
                let want = h.cholesky().unwrap().solve(&rhs);
                let scale = want.amax();
                assert!((theta - &want).amax() <= 1e-8 * scale, "weight {w}");
            }
        }
    }
}
