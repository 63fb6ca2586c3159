//! Helpers shared by the routines: flag decoding and column-major views.

use faer::{MatMut, MatRef};
use std::os::raw::{c_char, c_int};

/// Reads a single-character Fortran flag, upper-cased.
///
/// # Safety
/// `p` must point to a readable byte.
#[inline]
pub(crate) unsafe fn flag(p: *const c_char) -> u8 {
    unsafe { (*p as u8).to_ascii_uppercase() }
}

/// Reads an integer argument passed by pointer.
///
/// # Safety
/// `p` must point to a readable `c_int`.
#[inline]
pub(crate) unsafe fn int(p: *const c_int) -> i64 {
    unsafe { *p as i64 }
}

/// An `nrows × ncols` column-major view with leading dimension `ld`.
///
/// # Safety
/// `ptr` must be valid for `ld * (ncols - 1) + nrows` reads and `nrows, ncols > 0`.
#[inline]
pub(crate) unsafe fn mat_ref<'a>(
    ptr: *const f64,
    nrows: usize,
    ncols: usize,
    ld: usize,
) -> MatRef<'a, f64> {
    debug_assert!(nrows > 0 && ncols > 0 && !ptr.is_null());
    unsafe { MatRef::from_raw_parts(ptr, nrows, ncols, 1, ld as isize) }
}

/// Mutable version of [`mat_ref`].
///
/// # Safety
/// As [`mat_ref`], plus exclusive access.
#[inline]
pub(crate) unsafe fn mat_mut<'a>(
    ptr: *mut f64,
    nrows: usize,
    ncols: usize,
    ld: usize,
) -> MatMut<'a, f64> {
    debug_assert!(nrows > 0 && ncols > 0 && !ptr.is_null());
    unsafe { MatMut::from_raw_parts_mut(ptr, nrows, ncols, 1, ld as isize) }
}

/// `max(1, n)`, the smallest legal leading dimension for `n` rows.
#[inline]
pub(crate) fn min_ld(n: i64) -> i64 {
    n.max(1)
}
