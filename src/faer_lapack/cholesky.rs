//! Cholesky factorisation and solve: `dpotrf_`, `dpotrs_`.
//!
//! `uplo = 'L'` factors A = L Lᵀ in the lower triangle; `uplo = 'U'` factors
//! A = Uᵀ U in the upper triangle. An upper-stored matrix is handled as the
//! transposed view of a lower-stored one (swap of strides, no copy), so the
//! other triangle is never read or written, as in LAPACK.

use super::view::{flag, int, mat_mut, mat_ref, min_ld};
use faer::Mat;
use faer::Par;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    LltError, LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::*;
use std::os::raw::{c_char, c_int};

fn uplo_flag(f: u8) -> Option<bool> {
    match f {
        b'U' => Some(true),
        b'L' => Some(false),
        _ => None,
    }
}

/// Cholesky factorisation of the `n × n` symmetric positive definite A.
///
/// `info = 0` on success; `-i` when argument `i` is invalid; `i > 0` when the
/// leading minor of order `i` is not positive definite (the factorisation
/// stops there, as in LAPACK).
///
/// # Safety
/// Fortran LAPACK contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpotrf_(
    uplo: *const c_char,
    n: *const c_int,
    a: *mut f64,
    lda: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        *info = 0;
        let Some(upper) = uplo_flag(flag(uplo)) else {
            *info = -1;
            return;
        };
        let (n, lda) = (int(n), int(lda));
        if n < 0 {
            *info = -2;
            return;
        }
        if lda < min_ld(n) {
            *info = -4;
            return;
        }
        if n == 0 {
            return;
        }
        let n = n as usize;
        // faer's in-place factorisation uses the strictly upper part of its
        // matrix as scratch; LAPACK promises not to touch the other triangle,
        // so factor a copy of the referenced triangle and write it back.
        let am = mat_mut(a, n, n, lda as usize);
        let mut lower = if upper { am.transpose_mut() } else { am };
        let mut work = Mat::<f64>::zeros(n, n);
        for j in 0..n {
            for i in j..n {
                work[(i, j)] = lower[(i, j)];
            }
        }
        let mut buf = MemBuffer::new(cholesky_in_place_scratch::<f64>(
            n,
            Par::Seq,
            Default::default(),
        ));
        let stack = MemStack::new(&mut buf);
        let res = cholesky_in_place(
            work.as_mut(),
            LltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        );
        for j in 0..n {
            for i in j..n {
                lower[(i, j)] = work[(i, j)];
            }
        }
        if let Err(LltError::NonPositivePivot { index }) = res {
            *info = (index + 1) as c_int;
        }
    }
}

/// Solves `A X = B` with the factor from [`dpotrf_`]; B is `n × nrhs` and is
/// overwritten by X.
///
/// # Safety
/// Fortran LAPACK contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dpotrs_(
    uplo: *const c_char,
    n: *const c_int,
    nrhs: *const c_int,
    a: *const f64,
    lda: *const c_int,
    b: *mut f64,
    ldb: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        *info = 0;
        let Some(upper) = uplo_flag(flag(uplo)) else {
            *info = -1;
            return;
        };
        let (n, nrhs, lda, ldb) = (int(n), int(nrhs), int(lda), int(ldb));
        *info = if n < 0 {
            -2
        } else if nrhs < 0 {
            -3
        } else if lda < min_ld(n) {
            -5
        } else if ldb < min_ld(n) {
            -7
        } else {
            0
        };
        if *info != 0 || n == 0 || nrhs == 0 {
            return;
        }
        let (n, nrhs) = (n as usize, nrhs as usize);
        let av = mat_ref(a, n, n, lda as usize);
        let l = if upper { av.transpose() } else { av };
        let mut bm = mat_mut(b, n, nrhs, ldb as usize);
        solve_lower_triangular_in_place(l, bm.rb_mut(), Par::Seq);
        solve_upper_triangular_in_place(l.transpose(), bm, Par::Seq);
    }
}
