//! Small dense kernels the crate writes itself (large dense work is faer's,
//! small fixed-size algebra nalgebra's): the Cholesky factorisation, and
//! the pivoted one of a positive semidefinite matrix.

/// The Cholesky factor L of the small SPD matrix `a` (n × n, row-major),
/// in place: its lower triangle becomes L with `A = L Lᵀ` (the upper
/// triangle is left as it was); `false` if `a` is not positive definite (a
/// pivot ≤ 0 or not finite).
pub(crate) fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    true
}

/// A factor F (r × n, row-major, r the numerical rank) with `FᵀF = A` up
/// to the rounding of the sums, of the positive semidefinite `a` (n × n,
/// row-major, symmetric; overwritten) by Cholesky with complete (diagonal)
/// pivoting: each step takes the largest remaining diagonal entry, and the
/// factorisation stops when none exceeds `tol` (what is left, a Schur
/// complement whose entries are at most `tol`, is dropped). `None` if a
/// value is not finite. O(n³/6) work against the eigen-decomposition's
/// ~9 n³: the same stability for a semidefinite matrix (Higham, *Accuracy
/// and Stability of Numerical Algorithms*, §10.3).
pub(crate) fn pivoted_cholesky(a: &mut [f64], n: usize, tol: f64) -> Option<(Vec<f64>, usize)> {
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let mut perm: Vec<usize> = (0..n).collect();
    let mut rank = 0;
    for k in 0..n {
        let m = (k..n).max_by(|&i, &j| a[i * n + i].total_cmp(&a[j * n + j]))?;
        if a[m * n + m] <= tol {
            break;
        }
        swap_symmetric(a, n, k, m);
        perm.swap(k, m);
        let d = a[k * n + k].sqrt();
        for i in k..n {
            a[i * n + k] /= d;
        }
        for j in k + 1..n {
            let ljk = a[j * n + k];
            for i in j..n {
                a[i * n + j] -= a[i * n + k] * ljk;
            }
        }
        rank = k + 1;
    }
    // F = Lᵀ Pᵀ: row k of F holds column k of L, at the original indices
    let mut f = vec![0.0; rank * n];
    for k in 0..rank {
        for i in k..n {
            f[k * n + perm[i]] = a[i * n + k];
        }
    }
    Some((f, rank))
}

/// Swaps rows and columns k < m of the symmetric `a` whose lower triangle
/// is current (the eliminated columns' rows too: they are L's).
fn swap_symmetric(a: &mut [f64], n: usize, k: usize, m: usize) {
    if k == m {
        return;
    }
    for c in 0..k {
        a.swap(k * n + c, m * n + c);
    }
    a.swap(k * n + k, m * n + m);
    for i in k + 1..m {
        let (x, y) = (a[i * n + k], a[m * n + i]);
        a[i * n + k] = y;
        a[m * n + i] = x;
    }
    for i in m + 1..n {
        a.swap(i * n + k, i * n + m);
    }
}

#[cfg(test)]
mod tests {
    use super::{cholesky_in_place, pivoted_cholesky};

    /// `FᵀF` gives a semidefinite matrix of rank 2 (of order 4) back, with
    /// two rows; a full-rank one keeps every row; NaN is refused.
    #[test]
    fn the_pivoted_factor_reproduces_a_semidefinite_matrix() {
        // A = BᵀB with B 2 × 4: rank 2; the largest diagonal is not first
        let b = [1.0, -2.0, 0.5, 3.0, 0.3, 1.0, -4.0, 0.2];
        let n = 4;
        let a: Vec<f64> = (0..n * n)
            .map(|ij| (0..2).map(|r| b[r * n + ij / n] * b[r * n + ij % n]).sum())
            .collect();
        let mut w = a.clone();
        let (f, rank) = pivoted_cholesky(&mut w, n, 1e-12).unwrap();
        assert_eq!(rank, 2);
        for i in 0..n {
            for j in 0..n {
                let v: f64 = (0..rank).map(|k| f[k * n + i] * f[k * n + j]).sum();
                assert!((v - a[i * n + j]).abs() < 1e-12, "({i}, {j}): {v}");
            }
        }
        let spd = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let (f, rank) = pivoted_cholesky(&mut spd.clone(), 3, 1e-12).unwrap();
        assert_eq!(rank, 3);
        let v: f64 = (0..3).map(|k| f[k * 3 + 1] * f[k * 3 + 2]).sum();
        assert!((v - 1.0).abs() < 1e-12);
        assert!(pivoted_cholesky(&mut [f64::NAN], 1, 1e-12).is_none());
    }

    /// `L Lᵀ` gives the matrix back; an indefinite one is refused.
    #[test]
    fn the_factor_reproduces_the_matrix() {
        let a = [4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let mut l = a;
        assert!(cholesky_in_place(&mut l, 3));
        for i in 0..3 {
            for j in 0..=i {
                let v: f64 = (0..=j).map(|k| l[i * 3 + k] * l[j * 3 + k]).sum();
                assert!((v - a[i * 3 + j]).abs() < 1e-12, "({i}, {j})");
            }
        }
        let mut bad = [1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky_in_place(&mut bad, 2));
        let mut nan = [f64::NAN];
        assert!(!cholesky_in_place(&mut nan, 1));
    }
}

/// `A⁻¹ b` for `a` symmetric positive definite (its lower triangle read),
/// by faer's Cholesky factorisation on the calling thread (the callers
/// solve many small systems in parallel already: a nested parallel
/// factorisation costs more in joins than it gains); `None` when `a` is
/// not positive definite.
pub(crate) fn spd_solve(mut a: faer::Mat<f64>, b: &[f64]) -> Option<Vec<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::cholesky::llt::factor::{
        LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
    };
    use faer::linalg::triangular_solve::{
        solve_lower_triangular_in_place, solve_upper_triangular_in_place,
    };
    let (p, seq) = (a.nrows(), faer::Par::Seq);
    let mut buf = MemBuffer::new(cholesky_in_place_scratch::<f64>(p, seq, Default::default()));
    let reg = LltRegularization::default();
    cholesky_in_place(
        a.as_mut(),
        reg,
        seq,
        MemStack::new(&mut buf),
        Default::default(),
    )
    .ok()?;
    let mut x = faer::Mat::<f64>::from_fn(p, 1, |i, _| b[i]);
    solve_lower_triangular_in_place(a.as_ref(), x.as_mut(), seq);
    solve_upper_triangular_in_place(a.as_ref().transpose(), x.as_mut(), seq);
    Some((0..p).map(|i| x[(i, 0)]).collect())
}
