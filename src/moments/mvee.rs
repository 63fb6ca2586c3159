//! The minimum-volume enclosing ellipsoid (MVEE) of a point cloud: the
//! points reduced to their convex hull's vertices, then Todd and Yildirim's
//! algorithm with away steps (Todd & Yildirim, "On Khachiyan's algorithm for
//! the computation of minimum-volume enclosing ellipsoids", Discrete Appl.
//! Math. 2007), which converges linearly where Khachiyan's first-order
//! iteration alone stalls.
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

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use nalgebra::{Matrix3, Matrix4, SymmetricEigen, Vector3, Vector4};

/// The most iterations of [`mvee`] (each O(n) on n hull vertices).
pub const MVEE_MAX_ITERATIONS: usize = 100_000;

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
    /// Points it was computed on (the convex hull's vertices, or every
    /// distinct point when the hull could not be built).
    pub support_candidates: usize,
}

impl Ellipsoid {
    /// The minimum-volume enclosing ellipsoid of a point cloud, to relative
    /// tolerance `tol` ([`mvee`]: on the convex hull's vertices,
    /// Todd–Yildirim with away steps; the result always encloses every
    /// point). Needs at least 4 affinely independent points.
    pub fn minimum_volume_enclosing(
        points: &[Vector3<f64>],
        tol: f64,
    ) -> Result<Self, MomentsError> {
        mvee(points, tol).map(|r| r.ellipsoid)
    }
}

/// The minimum-volume ellipsoid enclosing `points` to relative tolerance
/// `tol` (e.g. 1e-7), computed on their convex hull's vertices. Needs at
/// least 4 finite, affinely independent points.
pub fn mvee(points: &[Vector3<f64>], tol: f64) -> Result<Mvee, MomentsError> {
    let n = points.len();
    if n < 4 || points.iter().any(|p| !p.iter().all(|x| x.is_finite())) {
        return Err(MomentsError::InvalidEllipsoid(format!(
            "need at least 4 finite points, got {n}"
        )));
    }
    let pts = hull_vertices(points);
    check_volume(&pts)?;
    let q: Vec<Vector4<f64>> = pts.iter().map(|p| p.push(1.0)).collect();
    let mut u = initial_weights(&pts);
    let (iterations, converged) = iterate(&q, &mut u, tol)?;
    let ellipsoid = from_weights(&pts, &u, points)?;
    Ok(Mvee {
        ellipsoid,
        iterations,
        converged,
        support_candidates: pts.len(),
    })
}

/// The convex hull's vertices (chull's robust quickhull), or the points
/// themselves when no hull with volume can be built (then the iteration
/// reports the flatness).
fn hull_vertices(points: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    // centre and scale first: the hull's tolerances are absolute
    let c: Vector3<f64> = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
    let s = points.iter().map(|p| (p - c).amax()).fold(0.0, f64::max);
    if s <= 0.0 {
        return points.to_vec();
    }
    let scaled: Vec<Vec<f64>> = points
        .iter()
        .map(|p| ((p - c) / s).iter().copied().collect())
        .collect();
    match chull::ConvexHullWrapper::try_new(&scaled, None) {
        Ok(h) => {
            let (v, _) = h.vertices_indices();
            let v: Vec<Vector3<f64>> = v
                .iter()
                .map(|x| Vector3::new(x[0], x[1], x[2]) * s + c)
                .collect();
            if v.len() >= 4 { v } else { points.to_vec() }
        }
        Err(_) => points.to_vec(),
    }
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
fn iterate(q: &[Vector4<f64>], u: &mut [f64], tol: f64) -> Result<(usize, bool), MomentsError> {
    const D: f64 = 4.0;
    let flat = || {
        MomentsError::InvalidEllipsoid(
            "points are coplanar (no enclosing ellipsoid with volume)".into(),
        )
    };
    let mut m = vec![0.0; q.len()];
    for it in 0..MVEE_MAX_ITERATIONS {
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
    Ok((MVEE_MAX_ITERATIONS, false))
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

/// The ellipsoid of the weights: centre `Σ u p`, shape `(Σ u (p − c)(p − c)ᵀ)⁻¹ / 3`,
/// scaled so that every one of `all` is inside.
fn from_weights(
    pts: &[Vector3<f64>],
    u: &[f64],
    all: &[Vector3<f64>],
) -> Result<Ellipsoid, MomentsError> {
    let c: Vector3<f64> = pts.iter().zip(u).map(|(p, w)| p * *w).sum();
    let mut cov = Matrix3::zeros();
    for (p, w) in pts.iter().zip(u) {
        cov += (p - c) * (p - c).transpose() * *w;
    }
    let a = cov
        .try_inverse()
        .ok_or_else(|| MomentsError::InvalidEllipsoid("points are coplanar".into()))?
        / 3.0;
    let worst = all
        .iter()
        .map(|p| (p - c).dot(&(a * (p - c))))
        .fold(0.0, f64::max);
    let a = a / worst.max(f64::MIN_POSITIVE);
    let eig = SymmetricEigen::new(a);
    let mut r = eig.eigenvectors;
    if r.determinant() < 0.0 {
        r.set_column(2, &(-r.column(2)));
    }
    Ellipsoid::with_rotation(c, eig.eigenvalues.map(|l| 1.0 / l.sqrt()), r)
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
        assert_eq!(
            r.support_candidates, 8,
            "the hull of a grid box is its corners"
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
