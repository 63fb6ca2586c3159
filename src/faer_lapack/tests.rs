//! Each routine against the plain references in [`super::reference`], on
//! random matrices with leading dimension > rows, every flag combination,
//! sizes 0 and 1, workspace queries and `info` codes.

use super::blas3::{dgemm_, dsyr2k_, dsyrk_};
use super::cholesky::{dpotrf_, dpotrs_};
use super::reference::{self as r, Rng, SENTINEL};
use super::svd::{dgesdd_, dgesvd_};
use super::syevr::dsyevr_;
use std::os::raw::{c_char, c_int};

fn ch(c: u8) -> c_char {
    c as c_char
}

const SIZES: [usize; 5] = [0, 1, 2, 5, 13];

/// Max abs difference over the logical `rows × cols` part; and asserts the
/// padding rows kept their sentinel.
fn diff(a: &[f64], b: &[f64], rows: usize, cols: usize, ld: usize) -> f64 {
    let mut d: f64 = 0.0;
    for j in 0..cols {
        for i in 0..ld {
            if i < rows {
                d = d.max((a[i + j * ld] - b[i + j * ld]).abs());
            } else {
                assert_eq!(a[i + j * ld], SENTINEL, "padding overwritten at ({i},{j})");
            }
        }
    }
    d
}

