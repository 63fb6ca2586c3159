//! The minimum-volume enclosing ellipsoid (MVEE) of a point cloud: Todd
//! and Yildirim's algorithm with away steps (Todd & Yildirim, "On
//! Khachiyan's algorithm for the computation of minimum-volume enclosing
//! ellipsoids", Discrete Appl. Math. 2007), which converges linearly where
//! Khachiyan's first-order iteration alone stalls, on a working set of the
//! cloud's extreme points, then polished exactly.
//!
//! Lifted to ℝ⁴ (`q = (p, 1)`), the dual is: find weights `u ≥ 0`,
//! `Σu = 1`, maximising `log det X(u)` with `X(u) = Σ u_k q_k q_kᵀ`. With
//! `m_k = q_kᵀ X⁻¹ q_k`, `u` is optimal iff `m_k ≤ 4` for every point and
//! `m_k = 4` wherever `u_k > 0`. Each iteration moves weight toward the
//! point of largest `m` (a Frank–Wolfe step) or away from the supporting
//! point of smallest `m` (an away step, which can drop it from the support),
//! whichever is further from optimal. It stops when every `m_k ≤ 4(1 + tol)`
//! and every supporting `m_k ≥ 4(1 − tol)`: the ellipsoid then has at most
//! `(1 + tol)²` times the minimum volume (Todd & Yildirim, Lemma 2.3),
//! before the final scaling that puts every point inside.
//!
//! The iteration runs on the points extreme along [`EXTREME_DIRECTIONS`]
//! directions (vertices of the convex hull, found in O(n) each), and only
//! to a coarse tolerance ([`POLISH_BELOW`]): points nearly all on the
//! ellipsoid (a finely tessellated rounded part) slow it down to thousands
//! of steps per digit. The MVEE is then solved exactly on the coarse
//! support — a small SDP through [`conic`](crate::conic): maximise
//! `log det A` subject to `‖A p + b‖ ≤ 1` — and the points of the whole
//! cloud it leaves outside are added, the worst first, until it contains
//! them all; it is then the MVEE of the whole cloud. Should the polish
//! fail, the iteration runs on every point to the tolerance asked.

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use crate::conic::{AffExpr, Problem, Settings};
use nalgebra::{Matrix3, Matrix4, SymmetricEigen, Vector3, Vector4};

/// The most iterations of [`mvee`] (each O(n) on its n working points).
pub const MVEE_MAX_ITERATIONS: usize = 100_000;

/// The tolerance the first-order iteration runs to when a finer one is
/// asked for; the exact polish does the rest.
pub const POLISH_BELOW: f64 = 1e-3;

/// Directions (over a sphere, in the cloud's whitened frame) whose extreme
/// points, both ways, form the iteration's working set.
pub const EXTREME_DIRECTIONS: usize = 200;

/// The result of [`mvee`]: the ellipsoid (which always contains every
/// point) and how close to minimal it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mvee {
    /// The enclosing ellipsoid.
    pub ellipsoid: Ellipsoid,
    /// Iterations used.
    pub iterations: usize,
    /// Whether the optimality test held to `tol` (else the iteration cap
    /// stopped it: the ellipsoid encloses the points but may be larger than
    /// minimal by more than `(1 + tol)²` in volume).
    pub converged: bool,
    /// Whether the exact conic polish ran (it finds the support, on which
    /// the first-order iteration then refines the ellipsoid); else the
    /// first-order iteration alone gave it.
    pub polished: bool,
    /// Points the iteration ran on (the extreme points, or every point
    /// when the polish failed).
    pub support_candidates: usize,
}

impl Ellipsoid {
    /// The minimum-volume enclosing ellipsoid of a point cloud, to relative
    /// tolerance `tol` ([`mvee`]: Todd–Yildirim with away steps on the
    /// extreme points, polished exactly; the result always encloses every
    /// point). Needs at least 4 affinely independent points.
    pub fn minimum_volume_enclosing(
        points: &[Vector3<f64>],
        tol: f64,
    ) -> Result<Self, MomentsError> {
        mvee(points, tol).map(|r| r.ellipsoid)
    }
}

