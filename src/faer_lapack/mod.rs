//! # A pure-Rust BLAS/LAPACK subset on faer, for Clarabel's PSD cones
//!
//! **Why this module exists.** Clarabel's semidefinite cones call eight
//! double-precision BLAS/LAPACK routines through the `blas`/`lapack` crates:
//! `dgemm_`, `dsyrk_`, `dsyr2k_` (BLAS 3) and `dpotrf_`, `dpotrs_`, `dsyevr_`,
//! `dgesdd_`, `dgesvd_` (LAPACK). Those crates only *declare* the symbols; some
//! other crate must provide a library that defines them. Clarabel's own
//! providers either download and build OpenBLAS at build time (fails offline)
//! or need a system library. This module defines the symbols itself
//! (`#[unsafe(no_mangle)] extern "C"`), implemented on [faer], so the crate
//! builds with plain `cargo` anywhere and links no system BLAS.
//!
//! Every routine follows the reference Fortran calling convention exactly as
//! the `blas-sys`/`lapack-sys` declarations expect it: all arguments by
//! pointer, column-major storage with a leading dimension (`lda ≥ max(1, rows)`),
//! single-character flags (case-insensitive), workspace queries with
//! `lwork = -1` / `liwork = -1`, and LAPACK `info` codes (`-i` for a bad
//! `i`-th argument, positive for a numerical failure). BLAS routines, which
//! have no `info`, return without touching their outputs on bad arguments
//! (the reference `xerbla` would abort the process, which a library must not).
//!
//! The module is compiled only with the default `faer-lapack` feature; the
//! opt-in `system-openblas` feature links a system OpenBLAS instead and the
//! two are mutually exclusive.
//!
//! One file per routine family: [`blas3`] (`dgemm_`, `dsyrk_`, `dsyr2k_`),
//! [`cholesky`] (`dpotrf_`, `dpotrs_`), [`syevr`] (`dsyevr_`) and [`svd`]
//! (`dgesdd_`, `dgesvd_`). The safe entry points used by tests are the `*_`
//! functions themselves, called through raw pointers.

pub mod blas3;
pub mod cholesky;
mod small;
pub mod svd;
pub mod syevr;
mod view;

#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;

/// Takes the address of every routine so that the linker keeps them, even
/// with linkers that resolve archives in one pass. The solver layer calls it
/// before handing a problem to Clarabel; it costs nothing at run time.
#[inline(never)]
pub fn ensure_linked() {
    let table: [*const (); 8] = [
        blas3::dgemm_ as *const (),
        blas3::dsyrk_ as *const (),
        blas3::dsyr2k_ as *const (),
        cholesky::dpotrf_ as *const (),
        cholesky::dpotrs_ as *const (),
        syevr::dsyevr_ as *const (),
        svd::dgesdd_ as *const (),
        svd::dgesvd_ as *const (),
    ];
    std::hint::black_box(table);
}
