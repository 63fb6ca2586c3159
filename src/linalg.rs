//! Small dense kernels the crate writes itself (large dense work is faer's,
//! small fixed-size algebra nalgebra's): the one Cholesky factorisation.

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

#[cfg(test)]
mod tests {
    use super::cholesky_in_place;

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