/// The minimum-volume ellipsoid enclosing `points` to relative tolerance
/// `tol` (e.g. 1e-7; below [`POLISH_BELOW`] the exact polish gives it to
/// the solver's accuracy). Needs at least 4 finite, affinely independent
/// points.
pub fn mvee(points: &[Vector3<f64>], tol: f64) -> Result<Mvee, MomentsError> {
    let n = points.len();
    if n < 4 || points.iter().any(|p| !p.iter().all(|x| x.is_finite())) {
        return Err(MomentsError::InvalidEllipsoid(format!(
            "need at least 4 finite points, got {n}"
        )));
    }
    check_volume(points)?;
    let work: Vec<Vector3<f64>> = extreme_points(points).iter().map(|&k| points[k]).collect();
    let coarse = tol.max(POLISH_BELOW);
    let (u, iterations, converged) = weights(&work, coarse, MVEE_MAX_ITERATIONS)?;
    if coarse > tol && converged {
        if let Ok(p) = polish(&work, &u, points) {
            return refined(p, points, tol, iterations);
        }
    }
    let (u, iterations, converged, pts) = if coarse > tol || !converged {
        let (u, i, c) = weights(points, tol, MVEE_MAX_ITERATIONS)?;
        (u, iterations + i, c, points)
    } else {
        (u, iterations, converged, &work[..])
    };
    let (centre, shape) = from_weights(pts, &u)?;
    Ok(Mvee {
        ellipsoid: enclosing_all(centre, shape, points)?,
        iterations,
        converged,
        polished: false,
        support_candidates: pts.len(),
    })
}

/// The polished MVEE, refined: the first-order iteration on the polish's
/// support alone (at most [`REFINE_ITERATIONS`], to [`REFINE_TOL`] or
/// `tol` if finer) reaches where the
/// interior-point solve stops short (its volume is flat at the optimum, so
/// a gap ε in `log det` leaves the shape off by ~√ε); the smaller of the
/// two ellipsoids, each scaled to enclose every point, is the result.
fn refined(
    p: Polished,
    points: &[Vector3<f64>],
    tol: f64,
    iterations: usize,
) -> Result<Mvee, MomentsError> {
    let exact = enclosing_all(p.centre, p.shape, points)?;
    let (u, more, _) = weights(&p.support, tol.min(REFINE_TOL), REFINE_ITERATIONS)?;
    let (c, a) = from_weights(&p.support, &u)?;
    let first_order = enclosing_all(c, a, points)?;
    Ok(Mvee {
        ellipsoid: if first_order.volume() < exact.volume() {
            first_order
        } else {
            exact
        },
        iterations: iterations + more,
        converged: true,
        polished: true,
        support_candidates: p.support.len(),
    })
}

/// Todd–Yildirim weights on `pts` to tolerance `tol` (at most
/// `max_iterations`), from the Kumar–Yildirim start; with the iterations and whether they converged.
fn weights(
    pts: &[Vector3<f64>],
    tol: f64,
    max_iterations: usize,
) -> Result<(Vec<f64>, usize, bool), MomentsError> {
    let q: Vec<Vector4<f64>> = pts.iter().map(|p| p.push(1.0)).collect();
    let mut u = initial_weights(pts);
    let (iterations, converged) = iterate(&q, &mut u, tol, max_iterations)?;
    Ok((u, iterations, converged))
}

/// The indices of the points extreme (largest and smallest) along
/// [`EXTREME_DIRECTIONS`] directions spread over the sphere in the cloud's
/// whitened frame (where it is round): vertices of its convex hull, and
/// the ones an ellipsoid touches first.
fn extreme_points(points: &[Vector3<f64>]) -> Vec<usize> {
    let n = points.len() as f64;
    let c: Vector3<f64> = points.iter().sum::<Vector3<f64>>() / n;
    let cov: Matrix3<f64> = points
        .iter()
        .map(|p| (p - c) * (p - c).transpose())
        .sum::<Matrix3<f64>>()
        / n;
    let eig = SymmetricEigen::new(cov);
    // a direction d of the whitened frame is Σ^{-1/2} d here
    let w = eig.eigenvectors * Matrix3::from_diagonal(&eig.eigenvalues.map(|l| 1.0 / l.sqrt()));
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut pick = vec![];
    for k in 0..EXTREME_DIRECTIONS {
        let z = 1.0 - 2.0 * (k as f64 + 0.5) / EXTREME_DIRECTIONS as f64;
        let r = (1.0 - z * z).sqrt();
        let a = golden * k as f64;
        let d = w * Vector3::new(r * a.cos(), r * a.sin(), z);
        let (mut lo, mut hi) = ((f64::INFINITY, 0), (f64::NEG_INFINITY, 0));
        for (i, p) in points.iter().enumerate() {
            let x = d.dot(p);
            if x < lo.0 {
                lo = (x, i);
            }
            if x > hi.0 {
                hi = (x, i);
            }
        }
        pick.extend([lo.1, hi.1]);
    }
    pick.sort_unstable();
    pick.dedup();
    pick
}

