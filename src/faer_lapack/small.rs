//! Decompositions of small matrices (order at most [`SMALL`]) by Jacobi
//! rotations, which carry no set-up cost and keep the small eigenvalues and
//! singular values of a graded matrix to high relative accuracy (Demmel &
//! Veselić, "Jacobi's method is more accurate than QR", SIAM J. Matrix
//! Anal. Appl. 1992). Clarabel factors one 4 × 4 (or so) matrix per PSD
//! cone several times an iteration (eigenvalues for the step length, an SVD
//! for the Nesterov–Todd scaling), where faer's blocked, SIMD-dispatched
//! routines spend most of their time preparing; near the optimum those
//! matrices are nearly singular, and their small values must stay right.
//! Results follow LAPACK's conventions: eigenvalues ascending, singular
//! values descending, orthonormal vectors (column-major `n × n`).

/// The largest order decomposed here (above it, faer's routines win).
pub(super) const SMALL: usize = 8;

/// Sweeps of rotations before giving up (a finite input converges in a
/// handful: Jacobi's convergence is quadratic).
const MAX_SWEEPS: usize = 60;

/// A column-major `n × n` matrix.
pub(super) type Square = Vec<f64>;

/// A pair is left alone when its coupling is below this fraction of the
/// geometric mean of its diagonal (or its columns' norms): √n ulps, as
/// LAPACK's one-sided Jacobi (`dgesvj`); at one ulp, rounding keeps pairs
/// of nearly null columns rotating.
fn tolerance(n: usize) -> f64 {
    (n as f64).sqrt() * f64::EPSILON
}

fn identity(n: usize) -> Square {
    let mut v = vec![0.0; n * n];
    (0..n).for_each(|i| v[i * n + i] = 1.0);
    v
}

/// The rotation `(c, s)` that zeroes the off-diagonal entry `apq` of the
/// symmetric 2 × 2 `[[app, apq], [apq, aqq]]` (the smaller angle); `None`
/// when that angle is below what `f64` can represent (`apq` negligible
/// against the difference of the diagonal: the pair is diagonal already).
fn rotation(app: f64, aqq: f64, apq: f64) -> Option<(f64, f64)> {
    let zeta = (aqq - app) / (2.0 * apq);
    let t = zeta.signum() / (zeta.abs() + zeta.hypot(1.0));
    let c = 1.0 / t.hypot(1.0);
    (t != 0.0 && t.is_finite()).then_some((c, c * t))
}

/// Columns `p`, `q` of the `n`-row column-major `m` turned by `(c, s)`:
/// `(x_p, x_q) ← (c x_p − s x_q, s x_p + c x_q)`.
fn rotate_columns(m: &mut [f64], n: usize, (p, q): (usize, usize), (c, s): (f64, f64)) {
    for r in 0..n {
        let (x, y) = (m[p * n + r], m[q * n + r]);
        m[p * n + r] = c * x - s * y;
        m[q * n + r] = s * x + c * y;
    }
}

/// The eigenvalues (ascending) and orthonormal eigenvectors (columns, in
/// the same order) of the symmetric `n × n` matrix `a` (column-major, both
/// triangles set), by cyclic Jacobi, to LAPACK's accuracy (each eigenvalue
/// within a few ulps of ‖A‖); `None` when `a` is not finite or the sweeps
/// run out.
pub(super) fn symmetric_eigen(mut a: Square, n: usize) -> Option<(Vec<f64>, Square)> {
    if !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let mut v = identity(n);
    // couplings below the rounding of the whole matrix are noise that
    // rotations among null directions regenerate: LAPACK's accuracy
    let floor = tolerance(n) * norm(&a);
    let converged = sweeps(n, |p, q| {
        let (app, aqq, apq) = (a[p * n + p], a[q * n + q], a[q * n + p]);
        let relative = tolerance(n) * app.abs().sqrt() * aqq.abs().sqrt();
        if apq.abs() <= relative.max(floor) {
            return false;
        }
        let Some(cs) = rotation(app, aqq, apq) else {
            return false;
        };
        rotate_columns(&mut a, n, (p, q), cs);
        rotate_rows(&mut a, n, (p, q), cs);
        rotate_columns(&mut v, n, (p, q), cs);
        true
    });
    if !converged {
        return None;
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| a[i * n + i].total_cmp(&a[j * n + j]));
    let values = order.iter().map(|&i| a[i * n + i]).collect();
    Some((values, permuted_columns(&v, n, &order)))
}

/// Cyclic sweeps over the pairs `p < q` of `n`, `rotate(p, q)` saying
/// whether it turned the pair, until a sweep turns none (`true`) or
/// [`MAX_SWEEPS`] run out (`false`).
fn sweeps(n: usize, mut rotate: impl FnMut(usize, usize) -> bool) -> bool {
    (0..MAX_SWEEPS).any(|_| {
        let mut rotated = false;
        for p in 0..n {
            for q in p + 1..n {
                rotated |= rotate(p, q);
            }
        }
        !rotated
    })
}

