//! The entropic (log-det Bregman) divergence between two bodies' moments,
//!
//! ```text
//! d(J ‖ Ĵ) = −log det(Ĵ⁻¹ J) + tr(Ĵ⁻¹ J) − 4 ,
//! ```
//!
//! the Bregman divergence of `−log det` on pseudo-inertias (Lee, Wensing &
//! Park, "Geometric Robot Dynamic Identification: A Convex Programming
//! Approach", IEEE T-RO 2020). It is dimensionless, invariant under a change
//! of body frame (`J ↦ T J Tᵀ` for any rigid or affine T acts on both) and
//! of units, zero only at `J = Ĵ`, convex in J, and infinite on the boundary
//! of consistency: a regulariser built on it keeps `J ≻ 0` by itself.
//!
//! [`entropic_divergence`] evaluates it and [`entropic_gradient`] its
//! gradient in π; [`add_entropic_divergence`] writes it into a
//! [`conic`](crate::conic) problem as an affine upper bound that is tight
//! when minimised.
//!
//! ```
//! use momentlmi::moments::{InertialParams, entropic_divergence};
//! use nalgebra::{Matrix3, Vector3};
//! let a = InertialParams::from_mass_com_inertia(2.0, Vector3::zeros(), Matrix3::identity() * 0.01);
//! let b = InertialParams::from_mass_com_inertia(2.2, Vector3::zeros(), Matrix3::identity() * 0.01);
//! assert!(entropic_divergence(&a, &a)? < 1e-12);
//! assert!(entropic_divergence(&b, &a)? > 0.0);
//! # Ok::<(), momentlmi::moments::MomentsError>(())
//! ```

use super::error::MomentsError;
use super::lmi::BodyVars;
use super::params::InertialParams;
use crate::conic::{AffExpr, LogDet, MatExpr, Problem};
use nalgebra::{DMatrix, Matrix4};

/// The Cholesky factor L of a pseudo-inertia (`J = L Lᵀ`), or the error
/// naming its smallest eigenvalue when J is not positive definite.
fn cholesky(j: &Matrix4<f64>) -> Result<Matrix4<f64>, MomentsError> {
    let bad = || MomentsError::NotPositiveSemidefinite {
        min_eig: j.symmetric_eigenvalues().min(),
    };
    if !j.iter().all(|x| x.is_finite()) {
        return Err(MomentsError::NonFinite("a pseudo-inertia".into()));
    }
    let l = j.cholesky().ok_or_else(bad)?.unpack();
    // a factor with a vanishing pivot is a singular J: d is infinite there
    if (0..4).any(|k| !(l[(k, k)] > 0.0)) {
        return Err(bad());
    }
    Ok(l)
}

/// `(L, L⁻¹)` with `J = L Lᵀ`, as [`cholesky`].
fn factor_and_inverse(j: &Matrix4<f64>) -> Result<(Matrix4<f64>, Matrix4<f64>), MomentsError> {
    let l = cholesky(j)?;
    // a triangular factor with positive pivots is invertible
    let li = l
        .try_inverse()
        .ok_or_else(|| MomentsError::NotPositiveSemidefinite {
            min_eig: j.symmetric_eigenvalues().min(),
        })?;
    Ok((l, li))
}

/// `d(J ‖ Ĵ)` for `J = J(pi)`, `Ĵ = J(prior)`; both must be positive
/// definite (else [`MomentsError::NotPositiveSemidefinite`]).
/// Dimensionless, ≥ 0, zero only at `pi = prior`.
pub fn entropic_divergence(
    pi: &InertialParams,
    prior: &InertialParams,
) -> Result<f64, MomentsError> {
    let x = whitened(pi, prior)?;
    // through X's Cholesky factor: log det X = 2 Σ ln Lᵢᵢ
    let lx = cholesky(&x)?;
    let logdet: f64 = 2.0 * (0..4).map(|k| lx[(k, k)].ln()).sum::<f64>();
    Ok((-logdet + x.trace() - 4.0).max(0.0))
}

/// `X = L̂⁻¹ J L̂⁻ᵀ` with `Ĵ = L̂ L̂ᵀ`: the body's pseudo-inertia in the
/// prior's coordinates, `I` at the prior (`det X = det(Ĵ⁻¹J)`,
/// `tr X = tr(Ĵ⁻¹J)`).
fn whitened(pi: &InertialParams, prior: &InertialParams) -> Result<Matrix4<f64>, MomentsError> {
    let (_, li) = factor_and_inverse(&prior.pseudo_inertia())?;
    let x = li * pi.pseudo_inertia() * li.transpose();
    Ok(0.5 * (x + x.transpose()))
}

/// The gradient of [`entropic_divergence`] in π (the paper's order): with
/// `∂d/∂J = Ĵ⁻¹ − J⁻¹`, entry k is `⟨Ĵ⁻¹ − J⁻¹, J(eₖ)⟩` (J is linear in π).
/// Units: 1 / the unit of each πₖ (1/kg, 1/(kg·m), 1/(kg·m²)).
pub fn entropic_gradient(
    pi: &InertialParams,
    prior: &InertialParams,
) -> Result<[f64; 10], MomentsError> {
    let inv = |p: &InertialParams| -> Result<Matrix4<f64>, MomentsError> {
        let (_, li) = factor_and_inverse(&p.pseudo_inertia())?;
        Ok(li.transpose() * li)
    };
    let g = inv(prior)? - inv(pi)?;
    Ok(std::array::from_fn(|k| {
        let mut e = [0.0; 10];
        e[k] = 1.0;
        g.component_mul(&InertialParams(e).pseudo_inertia()).sum()
    }))
}

/// The terms [`add_entropic_divergence`] added.
#[derive(Clone, Debug)]
pub struct EntropicTerm {
    /// An affine expression `D ≥ d(J ‖ Ĵ)` at every feasible point, equal
    /// to it when D is minimised (its `log det` bound is then tight).
    pub divergence: AffExpr,
    /// The `t ≤ log det X` constraints behind it.
    pub logdet: LogDet,
}

/// Adds `t ≤ log det(L̂⁻¹ J(π) L̂⁻ᵀ)` to `p` for the body's π and returns
/// `D = −t + tr(L̂⁻¹ J L̂⁻ᵀ) − 4 ≥ d(J ‖ Ĵ)`; minimising `γ D` (γ > 0) adds
/// the entropic regulariser toward `prior`, and keeps `J ≻ 0`. Whitening by
/// the prior's factor L̂ makes the `log det` block `I` at the prior, so its
/// conditioning does not depend on the body's units or size. The prior
/// must be strictly consistent ([`MomentsError::NotPositiveSemidefinite`]
/// otherwise).
pub fn add_entropic_divergence(
    p: &mut Problem,
    body: &BodyVars,
    prior: &InertialParams,
) -> Result<EntropicTerm, MomentsError> {
    let (_, li) = factor_and_inverse(&prior.pseudo_inertia())?;
    let li = DMatrix::from_fn(4, 4, |i, j| li[(i, j)]);
    let x: MatExpr = body.pseudo_inertia().congruence(&li)?;
    // symmetrise the congruence's round-off
    let x = MatExpr::from_fn(4, 4, |i, j| (x[(i, j)].clone() + &x[(j, i)]) * 0.5);
    let t = p.scalar("entropic.t");
    let logdet = p.add_logdet_ge(&x, t)?;
    Ok(EntropicTerm {
        divergence: x.trace() - AffExpr::from(t) - 4.0,
        logdet,
    })
}