/// Points that span a volume: the spread along the thinnest principal axis
/// is at least 1e-9 of the widest's (else they lie in a plane or on a line).
fn check_volume(pts: &[Vector3<f64>]) -> Result<(), MomentsError> {
    let c: Vector3<f64> = pts.iter().sum::<Vector3<f64>>() / pts.len() as f64;
    let cov: Matrix3<f64> = pts.iter().map(|p| (p - c) * (p - c).transpose()).sum();
    let e = SymmetricEigen::new(cov).eigenvalues;
    if e.min() > 1e-18 * e.max() && e.max() > 0.0 {
        Ok(())
    } else {
        Err(MomentsError::InvalidEllipsoid(
            "points are coplanar (no enclosing ellipsoid with volume)".into(),
        ))
    }
}

/// Kumar–Yildirim start: equal weight on the extreme points along the
/// principal axes of the cloud (at most 6), which spans the cloud from the
/// first iteration; every point equally when they are not independent.
fn initial_weights(pts: &[Vector3<f64>]) -> Vec<f64> {
    let n = pts.len();
    let c: Vector3<f64> = pts.iter().sum::<Vector3<f64>>() / n as f64;
    let cov: Matrix3<f64> = pts.iter().map(|p| (p - c) * (p - c).transpose()).sum();
    let axes = SymmetricEigen::new(cov).eigenvectors;
    let mut pick = vec![];
    for a in axes.column_iter() {
        let key = |k: &usize| (pts[*k] - c).dot(&a);
        let (lo, hi) = (0..n).fold((0, 0), |(lo, hi), k| {
            (
                if key(&k) < key(&lo) { k } else { lo },
                if key(&k) > key(&hi) { k } else { hi },
            )
        });
        pick.extend([lo, hi]);
    }
    pick.sort_unstable();
    pick.dedup();
    let mut u = vec![0.0; n];
    let x: Matrix4<f64> = pick
        .iter()
        .map(|&k| pts[k].push(1.0) * pts[k].push(1.0).transpose())
        .sum();
    if pick.len() >= 4
        && x.try_inverse()
            .is_some_and(|xi| xi.iter().all(|v| v.is_finite()))
    {
        pick.iter().for_each(|&k| u[k] = 1.0 / pick.len() as f64);
    } else {
        u.iter_mut().for_each(|w| *w = 1.0 / n as f64);
    }
    u
}

/// Todd–Yildirim iterations on the weights `u`; returns the iteration count
/// and whether the optimality test held.
fn iterate(
    q: &[Vector4<f64>],
    u: &mut [f64],
    tol: f64,
    max_iterations: usize,
) -> Result<(usize, bool), MomentsError> {
    const D: f64 = 4.0;
    let flat = || {
        MomentsError::InvalidEllipsoid(
            "points are coplanar (no enclosing ellipsoid with volume)".into(),
        )
    };
    let mut m = vec![0.0; q.len()];
    for it in 0..max_iterations {
        let x: Matrix4<f64> = q
            .iter()
            .zip(u.iter())
            .filter(|(_, w)| **w > 0.0)
            .map(|(v, w)| v * v.transpose() * *w)
            .sum();
        let xi = x.try_inverse().ok_or_else(flat)?;
        m.iter_mut()
            .zip(q)
            .for_each(|(mk, v)| *mk = v.dot(&(xi * v)));
        let (up, m_up) = extreme(&m, |_| true, |a, b| a > b);
        let (down, m_down) = extreme(&m, |k| u[k] > 0.0, |a, b| a < b);
        let (e_up, e_down) = (m_up / D - 1.0, 1.0 - m_down / D);
        if e_up <= tol && e_down <= tol {
            return Ok((it, true));
        }
        if e_up > e_down {
            let step = (m_up - D) / (D * (m_up - 1.0));
            u.iter_mut().for_each(|w| *w *= 1.0 - step);
            u[up] += step;
        } else {
            let cap = u[down] / (1.0 - u[down]);
            let step = ((D - m_down) / (D * (m_down - 1.0))).min(cap);
            u.iter_mut().for_each(|w| *w *= 1.0 + step);
            u[down] = if step == cap { 0.0 } else { u[down] - step };
        }
    }
    Ok((max_iterations, false))
}