/// Rows `p`, `q` of the `n × n` column-major `m` turned by `(c, s)`.
fn rotate_rows(m: &mut [f64], n: usize, (p, q): (usize, usize), (c, s): (f64, f64)) {
    for col in 0..n {
        let (x, y) = (m[col * n + p], m[col * n + q]);
        m[col * n + p] = c * x - s * y;
        m[col * n + q] = s * x + c * y;
    }
}

fn permuted_columns(m: &[f64], n: usize, order: &[usize]) -> Square {
    order
        .iter()
        .flat_map(|&k| m[k * n..(k + 1) * n].iter().copied())
        .collect()
}

/// The SVD `a = U Σ Vᵀ` of the `n × n` matrix `a` (column-major): the
/// singular values (descending), U and V (not Vᵀ), by one-sided Jacobi
/// (Hestenes: rotate column pairs of `a` until they are orthogonal); U's
/// columns for zero singular values complete an orthonormal basis. `None`
/// when `a` is not finite or the sweeps run out.
pub(super) fn square_svd(mut a: Square, n: usize) -> Option<(Vec<f64>, Square, Square)> {
    if !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let mut v = identity(n);
    let dot = |a: &[f64], i: usize, j: usize| -> f64 {
        (0..n).map(|r| a[i * n + r] * a[j * n + r]).sum()
    };
    let converged = sweeps(n, |p, q| {
        let (alpha, beta, gamma) = (dot(&a, p, p), dot(&a, q, q), dot(&a, p, q));
        let (small, big) = (alpha.min(beta).sqrt(), alpha.max(beta).sqrt());
        // a column below the other's rounding is null already
        if gamma == 0.0 || gamma.abs() <= tolerance(n) * small * big || small <= tolerance(n) * big
        {
            return false;
        }
        let Some(cs) = rotation(alpha, beta, gamma) else {
            return false;
        };
        rotate_columns(&mut a, n, (p, q), cs);
        rotate_columns(&mut v, n, (p, q), cs);
        true
    });
    if !converged {
        return None;
    }
    let sigma: Vec<f64> = (0..n).map(|k| dot(&a, k, k).sqrt()).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| sigma[j].total_cmp(&sigma[i]));
    let mut u = permuted_columns(&a, n, &order);
    let s: Vec<f64> = order.iter().map(|&k| sigma[k]).collect();
    normalise_or_complete(&mut u, n, &s);
    Some((s, u, permuted_columns(&v, n, &order)))
}

