//! Plain reference implementations (triple loops, Jacobi) used only by the
//! tests of this module. Column-major `Vec<f64>` with an explicit leading
//! dimension, like the routines under test.

/// Deterministic xorshift generator for test data.
pub struct Rng(pub u64);
impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    /// Column-major `rows × cols` with leading dimension `ld`, padding filled
    /// with a sentinel that must never be read into results or overwritten.
    pub fn mat(&mut self, rows: usize, cols: usize, ld: usize) -> Vec<f64> {
        let mut v = vec![SENTINEL; ld.max(1) * cols.max(1)];
        for j in 0..cols {
            for i in 0..rows {
                v[i + j * ld] = self.next_f64();
            }
        }
        v
    }
}

/// Value stored in padding rows (beyond `rows` in each column).
pub const SENTINEL: f64 = 12345.678;

pub fn get(a: &[f64], ld: usize, i: usize, j: usize) -> f64 {
    a[i + j * ld]
}

/// `op(A)[i, j]`.
pub fn op_get(a: &[f64], ld: usize, t: bool, i: usize, j: usize) -> f64 {
    if t {
        get(a, ld, j, i)
    } else {
        get(a, ld, i, j)
    }
}

/// Reference `α op(A) op(B) + β C` (β = 0 ignores C).
#[allow(clippy::too_many_arguments)]
pub fn gemm(
    ta: bool,
    tb: bool,
    m: usize,
    n: usize,
    k: usize,
    alpha: f64,
    a: &[f64],
    lda: usize,
    b: &[f64],
    ldb: usize,
    beta: f64,
    c: &mut [f64],
    ldc: usize,
) {
    for j in 0..n {
        for i in 0..m {
            let mut s = 0.0;
            for l in 0..k {
                s += op_get(a, lda, ta, i, l) * op_get(b, ldb, tb, l, j);
            }
            let old = if beta == 0.0 {
                0.0
            } else {
                beta * c[i + j * ldc]
            };
            c[i + j * ldc] = if k == 0 || alpha == 0.0 {
                old
            } else {
                alpha * s + old
            };
        }
    }
}

/// Symmetric eigenvalues by cyclic Jacobi, ascending. `a` is a full dense
/// `n × n` matrix (ld = n).
pub fn jacobi_eigenvalues(mut a: Vec<f64>, n: usize) -> Vec<f64> {
    for _sweep in 0..100 {
        let mut off = 0.0;
        for j in 0..n {
            for i in 0..n {
                if i != j {
                    off += a[i + j * n] * a[i + j * n];
                }
            }
        }
        if off < 1e-30 {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p + q * n];
                if apq.abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q + q * n] - a[p + p * n]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let akp = a[k + p * n];
                    let akq = a[k + q * n];
                    a[k + p * n] = c * akp - s * akq;
                    a[k + q * n] = s * akp + c * akq;
                }
                for k in 0..n {
                    let apk = a[p + k * n];
                    let aqk = a[q + k * n];
                    a[p + k * n] = c * apk - s * aqk;
                    a[q + k * n] = s * apk + c * aqk;
                }
            }
        }
    }
    let mut w: Vec<f64> = (0..n).map(|i| a[i + i * n]).collect();
    w.sort_by(f64::total_cmp);
    w
}

/// Reference Cholesky (lower, dense ld = n, column-major) of the symmetric
/// `a`, by the crate's own small-matrix Cholesky ([`crate::linalg`], not
/// faer's: the shim is tested against it); `None` if not positive definite.
pub fn cholesky_lower(a: &[f64], n: usize) -> Option<Vec<f64>> {
    // symmetric: the row-major reading of `a` is the same matrix
    let mut l = a.to_vec();
    if !crate::linalg::cholesky_in_place(&mut l, n) {
        return None;
    }
    // L (row-major, lower) to column-major, the upper triangle zero
    Some(
        (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                if i >= j { l[i * n + j] } else { 0.0 }
            })
            .collect(),
    )
}
