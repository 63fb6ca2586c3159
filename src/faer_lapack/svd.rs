//! Singular value decomposition: `dgesdd_` and `dgesvd_`.
//!
//! Both compute `A = U Σ Vᵀ` of the `m × n` matrix A with faer's SVD, or by
//! one-sided Jacobi for a small square one ([`super::small`]) (the algorithms
//! differ from LAPACK's, the contract does not): singular values in
//! descending order in `s`, U and Vᵀ written as the job flags ask:
//! - `'A'`: all columns of U (`m × m`) / all rows of Vᵀ (`n × n`);
//! - `'S'`: the first `min(m, n)` columns of U / rows of Vᵀ;
//! - `'O'`: those are written over A instead;
//! - `'N'`: not computed.
//!
//! Workspace queries (`lwork = -1`) answer LAPACK's documented minimum sizes;
//! the caller's workspace is not otherwise used, so any `lwork ≥ 1` is
//! accepted. On exit A is overwritten only for the `'O'` jobs (LAPACK allows
//! it to be destroyed in every case).

use super::view::{flag, int, mat_mut, mat_ref, min_ld};
use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::svd::{ComputeSvdVectors, svd, svd_scratch};
use faer::{Mat, MatMut, Par};
use std::os::raw::{c_char, c_int};

/// Which part of a singular-vector factor a job flag asks for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Job {
    All,
    Thin,
    Overwrite,
    None,
}

fn job(f: u8) -> Option<Job> {
    match f {
        b'A' => Some(Job::All),
        b'S' => Some(Job::Thin),
        b'O' => Some(Job::Overwrite),
        b'N' => Some(Job::None),
        _ => None,
    }
}

/// Computes the SVD of the `m × n` column-major A and writes U and Vᵀ where
/// their jobs ask. Returns `false` when the algorithm did not converge.
///
/// # Safety
/// Pointers valid for the sizes implied by the jobs and leading dimensions,
/// which the callers have checked.
#[allow(clippy::too_many_arguments)]
unsafe fn compute(
    ju: Job,
    jv: Job,
    m: usize,
    n: usize,
    a: *mut f64,
    lda: usize,
    s: *mut f64,
    u: *mut f64,
    ldu: usize,
    vt: *mut f64,
    ldvt: usize,
) -> bool {
    unsafe {
        let k = m.min(n);
        let want = |j: Job| match j {
            Job::All => ComputeSvdVectors::Full,
            Job::Thin | Job::Overwrite => ComputeSvdVectors::Thin,
            Job::None => ComputeSvdVectors::No,
        };
        let (cu, cv) = (want(ju), want(jv));
        let ucols = if ju == Job::All { m } else { k };
        let vcols = if jv == Job::All { n } else { k };
        let av = mat_ref(a, m, n, lda);
        let Some((sd, uo, vo)) = factor(av, cu, cv, (ucols, vcols)) else {
            return false;
        };
        for (i, x) in sd.into_iter().enumerate() {
            *s.add(i) = x;
        }
        if let Some(uo) = uo {
            let dst: MatMut<'_, f64> = if ju == Job::Overwrite {
                mat_mut(a, m, k, lda)
            } else {
                mat_mut(u, m, ucols, ldu)
            };
            let mut dst = dst;
            dst.copy_from(uo.as_ref());
        }
        if let Some(vo) = vo {
            let mut dst = if jv == Job::Overwrite {
                mat_mut(a, k, n, lda)
            } else {
                mat_mut(vt, vcols, n, ldvt)
            };
            dst.copy_from(vo.as_ref().transpose());
        }
        true
    }
}

/// SVD by "divide and conquer" (LAPACK's name; faer's algorithm): one job
/// flag `jobz` for both U and Vᵀ. With `jobz = 'O'`, U overwrites A when
/// `m ≥ n`, otherwise Vᵀ does and U is computed in full.
///
/// `iwork` (8·min(m, n) in LAPACK) is not used.
///
/// # Safety
/// Fortran LAPACK contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dgesdd_(
    jobz: *const c_char,
    m: *const c_int,
    n: *const c_int,
    a: *mut f64,
    lda: *const c_int,
    s: *mut f64,
    u: *mut f64,
    ldu: *const c_int,
    vt: *mut f64,
    ldvt: *const c_int,
    work: *mut f64,
    lwork: *const c_int,
    _iwork: *mut c_int,
    info: *mut c_int,
) {
    unsafe {
        *info = 0;
        let jz = job(flag(jobz));
        let (m, n, lda, ldu, ldvt, lwork) =
            (int(m), int(n), int(lda), int(ldu), int(ldvt), int(lwork));
        let (mn, mx) = (m.min(n), m.max(n));
        let wide = m < n;
        // (job for U, job for Vᵀ)
        let jobs = jz.map(|j| match j {
            Job::Overwrite if wide => (Job::All, Job::Overwrite),
            Job::Overwrite => (Job::Overwrite, Job::All),
            j => (j, j),
        });
        let lwmin = match jz {
            Some(Job::None) => 3 * mn + mx.max(7 * mn),
            Some(Job::Overwrite) => 3 * mn + mx.max(5 * mn * mn + 4 * mn),
            _ => 3 * mn * mn + (4 * mn * mn + 4 * mn).max(mx),
        }
        .max(1);
        let e = match jobs {
            None => -1,
            Some(_) if m < 0 => -2,
            Some(_) if n < 0 => -3,
            Some(_) if lda < min_ld(m) => -5,
            Some((ju, _)) if ldu < 1 || (matches!(ju, Job::All | Job::Thin) && ldu < m) => -8,
            Some((_, jv))
                if ldvt < 1 || (jv == Job::All && ldvt < n) || (jv == Job::Thin && ldvt < mn) =>
            {
                -10
            }
            Some(_) if lwork < 1 && lwork != -1 => -12,
            Some(_) => 0,
        };
        if e != 0 {
            *info = e;
            return;
        }
        if lwork == -1 {
            *work = lwmin as f64;
            return;
        }
        if m == 0 || n == 0 {
            return;
        }
        let (ju, jv) = jobs.unwrap_or((Job::None, Job::None));
        let ok = compute(
            ju,
            jv,
            m as usize,
            n as usize,
            a,
            lda as usize,
            s,
            u,
            ldu as usize,
            vt,
            ldvt as usize,
        );
        if !ok {
            *info = 1;
        }
    }
}