/// The index and value of the extreme `m_k` over the `k` that `keep`
/// accepts, by `better`.
fn extreme(
    m: &[f64],
    keep: impl Fn(usize) -> bool,
    better: impl Fn(f64, f64) -> bool,
) -> (usize, f64) {
    let mut best = (usize::MAX, f64::NAN);
    for (k, &v) in m.iter().enumerate() {
        if keep(k) && (best.0 == usize::MAX || better(v, best.1)) {
            best = (k, v);
        }
    }
    best
}

/// The ellipsoid of the weights: centre `Σ u p` and shape
/// `(Σ u (p − c)(p − c)ᵀ)⁻¹ / 3` (`(x − c)ᵀ A (x − c) ≤ 1`).
fn from_weights(
    pts: &[Vector3<f64>],
    u: &[f64],
) -> Result<(Vector3<f64>, Matrix3<f64>), MomentsError> {
    let c: Vector3<f64> = pts.iter().zip(u).map(|(p, w)| p * *w).sum();
    let mut cov = Matrix3::zeros();
    for (p, w) in pts.iter().zip(u) {
        cov += (p - c) * (p - c).transpose() * *w;
    }
    let a = cov
        .try_inverse()
        .ok_or_else(|| MomentsError::InvalidEllipsoid("points are coplanar".into()))?
        / 3.0;
    Ok((c, a))
}

/// The ellipsoid `(x − c)ᵀ A (x − c) ≤ 1`, scaled about `c` so that every
/// one of `all` is inside.
fn enclosing_all(
    c: Vector3<f64>,
    a: Matrix3<f64>,
    all: &[Vector3<f64>],
) -> Result<Ellipsoid, MomentsError> {
    let worst = all
        .iter()
        .map(|p| (p - c).dot(&(a * (p - c))))
        .fold(0.0, f64::max);
    Ellipsoid::from_shape(c, &(a / worst.max(f64::MIN_POSITIVE)))
}

/// The most rounds of the polish (each adds the points left outside).
const POLISH_ROUNDS: usize = 40;

/// The most iterations of the refinement on the polish's support.
pub const REFINE_ITERATIONS: usize = 5_000;

/// The tolerance of the refinement (a few points: cheap to reach; the
/// semi-axes are off by ~√tol at a tolerance tol in volume).
pub const REFINE_TOL: f64 = 1e-12;

/// What the polish found: the MVEE's centre and shape (as
/// [`from_weights`] gives them) and the points on its boundary.
struct Polished {
    centre: Vector3<f64>,
    shape: Matrix3<f64>,
    support: Vec<Vector3<f64>>,
}

/// The most points the polish adds in one round (the worst outside).
const POLISH_ADD: usize = 24;

/// The exact MVEE of `all` from the coarse weights `u` on `work`: solved
/// on the coarse support, in coordinates centred and scaled to unit size,
/// with the points of `all` left outside added (the [`POLISH_ADD`] worst
/// each round) until none is.
fn polish(
    work: &[Vector3<f64>],
    u: &[f64],
    all: &[Vector3<f64>],
) -> Result<Polished, MomentsError> {
    let c: Vector3<f64> = all.iter().sum::<Vector3<f64>>() / all.len() as f64;
    let s = all.iter().map(|p| (p - c).amax()).fold(0.0, f64::max);
    let mut cand: Vec<Vector3<f64>> = work
        .iter()
        .zip(u)
        .filter(|(_, w)| **w > 0.0)
        .map(|(p, _)| (p - c) / s)
        .collect();
    for _ in 0..POLISH_ROUNDS {
        let (a, b) = conic_mvee(&cand)?;
        let mut out: Vec<(f64, Vector3<f64>)> = all
            .iter()
            .map(|p| (p - c) / s)
            .map(|x| ((a * x + b).norm(), x))
            .filter(|(l, _)| *l > 1.0 + 1e-7)
            .collect();
        if out.is_empty() {
            let ai = a
                .try_inverse()
                .ok_or_else(|| MomentsError::InvalidEllipsoid("a flat MVEE".into()))?;
            let support = all
                .iter()
                .filter(|p| (a * ((*p - c) / s) + b).norm() > 1.0 - 1e-4)
                .copied()
                .collect();
            // ‖A (x − c)/s + b‖ ≤ 1: centre c − s A⁻¹ b, shape A²/s²
            return Ok(Polished {
                centre: c - s * (ai * b),
                shape: a * a / (s * s),
                support,
            });
        }
        out.sort_by(|x, y| y.0.total_cmp(&x.0));
        cand.extend(out.iter().take(POLISH_ADD).map(|(_, x)| *x));
    }
    Err(MomentsError::InvalidEllipsoid(
        "the MVEE polish did not settle".into(),
    ))
}

