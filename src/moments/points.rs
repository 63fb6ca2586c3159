//! Four point masses with the same moments as π (Theorem 4's last claim).
//!
//! Construction (docs/math.md): factor `J = L Lᵀ`; for any orthogonal U,
//! `J = Σₖ (L uₖ)(L uₖ)ᵀ`, and a column `(a, b) = L uₖ` with b ≠ 0 is the
//! point mass `b²` at `a / b`. In an ellipsoid with matrix Q the point is
//! inside iff `uₖᵀ (LᵀQL) uₖ ≥ 0`; since `tr(LᵀQL) = tr(JQ) ≥ 0`, rotating
//! `M = LᵀQL` to constant diagonal `tr(JQ)/4` puts all four inside.

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use super::params::InertialParams;
use nalgebra::{Matrix4, SymmetricEigen, Vector3, Vector4};

/// A point mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMass {
    /// Mass (kg), ≥ 0.
    pub mass: f64,
    /// Position in the body frame (m).
    pub position: Vector3<f64>,
}

/// The pseudo-inertia of a set of point masses, `Σ mₖ [xₖ; 1][xₖ; 1]ᵀ`.
pub fn pseudo_inertia_of(points: &[PointMass]) -> Matrix4<f64> {
    points.iter().fold(Matrix4::zeros(), |acc, p| {
        let v = Vector4::new(p.position.x, p.position.y, p.position.z, 1.0);
        acc + v * v.transpose() * p.mass
    })
}

/// Eigenvalues of J down to `−FACTOR_TOL · λmax(J)` count as zero, and
/// `tr(JQ) ≥ −FACTOR_TOL · m` counts as inside (round-off
/// of a body on the boundary, e.g. an interior-point solver's output; the
/// points then sit within that relative slack of the ellipsoid).
pub const FACTOR_TOL: f64 = 1e-7;

/// A symmetric square root factor `L` with `J = L Lᵀ` for J ⪰ 0 (eigenvalues
/// below zero by round-off are clamped).
fn psd_factor(j: &Matrix4<f64>, tol: f64) -> Result<Matrix4<f64>, MomentsError> {
    let e = SymmetricEigen::new(*j);
    let lmax = e.eigenvalues.max().max(0.0);
    if e.eigenvalues.min() < -tol * lmax.max(f64::MIN_POSITIVE) || !(lmax > 0.0) {
        return Err(MomentsError::NotPositiveSemidefinite {
            min_eig: e.eigenvalues.min(),
        });
    }
    let d = e.eigenvalues.map(|l| l.max(0.0).sqrt());
    Ok(e.eigenvectors * Matrix4::from_diagonal(&d))
}

fn points_from(l: &Matrix4<f64>, u: &Matrix4<f64>) -> Result<[PointMass; 4], MomentsError> {
    let lu = l * u;
    let mut out = [PointMass {
        mass: 0.0,
        position: Vector3::zeros(),
    }; 4];
    for k in 0..4 {
        let c = lu.column(k);
        let b = c[3];
        let norm = c.norm();
        if b.abs() <= 1e-14 * norm {
            if norm <= 1e-300 {
                continue; // a zero column: a massless point
            }
            return Err(MomentsError::PointAtInfinity);
        }
        out[k] = PointMass {
            mass: b * b,
            position: Vector3::new(c[0] / b, c[1] / b, c[2] / b),
        };
    }
    Ok(out)
}

/// Householder reflection mapping unit vector `a` to `e₁` (symmetric, orthogonal).
fn reflect_to_e1(a: &Vector4<f64>) -> Matrix4<f64> {
    let mut v = *a;
    v[0] -= 1.0;
    let n2 = v.norm_squared();
    if n2 < 1e-30 {
        return Matrix4::identity();
    }
    Matrix4::identity() - v * v.transpose() * (2.0 / n2)
}

/// Four point masses anywhere in space reproducing `J(π)` (needs J ⪰ 0, m > 0).
pub fn four_point_masses(pi: &InertialParams) -> Result<[PointMass; 4], MomentsError> {
    if !pi.is_finite() {
        return Err(MomentsError::NonFinite("four-point recovery".into()));
    }
    let j = pi.pseudo_inertia();
    let l = psd_factor(&j, FACTOR_TOL)?;
    // b = Lᵀ e₄; choose U with bᵀuₖ = ‖b‖/2 for every k (rotated Hadamard).
    let b: Vector4<f64> = l.row(3).transpose();
    let nb = b.norm();
    if nb == 0.0 {
        return Err(MomentsError::ZeroMass);
    }
    let h = Matrix4::new(
        1.0, 1.0, 1.0, 1.0, 1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, -1.0, -1.0, 1.0,
    ) * 0.5;
    let r = reflect_to_e1(&(b / nb));
    points_from(&l, &(r * h))
}

/// Rotates the symmetric M by Givens rotations so that its diagonal is
/// constant (= tr M / n); returns the accumulated orthogonal U (M ← UᵀMU).
fn equalize_diagonal(m: &Matrix4<f64>) -> Matrix4<f64> {
    let mut m = *m;
    let mut u = Matrix4::<f64>::identity();
    let target = m.trace() / 4.0;
    for _ in 0..4 {
        // pick i above target and j below
        let d: Vec<f64> = (0..4).map(|k| m[(k, k)] - target).collect();
        let i = (0..4).max_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap_or(0);
        let j = (0..4).min_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap_or(0);
        if d[i] - d[j] <= 1e-15 * (1.0 + target.abs()) {
            break;
        }
        // rotation in (i, j) with angle θ: new m_ii = c²m_ii + 2cs m_ij + s²m_jj = target
        let (a, bb, c0) = (m[(i, i)], m[(j, j)], m[(i, j)]);
        // solve (a − bb)/2 cos2θ + c0 sin2θ + (a + bb)/2 = target
        let p = 0.5 * (a - bb);
        let q = c0;
        let rhs = target - 0.5 * (a + bb);
        let rho = (p * p + q * q).sqrt();
        let phi = q.atan2(p);
        let theta = 0.5 * ((rhs / rho).clamp(-1.0, 1.0).acos() + phi);
        let (s, c) = theta.sin_cos();
        let mut g = Matrix4::<f64>::identity();
        g[(i, i)] = c;
        g[(j, j)] = c;
        g[(j, i)] = s;
        g[(i, j)] = -s;
        m = g.transpose() * m * g;
        u *= g;
    }
    u
}

/// Four point masses inside the ellipsoid S reproducing `J(π)`; needs π
/// density realizable in S (J ⪰ 0, tr(JQ) ≥ 0).
pub fn four_point_masses_in(
    pi: &InertialParams,
    s: &Ellipsoid,
) -> Result<[PointMass; 4], MomentsError> {
    if !pi.is_finite() {
        return Err(MomentsError::NonFinite("four-point recovery".into()));
    }
    let j = pi.pseudo_inertia();
    let q = s.q_matrix();
    let tr = (j * q).trace();
    if tr < -FACTOR_TOL * pi.mass().abs() {
        return Err(MomentsError::OutsideEllipsoid { trace_jq: tr });
    }
    let l = psd_factor(&j, FACTOR_TOL)?;
    let m = l.transpose() * q * l;
    let u = equalize_diagonal(&m);
    points_from(&l, &u)
}