#[test]
fn gemm_matches_reference_all_flags_and_sizes() {
    let mut rng = Rng(0x9E3779B97F4A7C15);
    for &ta in &[b'N', b'T', b'c'] {
        for &tb in &[b'n', b'T', b'C'] {
            for &m in &SIZES {
                for &n in &SIZES {
                    for &k in &[0usize, 1, 4, 7] {
                        for &(alpha, beta) in &[(1.0, 0.0), (0.7, 1.0), (-1.3, 0.5), (0.0, 2.0)] {
                            let t_a = ta != b'N' && ta != b'n';
                            let t_b = tb != b'N' && tb != b'n';
                            let (ar, ac) = if t_a { (k, m) } else { (m, k) };
                            let (br, bc) = if t_b { (n, k) } else { (k, n) };
                            let (lda, ldb, ldc) = (ar + 2, br + 1, m + 3);
                            let a = rng.mat(ar, ac, lda);
                            let b = rng.mat(br, bc, ldb);
                            let mut c = rng.mat(m, n, ldc);
                            if beta == 0.0 && m > 0 && n > 0 {
                                c[0] = f64::NAN; // must not be read
                            }
                            let mut cref = c.clone();
                            r::gemm(
                                t_a, t_b, m, n, k, alpha, &a, lda, &b, ldb, beta, &mut cref, ldc,
                            );
                            let (mi, ni, ki) = (m as c_int, n as c_int, k as c_int);
                            let (li, lb, lc) = (lda as c_int, ldb as c_int, ldc as c_int);
                            unsafe {
                                dgemm_(
                                    &ch(ta),
                                    &ch(tb),
                                    &mi,
                                    &ni,
                                    &ki,
                                    &alpha,
                                    a.as_ptr(),
                                    &li,
                                    b.as_ptr(),
                                    &lb,
                                    &beta,
                                    c.as_mut_ptr(),
                                    &lc,
                                );
                            }
                            let d = diff(&c, &cref, m, n, ldc);
                            assert!(d < 1e-12, "gemm {ta} {tb} m={m} n={n} k={k}: {d}");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn gemm_bad_arguments_leave_c_untouched() {
    let a = vec![1.0; 16];
    let mut c = vec![5.0; 16];
    let (two, one, alpha, beta) = (2 as c_int, 1 as c_int, 1.0, 0.0);
    unsafe {
        dgemm_(
            &ch(b'X'),
            &ch(b'N'),
            &two,
            &two,
            &two,
            &alpha,
            a.as_ptr(),
            &two,
            a.as_ptr(),
            &two,
            &beta,
            c.as_mut_ptr(),
            &two,
        );
        // lda = 1 < m = 2
        dgemm_(
            &ch(b'N'),
            &ch(b'N'),
            &two,
            &two,
            &two,
            &alpha,
            a.as_ptr(),
            &one,
            a.as_ptr(),
            &two,
            &beta,
            c.as_mut_ptr(),
            &two,
        );
    }
    assert!(c.iter().all(|&x| x == 5.0));
}

/// Reference for syrk/syr2k on the full matrix, then only the `uplo`
/// triangle is compared; the other triangle must be untouched.
#[test]
fn syrk_and_syr2k_match_reference_on_their_triangle() {
    let mut rng = Rng(42);
    for &uplo in &[b'U', b'l'] {
        for &trans in &[b'N', b't', b'C'] {
            for &n in &SIZES {
                for &k in &[0usize, 1, 3, 8] {
                    for &(alpha, beta) in &[(1.0, 0.0), (-0.4, 1.0), (2.0, -0.5), (0.0, 0.3)] {
                        let t = trans != b'N';
                        let (ar, ac) = if t { (k, n) } else { (n, k) };
                        let (lda, ldb, ldc) = (ar + 1, ar + 3, n + 2);
                        let a = rng.mat(ar, ac, lda);
                        let b = rng.mat(ar, ac, ldb);
                        let c0 = rng.mat(n, n, ldc);
                        // references: full products, via gemm
                        // syrk uses op(A) op(A)ᵀ: N → A Aᵀ (ta=false, tb=true)
                        let mut c1 = c0.clone();
                        r::gemm(t, !t, n, n, k, alpha, &a, lda, &a, lda, beta, &mut c1, ldc);
                        let mut c2 = c0.clone();
                        r::gemm(t, !t, n, n, k, alpha, &a, lda, &b, ldb, beta, &mut c2, ldc);
                        r::gemm(t, !t, n, n, k, alpha, &b, ldb, &a, lda, 1.0, &mut c2, ldc);
                        let upper = uplo == b'U';
                        for (c_ref, two) in [(c1, false), (c2, true)] {
                            let mut c = c0.clone();
                            let (ni, ki, la, lb, lc) = (
                                n as c_int,
                                k as c_int,
                                lda as c_int,
                                ldb as c_int,
                                ldc as c_int,
                            );
                            unsafe {
                                if two {
                                    dsyr2k_(
                                        &ch(uplo),
                                        &ch(trans),
                                        &ni,
                                        &ki,
                                        &alpha,
                                        a.as_ptr(),
                                        &la,
                                        b.as_ptr(),
                                        &lb,
                                        &beta,
                                        c.as_mut_ptr(),
                                        &lc,
                                    );
                                } else {
                                    dsyrk_(
                                        &ch(uplo),
                                        &ch(trans),
                                        &ni,
                                        &ki,
                                        &alpha,
                                        a.as_ptr(),
                                        &la,
                                        &beta,
                                        c.as_mut_ptr(),
                                        &lc,
                                    );
                                }
                            }
                            for j in 0..n {
                                for i in 0..ldc {
                                    let got = c[i + j * ldc];
                                    let in_tri = i < n && if upper { i <= j } else { i >= j };
                                    let want = if in_tri {
                                        c_ref[i + j * ldc]
                                    } else {
                                        c0[i + j * ldc]
                                    };
                                    assert!(
                                        (got - want).abs() < 1e-12 || (!in_tri && got == want),
                                        "syr{}k {} {} n={n} k={k} ({i},{j}): {got} vs {want}",
                                        if two { "2" } else { "" },
                                        uplo as char,
                                        trans as char
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// A random symmetric positive definite matrix `M Mᵀ + n I`, dense ld = n.
fn spd(rng: &mut Rng, n: usize) -> Vec<f64> {
    let m = rng.mat(n, n, n);
    let mut a = vec![0.0; n * n];
    r::gemm(
        false,
        true,
        n,
        n,
        n,
        1.0,
        &m,
        n.max(1),
        &m,
        n.max(1),
        0.0,
        &mut a,
        n.max(1),
    );
    for i in 0..n {
        a[i + i * n] += n as f64;
    }
    a
}

/// Copies a dense (ld = n) matrix into a padded one with leading dimension ld.
fn pad(a: &[f64], rows: usize, cols: usize, ld: usize) -> Vec<f64> {
    let mut v = vec![SENTINEL; ld.max(1) * cols.max(1)];
    for j in 0..cols {
        for i in 0..rows {
            v[i + j * ld] = a[i + j * rows];
        }
    }
    v
}

#[test]
fn potrf_potrs_match_reference() {
    let mut rng = Rng(7);
    for &uplo in &[b'L', b'u'] {
        for &n in &SIZES {
            let a = spd(&mut rng, n);
            let lda = n + 2;
            let mut ap = pad(&a, n, n, lda);
            // poison the triangle that must not be read or written
            for j in 0..n {
                for i in 0..n {
                    let other = if uplo == b'L' { i < j } else { i > j };
                    if other {
                        ap[i + j * lda] = -999.0;
                    }
                }
            }
            let (ni, li) = (n as c_int, lda as c_int);
            let mut info: c_int = 77;
            unsafe { dpotrf_(&ch(uplo), &ni, ap.as_mut_ptr(), &li, &mut info) };
            assert_eq!(info, 0);
            let lref = r::cholesky_lower(&a, n).unwrap();
            for j in 0..n {
                for i in 0..n {
                    let v = ap[i + j * lda];
                    if uplo == b'L' {
                        if i >= j {
                            assert!((v - lref[i + j * n]).abs() < 1e-12);
                        } else {
                            assert_eq!(v, -999.0);
                        }
                    } else if i <= j {
                        assert!((v - lref[j + i * n]).abs() < 1e-12); // U = Lᵀ
                    } else {
                        assert_eq!(v, -999.0);
                    }
                }
            }
            // solve A X = B for 3 right-hand sides
            let nrhs = 3;
            let ldb = n + 1;
            let b = rng.mat(n, nrhs, ldb);
            let mut x = b.clone();
            let (nr, lb) = (nrhs as c_int, ldb as c_int);
            unsafe {
                dpotrs_(
                    &ch(uplo),
                    &ni,
                    &nr,
                    ap.as_ptr(),
                    &li,
                    x.as_mut_ptr(),
                    &lb,
                    &mut info,
                )
            };
            assert_eq!(info, 0);
            let mut ax = vec![SENTINEL; ldb * nrhs];
            let xd: Vec<f64> = (0..nrhs)
                .flat_map(|j| (0..n).map(move |i| (i, j)))
                .map(|(i, j)| x[i + j * ldb])
                .collect();
            r::gemm(
                false,
                false,
                n,
                nrhs,
                n,
                1.0,
                &a,
                n.max(1),
                &xd,
                n.max(1),
                0.0,
                &mut ax,
                ldb,
            );
            assert!(diff(&ax, &b, n, nrhs, ldb) < 1e-10);
        }
    }
}

#[test]
fn potrf_reports_non_positive_minor_and_bad_arguments() {
    // leading 2×2 minor [[1, 2], [2, 1]] is indefinite → info = 2
    let mut a = vec![1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let (n, lda) = (3 as c_int, 3 as c_int);
    let mut info = 0;
    unsafe { dpotrf_(&ch(b'L'), &n, a.as_mut_ptr(), &lda, &mut info) };
    assert_eq!(info, 2);
    unsafe { dpotrf_(&ch(b'Q'), &n, a.as_mut_ptr(), &lda, &mut info) };
    assert_eq!(info, -1);
    let neg = -1 as c_int;
    unsafe { dpotrf_(&ch(b'L'), &neg, a.as_mut_ptr(), &lda, &mut info) };
    assert_eq!(info, -2);
    let small = 2 as c_int;
    unsafe { dpotrf_(&ch(b'L'), &n, a.as_mut_ptr(), &small, &mut info) };
    assert_eq!(info, -4);
    let one = 1 as c_int;
    unsafe {
        dpotrs_(
            &ch(b'L'),
            &n,
            &one,
            a.as_ptr(),
            &lda,
            a.as_mut_ptr(),
            &small,
            &mut info,
        )
    };
    assert_eq!(info, -7);
}

#[test]
fn syevr_matches_jacobi_all_ranges() {
    let mut rng = Rng(99);
    for &jobz in &[b'N', b'V'] {
        for &uplo in &[b'U', b'L'] {
            for &n in &SIZES {
                let m0 = rng.mat(n, n, n);
                // symmetric dense
                let mut a = vec![0.0; n * n];
                for j in 0..n {
                    for i in 0..n {
                        a[i + j * n] = m0[i + j * n.max(1)] + m0[j + i * n.max(1)];
                    }
                }
                let wref = r::jacobi_eigenvalues(a.clone(), n);
                let lda = n + 3;
                let mut ap = pad(&a, n, n, lda);
                for j in 0..n {
                    for i in 0..n {
                        if (uplo == b'U' && i > j) || (uplo == b'L' && i < j) {
                            ap[i + j * lda] = f64::NAN; // never read
                        }
                    }
                }
                let ranges: Vec<(u8, f64, f64, c_int, c_int)> = {
                    let mut v = vec![(b'A', 0.0, 0.0, 0, 0)];
                    if n > 0 {
                        let mid = (n - 1) / 2;
                        let hi = if mid + 1 < n {
                            0.5 * (wref[mid] + wref[mid + 1])
                        } else {
                            wref[mid] + 1.0
                        };
                        let lo = wref[0] - 1.0;
                        v.push((b'V', lo, hi, 0, 0));
                        v.push((b'I', 0.0, 0.0, 1.max(n as c_int / 2), n as c_int));
                    }
                    v
                };
                for (range, vl, vu, il, iu) in ranges {
                    let (ni, li, ldz) = (n as c_int, lda as c_int, (n + 1).max(1) as c_int);
                    let mut work = vec![0.0; 1];
                    let mut iwork = vec![0 as c_int; 1];
                    let (mut m, mut info) = (0 as c_int, 0 as c_int);
                    let mut w = vec![0.0; n.max(1)];
                    let mut z = vec![0.0; ldz as usize * n.max(1)];
                    let mut isuppz = vec![0 as c_int; 2 * n.max(1)];
                    let abstol = -1.0;
                    let q = -1 as c_int;
                    unsafe {
                        dsyevr_(
                            &ch(jobz),
                            &ch(range),
                            &ch(uplo),
                            &ni,
                            ap.as_mut_ptr(),
                            &li,
                            &vl,
                            &vu,
                            &il,
                            &iu,
                            &abstol,
                            &mut m,
                            w.as_mut_ptr(),
                            z.as_mut_ptr(),
                            &ldz,
                            isuppz.as_mut_ptr(),
                            work.as_mut_ptr(),
                            &q,
                            iwork.as_mut_ptr(),
                            &q,
                            &mut info,
                        );
                    }
                    assert_eq!(info, 0);
                    let (lw, liw) = (work[0] as usize, iwork[0] as usize);
                    assert!(lw >= (26 * n).max(1) && liw >= (10 * n).max(1));
                    work.resize(lw, 0.0);
                    iwork.resize(liw, 0);
                    let (lwi, liwi) = (lw as c_int, liw as c_int);
                    unsafe {
                        dsyevr_(
                            &ch(jobz),
                            &ch(range),
                            &ch(uplo),
                            &ni,
                            ap.as_mut_ptr(),
                            &li,
                            &vl,
                            &vu,
                            &il,
                            &iu,
                            &abstol,
                            &mut m,
                            w.as_mut_ptr(),
                            z.as_mut_ptr(),
                            &ldz,
                            isuppz.as_mut_ptr(),
                            work.as_mut_ptr(),
                            &lwi,
                            iwork.as_mut_ptr(),
                            &liwi,
                            &mut info,
                        );
                    }
                    assert_eq!(info, 0);
                    let expect: Vec<f64> = match range {
                        b'A' => wref.clone(),
                        b'V' => wref
                            .iter()
                            .copied()
                            .filter(|&x| x > vl && x <= vu)
                            .collect(),
                        _ => wref[(il - 1) as usize..iu as usize].to_vec(),
                    };
                    assert_eq!(m as usize, expect.len(), "range {}", range as char);
                    for (i, e) in expect.iter().enumerate() {
                        assert!((w[i] - e).abs() < 1e-10, "eigenvalue {i}: {} vs {e}", w[i]);
                    }
                    if jobz == b'V' {
                        let ld = ldz as usize;
                        for c in 0..m as usize {
                            // A z = λ z and ‖z‖ = 1
                            let mut nrm = 0.0;
                            for i in 0..n {
                                let mut s = 0.0;
                                for k in 0..n {
                                    s += a[i + k * n] * z[k + c * ld];
                                }
                                assert!((s - w[c] * z[i + c * ld]).abs() < 1e-10);
                                nrm += z[i + c * ld] * z[i + c * ld];
                            }
                            assert!((nrm - 1.0).abs() < 1e-12);
                            assert!(isuppz[2 * c] >= 1 && isuppz[2 * c + 1] <= n as c_int);
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn syevr_argument_errors() {
    let mut a = vec![1.0; 4];
    let (n, lda) = (2 as c_int, 2 as c_int);
    let (mut m, mut info) = (0, 0);
    let mut w = vec![0.0; 2];
    let mut z = vec![0.0; 4];
    let mut isuppz = vec![0; 4];
    let mut work = vec![0.0; 100];
    let mut iwork = vec![0; 100];
    let (lw, liw, small) = (100 as c_int, 100 as c_int, 1 as c_int);
    let (vl, vu, il, iu, tol) = (1.0, 0.0, 1, 1, 0.0);
    let mut call = |jobz: u8, range: u8, ldz: c_int, lwork: c_int| unsafe {
        dsyevr_(
            &ch(jobz),
            &ch(range),
            &ch(b'U'),
            &n,
            a.as_mut_ptr(),
            &lda,
            &vl,
            &vu,
            &il,
            &iu,
            &tol,
            &mut m,
            w.as_mut_ptr(),
            z.as_mut_ptr(),
            &ldz,
            isuppz.as_mut_ptr(),
            work.as_mut_ptr(),
            &lwork,
            iwork.as_mut_ptr(),
            &liw,
            &mut info,
        );
        info
    };
    assert_eq!(call(b'X', b'A', 2, lw), -1);
    assert_eq!(call(b'V', b'X', 2, lw), -2);
    assert_eq!(call(b'V', b'V', 2, lw), -8); // vu <= vl
    assert_eq!(call(b'V', b'A', 1, lw), -15); // ldz < n
    assert_eq!(call(b'V', b'A', 2, small), -18);
}

/// Checks an SVD result: U Σ Vᵀ = A, orthonormal columns/rows, descending
/// singular values equal to √eig(AᵀA).
#[allow(clippy::too_many_arguments)]
fn check_svd(
    a: &[f64],
    m: usize,
    n: usize,
    s: &[f64],
    u: &[f64],
    ldu: usize,
    ucols: usize,
    vt: &[f64],
    ldvt: usize,
    vrows: usize,
) {
    let k = m.min(n);
    // reference singular values from AᵀA
    let mut ata = vec![0.0; n * n];
    r::gemm(
        true,
        false,
        n,
        n,
        m,
        1.0,
        a,
        m.max(1),
        a,
        m.max(1),
        0.0,
        &mut ata,
        n.max(1),
    );
    let ev = r::jacobi_eigenvalues(ata, n);
    for i in 0..k {
        let want = ev[n - 1 - i].max(0.0).sqrt();
        assert!((s[i] - want).abs() < 1e-10, "σ{i}: {} vs {want}", s[i]);
        if i > 0 {
            assert!(s[i] <= s[i - 1]);
        }
    }
    for i in 0..m {
        for j in 0..n {
            let mut x = 0.0;
            for l in 0..k {
                x += u[i + l * ldu] * s[l] * vt[l + j * ldvt];
            }
            assert!((x - a[i + j * m]).abs() < 1e-10, "reconstruction ({i},{j})");
        }
    }
    for p in 0..ucols {
        for q in 0..ucols {
            let d: f64 = (0..m).map(|i| u[i + p * ldu] * u[i + q * ldu]).sum();
            assert!((d - if p == q { 1.0 } else { 0.0 }).abs() < 1e-10, "UᵀU");
        }
    }
    for p in 0..vrows {
        for q in 0..vrows {
            let d: f64 = (0..n).map(|j| vt[p + j * ldvt] * vt[q + j * ldvt]).sum();
            assert!(
                (d - if p == q { 1.0 } else { 0.0 }).abs() < 1e-10,
                "VVᵀ m={m} n={n} p={p} q={q} d={d}"
            );
        }
    }
}

#[test]
fn gesdd_and_gesvd_all_jobs() {
    let mut rng = Rng(2024);
    let shapes = [
        (0usize, 3usize),
        (1, 1),
        (1, 4),
        (4, 1),
        (5, 5),
        (7, 3),
        (3, 8),
    ];
    for &(m, n) in &shapes {
        let k = m.min(n);
        let a = rng.mat(m, n, m.max(1));
        let lda = m + 2;
        // (routine, jobu, jobvt)
        let mut jobs = vec![];
        for j in [b'A', b'S', b'O', b'N'] {
            jobs.push((true, j, j));
        }
        for ju in [b'A', b'S', b'O', b'N'] {
            for jv in [b'A', b'S', b'O', b'N'] {
                if !(ju == b'O' && jv == b'O') {
                    jobs.push((false, ju, jv));
                }
            }
        }
        for (dd, ju, jv) in jobs {
            let mut ap = pad(&a, m, n, lda);
            let ucols = match (dd, ju) {
                (_, b'A') => m,
                (true, b'O') if m < n => m,
                _ => k,
            };
            let vrows = match (dd, jv) {
                (_, b'A') => n,
                (true, b'O') if m >= n => n,
                _ => k,
            };
            let ldu = m + 1;
            let ldvt = vrows.max(1) + 1;
            let mut u = vec![0.0; ldu * m.max(1)];
            let mut vt = vec![0.0; ldvt * n.max(1)];
            let mut s = vec![0.0; k.max(1)];
            let mut work = vec![0.0; 1];
            let mut iwork = vec![0 as c_int; 8 * k.max(1)];
            let (mi, ni, li, lu, lv) = (
                m as c_int,
                n as c_int,
                lda as c_int,
                ldu as c_int,
                ldvt as c_int,
            );
            let mut info = 0;
            for pass in 0..2 {
                let lw = if pass == 0 { -1 } else { work.len() as c_int };
                unsafe {
                    if dd {
                        dgesdd_(
                            &ch(ju),
                            &mi,
                            &ni,
                            ap.as_mut_ptr(),
                            &li,
                            s.as_mut_ptr(),
                            u.as_mut_ptr(),
                            &lu,
                            vt.as_mut_ptr(),
                            &lv,
                            work.as_mut_ptr(),
                            &lw,
                            iwork.as_mut_ptr(),
                            &mut info,
                        );
                    } else {
                        dgesvd_(
                            &ch(ju),
                            &ch(jv),
                            &mi,
                            &ni,
                            ap.as_mut_ptr(),
                            &li,
                            s.as_mut_ptr(),
                            u.as_mut_ptr(),
                            &lu,
                            vt.as_mut_ptr(),
                            &lv,
                            work.as_mut_ptr(),
                            &lw,
                            &mut info,
                        );
                    }
                }
                assert_eq!(
                    info,
                    0,
                    "{} {} {} m={m} n={n}",
                    if dd { "gesdd" } else { "gesvd" },
                    ju as char,
                    jv as char
                );
                if pass == 0 {
                    assert!(work[0] >= 1.0);
                    work.resize(work[0] as usize, 0.0);
                }
            }
            // fetch U and Vᵀ from where the job put them
            let u_in_a = ju == b'O' && !(dd && m < n);
            let v_in_a = jv == b'O' && !(dd && m >= n);
            let (uu, ldu2) = if u_in_a {
                (ap.clone(), lda)
            } else {
                (u.clone(), ldu)
            };
            let (vv, ldv2) = if v_in_a {
                (ap.clone(), lda)
            } else {
                (vt.clone(), ldvt)
            };
            if k == 0 {
                continue; // quick return: nothing is computed, as in LAPACK
            }
            if ju != b'N' && jv != b'N' {
                check_svd(&a, m, n, &s, &uu, ldu2, ucols, &vv, ldv2, vrows);
            } else {
                let mut ata = vec![0.0; n * n];
                r::gemm(
                    true,
                    false,
                    n,
                    n,
                    m,
                    1.0,
                    &a,
                    m.max(1),
                    &a,
                    m.max(1),
                    0.0,
                    &mut ata,
                    n.max(1),
                );
                let ev = r::jacobi_eigenvalues(ata, n);
                for i in 0..k {
                    assert!((s[i] - ev[n - 1 - i].max(0.0).sqrt()).abs() < 1e-10);
                }
            }
        }
    }
}

#[test]
fn svd_argument_errors() {
    let mut a = vec![1.0; 12];
    let (m, n, lda) = (3 as c_int, 2 as c_int, 3 as c_int);
    let mut s = vec![0.0; 2];
    let mut u = vec![0.0; 9];
    let mut vt = vec![0.0; 4];
    let mut work = vec![0.0; 200];
    let mut iwork = vec![0; 16];
    let mut info = 0;
    let (ld1, ld3, lw) = (1 as c_int, 3 as c_int, 200 as c_int);
    unsafe {
        dgesdd_(
            &ch(b'X'),
            &m,
            &n,
            a.as_mut_ptr(),
            &lda,
            s.as_mut_ptr(),
            u.as_mut_ptr(),
            &ld3,
            vt.as_mut_ptr(),
            &ld3,
            work.as_mut_ptr(),
            &lw,
            iwork.as_mut_ptr(),
            &mut info,
        );
        assert_eq!(info, -1);
        dgesdd_(
            &ch(b'A'),
            &m,
            &n,
            a.as_mut_ptr(),
            &lda,
            s.as_mut_ptr(),
            u.as_mut_ptr(),
            &ld1,
            vt.as_mut_ptr(),
            &ld3,
            work.as_mut_ptr(),
            &lw,
            iwork.as_mut_ptr(),
            &mut info,
        );
        assert_eq!(info, -8);
        dgesvd_(
            &ch(b'O'),
            &ch(b'O'),
            &m,
            &n,
            a.as_mut_ptr(),
            &lda,
            s.as_mut_ptr(),
            u.as_mut_ptr(),
            &ld3,
            vt.as_mut_ptr(),
            &ld3,
            work.as_mut_ptr(),
            &lw,
            &mut info,
        );
        assert_eq!(info, -2);
        dgesvd_(
            &ch(b'S'),
            &ch(b'A'),
            &m,
            &n,
            a.as_mut_ptr(),
            &lda,
            s.as_mut_ptr(),
            u.as_mut_ptr(),
            &ld3,
            vt.as_mut_ptr(),
            &ld1,
            work.as_mut_ptr(),
            &lw,
            &mut info,
        );
        assert_eq!(info, -11);
        dgesvd_(
            &ch(b'S'),
            &ch(b'S'),
            &m,
            &n,
            a.as_mut_ptr(),
            &lda,
            s.as_mut_ptr(),
            u.as_mut_ptr(),
            &ld3,
            vt.as_mut_ptr(),
            &ld3,
            work.as_mut_ptr(),
            &ld1,
            &mut info,
        );
        assert_eq!(info, -13);
    }
}
