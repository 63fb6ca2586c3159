//! BLAS level 3: `dgemm_`, `dsyrk_`, `dsyr2k_` on faer's matrix multiply.
//!
//! Semantics are those of reference BLAS:
//! - `beta = 0` means C is not read (NaNs in C are overwritten);
//! - `alpha = 0` or `k = 0` means A and B are not read;
//! - `dsyrk_`/`dsyr2k_` touch only the `uplo` triangle of C;
//! - on an invalid argument the routine returns without touching C
//!   (reference BLAS would call `xerbla` and abort the process).

use super::view::{flag, int, mat_mut, mat_ref, min_ld};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::reborrow::*;
use faer::{Accum, MatMut, MatRef, Par};
use std::os::raw::{c_char, c_int};

/// Validated `trans` flag: `false` for `N`, `true` for `T`/`C` (real data).
fn trans_flag(f: u8) -> Option<bool> {
    match f {
        b'N' => Some(false),
        b'T' | b'C' => Some(true),
        _ => None,
    }
}

fn uplo_flag(f: u8) -> Option<bool> {
    match f {
        b'U' => Some(true),
        b'L' => Some(false),
        _ => None,
    }
}

/// C ← β C on the whole matrix (β = 0 writes exact zeros).
fn scale_full(mut c: MatMut<'_, f64>, beta: f64) {
    for j in 0..c.ncols() {
        for i in 0..c.nrows() {
            c[(i, j)] = if beta == 0.0 { 0.0 } else { beta * c[(i, j)] };
        }
    }
}

/// C ← β C on one triangle (diagonal included) of a square C.
fn scale_triangle(mut c: MatMut<'_, f64>, upper: bool, beta: f64) {
    let n = c.nrows();
    for j in 0..n {
        let (lo, hi) = if upper { (0, j + 1) } else { (j, n) };
        for i in lo..hi {
            c[(i, j)] = if beta == 0.0 { 0.0 } else { beta * c[(i, j)] };
        }
    }
}

/// `op(X)`: the view itself or its transpose.
fn op(x: MatRef<'_, f64>, t: bool) -> MatRef<'_, f64> {
    if t { x.transpose() } else { x }
}

/// `C ← α op(A) op(B) + β C`, with op(A) `m × k`, op(B) `k × n`, C `m × n`.
///
/// # Safety
/// Fortran BLAS contract: every pointer valid for the sizes its leading
/// dimension and flags imply.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dgemm_(
    transa: *const c_char,
    transb: *const c_char,
    m: *const c_int,
    n: *const c_int,
    k: *const c_int,
    alpha: *const f64,
    a: *const f64,
    lda: *const c_int,
    b: *const f64,
    ldb: *const c_int,
    beta: *const f64,
    c: *mut f64,
    ldc: *const c_int,
) {
    unsafe {
        let (Some(ta), Some(tb)) = (trans_flag(flag(transa)), trans_flag(flag(transb))) else {
            return;
        };
        let (m, n, k) = (int(m), int(n), int(k));
        let (lda, ldb, ldc) = (int(lda), int(ldb), int(ldc));
        let nrowa = if ta { k } else { m };
        let nrowb = if tb { n } else { k };
        if m < 0 || n < 0 || k < 0 || lda < min_ld(nrowa) || ldb < min_ld(nrowb) || ldc < min_ld(m)
        {
            return;
        }
        let (alpha, beta) = (*alpha, *beta);
        if m == 0 || n == 0 || ((alpha == 0.0 || k == 0) && beta == 1.0) {
            return;
        }
        let (m, n, k) = (m as usize, n as usize, k as usize);
        let mut cm = mat_mut(c, m, n, ldc as usize);
        if alpha == 0.0 || k == 0 {
            scale_full(cm, beta);
            return;
        }
        let (ar, ac) = if ta { (k, m) } else { (m, k) };
        let (br, bc) = if tb { (n, k) } else { (k, n) };
        let av = op(mat_ref(a, ar, ac, lda as usize), ta);
        let bv = op(mat_ref(b, br, bc, ldb as usize), tb);
        let accum = if beta == 0.0 {
            Accum::Replace
        } else {
            if beta != 1.0 {
                scale_full(cm.rb_mut(), beta);
            }
            Accum::Add
        };
        matmul(cm, accum, av, bv, alpha, Par::Seq);
    }
}