/// The MVEE `{x : ‖A x + b‖ ≤ 1}` of `pts` as one SDP: maximise
/// `log det A` over symmetric A, subject to every point inside.
fn conic_mvee(pts: &[Vector3<f64>]) -> Result<(Matrix3<f64>, Vector3<f64>), MomentsError> {
    let mut p = Problem::new();
    let a = p.symmetric("A", 3);
    let b = p.vector("b", 3);
    let t = p.scalar("log det A");
    p.add_logdet_ge(&a, t)?;
    let ae = a.expr();
    for x in pts {
        let rows: Vec<AffExpr> = (0..3)
            .map(|i| (0..3).map(|j| ae[(i, j)].clone() * x[j]).sum::<AffExpr>() + b[i])
            .collect();
        p.add_soc(1.0, rows)?;
    }
    p.maximize(t);
    let sol = p.solve(&Settings::default())?;
    if !sol.status.is_solved() {
        return Err(MomentsError::Solver {
            status: sol.status,
            task: "the minimum-volume ellipsoid of a mesh".into(),
        });
    }
    let am = Matrix3::from_fn(|i, j| ae[(i, j)].eval(sol.x()));
    let bv = Vector3::from_fn(|i, _| sol.value(b[i]).unwrap_or(f64::NAN));
    Ok((am, bv))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box's MVEE is the box's bounding ellipsoid √3·(half-sides), a
    /// closed form; Khachiyan's plain iteration stalls short of it on the
    /// mesh-like clouds below.
    #[test]
    fn a_box_gives_the_closed_form_ellipsoid() {
        let h = Vector3::new(0.3, 0.1, 0.05);
        let mut pts = vec![];
        for i in 0..=10 {
            for j in 0..=10 {
                for k in 0..=10 {
                    let f = |n: i32| 2.0 * n as f64 / 10.0 - 1.0;
                    pts.push(h.component_mul(&Vector3::new(f(i), f(j), f(k))));
                }
            }
        }
        let r = mvee(&pts, 1e-9).unwrap();
        assert!(r.converged);
        assert!(r.polished);
        assert_eq!(
            r.support_candidates, 8,
            "the extreme points of a grid box are its corners"
        );
        let mut a: Vec<f64> = r.ellipsoid.semi_axes.iter().copied().collect();
        a.sort_by(f64::total_cmp);
        let mut want = [0.05, 0.1, 0.3].map(|x| x * 3f64.sqrt());
        want.sort_by(f64::total_cmp);
        for (x, y) in a.iter().zip(want) {
            assert!((x - y).abs() < 1e-6 * y, "{a:?} vs {want:?}");
        }
        assert!(r.ellipsoid.center.norm() < 1e-9);
    }

    #[test]
    fn a_sphere_cloud_converges_and_encloses_everything() {
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let pts: Vec<Vector3<f64>> = (0..2000)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / 2000.0;
                let r = (1.0 - z * z).sqrt();
                let a = golden * k as f64;
                Vector3::new(0.2 * r * a.cos() + 1.0, 0.5 * r * a.sin(), 0.1 * z)
            })
            .collect();
        let r = mvee(&pts, 1e-7).unwrap();
        assert!(r.converged, "{} iterations", r.iterations);
        for p in &pts {
            assert!(r.ellipsoid.level(p) >= -1e-12);
        }
        // the cloud samples the ellipsoid (1, 0, 0) + diag(0.2, 0.5, 0.1)
        let v = r.ellipsoid.semi_axes.product();
        assert!((v / (0.2 * 0.5 * 0.1) - 1.0).abs() < 1e-3, "{v}");
    }

    #[test]
    fn coplanar_points_are_an_error_not_a_flat_ellipsoid() {
        let pts: Vec<Vector3<f64>> = (0..20)
            .map(|k| Vector3::new((k % 5) as f64, (k / 5) as f64, 0.0))
            .collect();
        assert!(mvee(&pts, 1e-7).is_err());
    }
}