/// SVD with separate job flags for U (`jobu`) and Vᵀ (`jobvt`); they may not
/// both be `'O'`.
///
/// # Safety
/// Fortran LAPACK contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dgesvd_(
    jobu: *const c_char,
    jobvt: *const c_char,
    m: *const c_int,
    n: *const c_int,
    a: *mut f64,
    lda: *const c_int,
    s: *mut f64,
    u: *mut f64,
    ldu: *const c_int,
    vt: *mut f64,
    ldvt: *const c_int,
    work: *mut f64,
    lwork: *const c_int,
    info: *mut c_int,
) {
    unsafe {
        *info = 0;
        let (ju, jv) = (job(flag(jobu)), job(flag(jobvt)));
        let (m, n, lda, ldu, ldvt, lwork) =
            (int(m), int(n), int(lda), int(ldu), int(ldvt), int(lwork));
        let (mn, mx) = (m.min(n), m.max(n));
        let lwmin = (3 * mn + mx).max(5 * mn).max(1);
        let e = match (ju, jv) {
            (None, _) => -1,
            (_, None) | (Some(Job::Overwrite), Some(Job::Overwrite)) => -2,
            _ if m < 0 => -3,
            _ if n < 0 => -4,
            _ if lda < min_ld(m) => -6,
            (Some(u), _) if ldu < 1 || (matches!(u, Job::All | Job::Thin) && ldu < m) => -9,
            (_, Some(v))
                if ldvt < 1 || (v == Job::All && ldvt < n) || (v == Job::Thin && ldvt < mn) =>
            {
                -11
            }
            _ if lwork < lwmin && lwork != -1 => -13,
            _ => 0,
        };
        if e != 0 {
            *info = e;
            return;
        }
        if lwork == -1 {
            *work = lwmin as f64;
            return;
        }
        if m == 0 || n == 0 {
            return;
        }
        let (ju, jv) = (ju.unwrap_or(Job::None), jv.unwrap_or(Job::None));
        let ok = compute(
            ju,
            jv,
            m as usize,
            n as usize,
            a,
            lda as usize,
            s,
            u,
            ldu as usize,
            vt,
            ldvt as usize,
        );
        if !ok {
            *info = 1;
        }
    }
}

/// Singular values, U and V where asked.
type Factors = (Vec<f64>, Option<Mat<f64>>, Option<Mat<f64>>);

/// The singular values (descending), U (`m × ucols`) and V (`n × vcols`)
/// where asked, of `av`: a small square matrix by one-sided Jacobi
/// ([`super::small`]), others through faer. `None`: no convergence.
fn factor(
    av: faer::MatRef<'_, f64>,
    cu: ComputeSvdVectors,
    cv: ComputeSvdVectors,
    (ucols, vcols): (usize, usize),
) -> Option<Factors> {
    let (m, n) = (av.nrows(), av.ncols());
    let (want_u, want_v) = (cu != ComputeSvdVectors::No, cv != ComputeSvdVectors::No);
    if m == n && n <= super::small::SMALL {
        let a = (0..n * n).map(|k| av[(k % n, k / n)]).collect();
        let (s, u, v) = super::small::square_svd(a, n)?;
        let to_faer = |x: Vec<f64>| Mat::from_fn(n, n, |i, j| x[j * n + i]);
        return Some((s, want_u.then(|| to_faer(u)), want_v.then(|| to_faer(v))));
    }
    let mut uo = want_u.then(|| Mat::<f64>::zeros(m, ucols));
    let mut vo = want_v.then(|| Mat::<f64>::zeros(n, vcols));
    let mut sd = Diag::<f64>::zeros(m.min(n));
    let mut buf = MemBuffer::new(svd_scratch::<f64>(
        m,
        n,
        cu,
        cv,
        Par::Seq,
        Default::default(),
    ));
    svd(
        av,
        sd.as_mut(),
        uo.as_mut().map(|x| x.as_mut()),
        vo.as_mut().map(|x| x.as_mut()),
        Par::Seq,
        MemStack::new(&mut buf),
        Default::default(),
    )
    .ok()?;
    Some(((0..m.min(n)).map(|i| sd[i]).collect(), uo, vo))
}