/// Shared argument handling of `dsyrk_`/`dsyr2k_`: returns
/// `(upper, trans, n, k, C view)` or `None` when there is nothing to do.
///
/// # Safety
/// As the callers.
#[allow(clippy::too_many_arguments)]
unsafe fn rank_k_setup<'a>(
    uplo: *const c_char,
    trans: *const c_char,
    n: *const c_int,
    k: *const c_int,
    alpha: f64,
    lds: &[i64],
    beta: f64,
    c: *mut f64,
    ldc: *const c_int,
) -> Option<(bool, bool, usize, usize, MatMut<'a, f64>)> {
    unsafe {
        let upper = uplo_flag(flag(uplo))?;
        let t = trans_flag(flag(trans))?;
        let (n, k, ldc) = (int(n), int(k), int(ldc));
        let nrowa = if t { k } else { n };
        if n < 0 || k < 0 || lds.iter().any(|&ld| ld < min_ld(nrowa)) || ldc < min_ld(n) {
            return None;
        }
        if n == 0 || ((alpha == 0.0 || k == 0) && beta == 1.0) {
            return None;
        }
        let mut cm = mat_mut(c, n as usize, n as usize, ldc as usize);
        if beta != 1.0 {
            scale_triangle(cm.rb_mut(), upper, beta);
        }
        if alpha == 0.0 || k == 0 {
            return None;
        }
        Some((upper, t, n as usize, k as usize, cm))
    }
}

fn tri(upper: bool) -> BlockStructure {
    if upper {
        BlockStructure::TriangularUpper
    } else {
        BlockStructure::TriangularLower
    }
}

/// Symmetric rank-k update of one triangle of the `n × n` matrix C:
/// `C ← α A Aᵀ + β C` (`trans = N`, A is `n × k`) or `C ← α Aᵀ A + β C`
/// (`trans = T`/`C`, A is `k × n`).
///
/// # Safety
/// Fortran BLAS contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dsyrk_(
    uplo: *const c_char,
    trans: *const c_char,
    n: *const c_int,
    k: *const c_int,
    alpha: *const f64,
    a: *const f64,
    lda: *const c_int,
    beta: *const f64,
    c: *mut f64,
    ldc: *const c_int,
) {
    unsafe {
        let (alpha, beta) = (*alpha, *beta);
        let Some((upper, t, n, k, cm)) =
            rank_k_setup(uplo, trans, n, k, alpha, &[int(lda)], beta, c, ldc)
        else {
            return;
        };
        let (ar, ac) = if t { (k, n) } else { (n, k) };
        let x = op(mat_ref(a, ar, ac, int(lda) as usize), t); // n × k
        triangular::matmul(
            cm,
            tri(upper),
            Accum::Add,
            x,
            BlockStructure::Rectangular,
            x.transpose(),
            BlockStructure::Rectangular,
            alpha,
            Par::Seq,
        );
    }
}

/// Symmetric rank-2k update of one triangle of the `n × n` matrix C:
/// `C ← α A Bᵀ + α B Aᵀ + β C` (`trans = N`, A and B `n × k`) or
/// `C ← α Aᵀ B + α Bᵀ A + β C` (`trans = T`/`C`, A and B `k × n`).
///
/// # Safety
/// Fortran BLAS contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dsyr2k_(
    uplo: *const c_char,
    trans: *const c_char,
    n: *const c_int,
    k: *const c_int,
    alpha: *const f64,
    a: *const f64,
    lda: *const c_int,
    b: *const f64,
    ldb: *const c_int,
    beta: *const f64,
    c: *mut f64,
    ldc: *const c_int,
) {
    unsafe {
        let (alpha, beta) = (*alpha, *beta);
        let Some((upper, t, n, k, mut cm)) = rank_k_setup(
            uplo,
            trans,
            n,
            k,
            alpha,
            &[int(lda), int(ldb)],
            beta,
            c,
            ldc,
        ) else {
            return;
        };
        let (r, cc) = if t { (k, n) } else { (n, k) };
        let x = op(mat_ref(a, r, cc, int(lda) as usize), t); // n × k
        let y = op(mat_ref(b, r, cc, int(ldb) as usize), t); // n × k
        for (l, rr) in [(x, y), (y, x)] {
            triangular::matmul(
                cm.rb_mut(),
                tri(upper),
                Accum::Add,
                l,
                BlockStructure::Rectangular,
                rr.transpose(),
                BlockStructure::Rectangular,
                alpha,
                Par::Seq,
            );
        }
    }
}
