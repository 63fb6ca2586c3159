//! Symmetric eigen-decomposition: `dsyevr_`.
//!
//! Computes all eigenvalues (and optionally eigenvectors) with faer's
//! self-adjoint EVD (by Jacobi rotations for a small matrix: [`super::small`]), then selects the requested ones (`range = 'A'` all,
//! `'V'` those in the half-open interval (vl, vu], `'I'` the il-th through
//! iu-th in ascending order, 1-based). `abstol` is accepted and ignored: the
//! eigenvalues are always computed to full working accuracy. The caller's
//! `work`/`iwork` are only used to answer workspace queries
//! (`lwork = -1` or `liwork = -1`); the minimal sizes LAPACK documents
//! (`26 n` and `10 n`) are still enforced so that code which runs here also
//! runs on a real LAPACK.

use super::view::{flag, int, mat_mut, mat_ref, min_ld};
use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use faer::{Mat, Par};
use std::os::raw::{c_char, c_int};

/// Eigenvalues and optionally eigenvectors of the `n × n` symmetric A, of which
/// only the `uplo` triangle is read.
///
/// On exit `m` holds the number of eigenvalues found, `w[0..m]` the eigenvalues
/// in ascending order, and with `jobz = 'V'` the columns of Z (`ldz ≥ n`) the
/// orthonormal eigenvectors. `isuppz[2i], isuppz[2i+1]` are the 1-based first
/// and last non-zero rows of eigenvector i. A itself is left unchanged (LAPACK
/// allows it to be destroyed).
///
/// # Safety
/// Fortran LAPACK contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dsyevr_(
    jobz: *const c_char,
    range: *const c_char,
    uplo: *const c_char,
    n: *const c_int,
    a: *mut f64,
    lda: *const c_int,
    vl: *const f64,
    vu: *const f64,
    il: *const c_int,
    iu: *const c_int,
    _abstol: *const f64,
    m: *mut c_int,
    w: *mut f64,
    z: *mut f64,
    ldz: *const c_int,
    isuppz: *mut c_int,
    work: *mut f64,
    lwork: *const c_int,
    iwork: *mut c_int,
    liwork: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        *info = 0;
        let (jobz, range, uplo) = (flag(jobz), flag(range), flag(uplo));
        let (n, lda, ldz, lwork, liwork) = (int(n), int(lda), int(ldz), int(lwork), int(liwork));
        let wantz = jobz == b'V';
        let query = lwork == -1 || liwork == -1;
        let lwmin = (26 * n).max(1);
        let liwmin = (10 * n).max(1);
        let (il, iu) = (int(il), int(iu));
        let e = if !(wantz || jobz == b'N') {
            -1
        } else if !matches!(range, b'A' | b'V' | b'I') {
            -2
        } else if !matches!(uplo, b'U' | b'L') {
            -3
        } else if n < 0 {
            -4
        } else if lda < min_ld(n) {
            -6
        } else if range == b'V' && n > 0 && *vu <= *vl {
            -8
        } else if range == b'I' && (il < 1 || il > n.max(1)) {
            -9
        } else if range == b'I' && (iu < n.min(il) || iu > n) {
            -10
        } else if ldz < 1 || (wantz && ldz < n) {
            -15
        } else if lwork < lwmin && !query {
            -18
        } else if liwork < liwmin && !query {
            -20
        } else {
            0
        };
        if e != 0 {
            *info = e as c_int;
            return;
        }
        if query {
            *work = lwmin as f64;
            *iwork = liwmin as c_int;
            return;
        }
        *m = 0;
        if n == 0 {
            return;
        }
        let n = n as usize;
        let av = mat_ref(a, n, n, lda as usize);
        let lower = if uplo == b'U' { av.transpose() } else { av };
        let Some((vals, u)) = eigen(lower, wantz) else {
            *info = 1;
            return;
        };
        let selected: Vec<usize> = match range {
            b'A' => (0..n).collect(),
            b'V' => (0..n)
                .filter(|&i| vals[i] > *vl && vals[i] <= *vu)
                .collect(),
            _ => ((il - 1) as usize..iu as usize).collect(),
        };
        *m = selected.len() as c_int;
        for (out, &i) in selected.iter().enumerate() {
            *w.add(out) = vals[i];
        }
        if let Some(u) = u {
            if selected.is_empty() {
                return;
            }
            let mut zm = mat_mut(z, n, selected.len(), ldz as usize);
            for (out, &i) in selected.iter().enumerate() {
                let (mut first, mut last) = (0usize, 0usize);
                let mut seen = false;
                for r in 0..n {
                    let v = u[(r, i)];
                    zm[(r, out)] = v;
                    if v != 0.0 {
                        if !seen {
                            first = r;
                            seen = true;
                        }
                        last = r;
                    }
                }
                if !isuppz.is_null() {
                    *isuppz.add(2 * out) = (first + 1) as c_int;
                    *isuppz.add(2 * out + 1) = (last + 1) as c_int;
                }
            }
        }
    }
}

/// All eigenvalues (ascending) of the symmetric matrix whose lower triangle
/// is `lower`, and with `wantz` its eigenvectors; small orders by Jacobi
/// ([`super::small`]), others through faer. `None`: no convergence.
fn eigen(lower: faer::MatRef<'_, f64>, wantz: bool) -> Option<(Vec<f64>, Option<Mat<f64>>)> {
    let n = lower.nrows();
    if n <= super::small::SMALL {
        let a = (0..n * n).map(|k| lower[((k % n).max(k / n), (k % n).min(k / n))]);
        let (vals, v) = super::small::symmetric_eigen(a.collect(), n)?;
        let u = wantz.then(|| Mat::from_fn(n, n, |i, j| v[j * n + i]));
        return Some((vals, u));
    }
    let compute = if wantz {
        ComputeEigenvectors::Yes
    } else {
        ComputeEigenvectors::No
    };
    let mut s = Diag::<f64>::zeros(n);
    let mut u = wantz.then(|| Mat::<f64>::zeros(n, n));
    let mut buf = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        compute,
        Par::Seq,
        Default::default(),
    ));
    self_adjoint_evd(
        lower,
        s.as_mut(),
        u.as_mut().map(|u| u.as_mut()),
        Par::Seq,
        MemStack::new(&mut buf),
        Default::default(),
    )
    .ok()?;
    Some(((0..n).map(|i| s[i]).collect(), u))
}