/// Scales U's columns by `1/σ`; those whose σ is null to rounding (below
/// [`tolerance`] times the largest: the last ones, σ descending; their
/// direction is rounding noise) become unit vectors orthogonal to every
/// column before them (Gram–Schmidt, twice, on the coordinate vector that
/// keeps most).
fn normalise_or_complete(u: &mut [f64], n: usize, s: &[f64]) {
    let null = tolerance(n) * s.first().copied().unwrap_or(0.0);
    for k in 0..n {
        let col = k * n..(k + 1) * n;
        if s[k] > null {
            u[col].iter_mut().for_each(|x| *x /= s[k]);
            continue;
        }
        let best = (0..n)
            .map(|e| {
                let mut x = vec![0.0; n];
                x[e] = 1.0;
                orthogonalise(&mut x, &u[..k * n], n);
                x
            })
            .max_by(|x, y| norm(x).total_cmp(&norm(y)))
            .expect("n ≥ 1");
        let l = norm(&best);
        u[col].iter_mut().zip(&best).for_each(|(d, x)| *d = x / l);
    }
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// `x` minus its projections on the unit columns of `basis` (`n` rows),
/// twice (classical Gram–Schmidt with one reorthogonalisation).
fn orthogonalise(x: &mut [f64], basis: &[f64], n: usize) {
    for _ in 0..2 {
        for b in basis.chunks_exact(n) {
            let d: f64 = b.iter().zip(x.iter()).map(|(p, q)| p * q).sum();
            x.iter_mut().zip(b).for_each(|(xi, bi)| *xi -= d * bi);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    fn mat(m: &DMatrix<f64>) -> Square {
        m.as_slice().to_vec()
    }

    fn back(v: &Square, n: usize) -> DMatrix<f64> {
        DMatrix::from_column_slice(n, n, v)
    }

    /// An orthonormal basis of order `n` (a fixed one).
    fn basis(n: usize) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3 + 1) as f64).sin())
            .qr()
            .q()
    }

    #[test]
    fn eigen_ascending_orthonormal_and_exact_on_clusters() {
        for values in [
            vec![3.0, -1.0, 2.0, 0.5],
            vec![1.0, 1.0, 1.0, 1e-12],
            vec![0.0, 0.0, 5.0],
            vec![2.0; 8],
            vec![-4.0],
        ] {
            let n = values.len();
            let q = basis(n);
            let d = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(&values));
            let a = &q * d * q.transpose();
            let a = (&a + a.transpose()) / 2.0;
            let (w, v) = symmetric_eigen(mat(&a), n).unwrap();
            let mut want = values.clone();
            want.sort_by(f64::total_cmp);
            for (x, y) in w.iter().zip(&want) {
                assert!((x - y).abs() < 1e-13 * 5.0, "{w:?} vs {want:?}");
            }
            let v = back(&v, n);
            assert!((v.transpose() * &v - DMatrix::identity(n, n)).amax() < 1e-14);
            let dw = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(w));
            assert!((&v * dw * v.transpose() - &a).amax() < 1e-13);
        }
        assert!(symmetric_eigen(vec![1.0, f64::NAN, f64::NAN, 2.0], 2).is_none());
    }

    /// A graded positive definite matrix D B D (B well conditioned, D with
    /// entries 1 … 1e-12) and an arrow matrix with a null block (which
    /// keeps plain Jacobi rotating on rounding noise): the eigenvalues
    /// within a few ulps of ‖A‖ of faer's.
    #[test]
    fn eigenvalues_agree_with_faer_to_the_norms_rounding() {
        let n = 4;
        let b = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                2.0
            } else {
                0.3 / (1.0 + (i + j) as f64)
            }
        });
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![1.0, 1e-4, 1e-8, 1e-12]));
        let graded = &d * &b * &d;
        let mut arrow = DMatrix::<f64>::zeros(5, 5);
        for (k, x) in [
            -1.0047850454245124,
            -0.06516373288130786,
            -0.04025811755584945,
            0.03545083147396698,
        ]
        .iter()
        .enumerate()
        {
            arrow[(4, k)] = *x;
            arrow[(k, 4)] = *x;
        }
        arrow[(4, 4)] = 0.1895785404257982;
        for a in [graded, arrow] {
            let n = a.nrows();
            let (w, _) = symmetric_eigen(mat(&a), n).unwrap();
            let f = faer::Mat::from_fn(n, n, |i, j| a[(i, j)]);
            let mut fw: Vec<f64> = f.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
            fw.sort_by(f64::total_cmp);
            for (x, y) in w.iter().zip(&fw) {
                assert!(
                    (x - y).abs() < 8.0 * f64::EPSILON * a.norm(),
                    "{w:?} vs {fw:?}"
                );
            }
        }
    }

    #[test]
    fn svd_descending_orthonormal_and_complete_when_rank_deficient() {
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, 2.0, 3.0, 4.0, //
                2.0, 4.0, 6.0, 8.0, //
                0.0, 1.0, 0.0, 1.0, //
                0.0, 0.0, 0.0, 0.0,
            ],
        );
        for a in [
            a,
            basis(5)
                * DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![
                    3.0, 1e-3, 1e-9, 1e-15, 0.5,
                ]))
                * basis(5).transpose(),
        ] {
            let n = a.nrows();
            let (s, u, v) = square_svd(mat(&a), n).unwrap();
            let (u, v) = (back(&u, n), back(&v, n));
            assert!(s.windows(2).all(|p| p[0] >= p[1]), "{s:?}");
            let id = DMatrix::<f64>::identity(n, n);
            assert!((u.transpose() * &u - &id).amax() < 1e-13, "{u}");
            assert!((v.transpose() * &v - &id).amax() < 1e-13);
            let sigma = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(s));
            assert!((&u * sigma * v.transpose() - &a).amax() < 1e-13);
        }
        assert!(square_svd(vec![f64::INFINITY, 0.0, 0.0, 1.0], 2).is_none());
    }

    /// A graded matrix B D: its singular values to high relative accuracy.
    #[test]
    fn graded_singular_values_keep_their_relative_accuracy() {
        let n = 4;
        let b = basis(n) + DMatrix::from_fn(n, n, |i, j| 0.1 * ((i + 2 * j) as f64).cos());
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![1.0, 1e-5, 1e-10, 1e-14]));
        let a = &b * &d;
        let (s, _, _) = square_svd(mat(&a), n).unwrap();
        let f = faer::Mat::from_fn(n, n, |i, j| a[(i, j)]);
        let fs = f.singular_values().unwrap();
        for (x, y) in s.iter().zip(&fs) {
            assert!(((x - y) / y).abs() < 1e-10, "{s:?} vs {fs:?}");
        }
    }
}
