//! The entropic divergence's second-order term at the prior, per body:
//! `d(J ‖ Ĵ) = ½ tr(Ĵ⁻¹ΔJ Ĵ⁻¹ΔJ) + O(ΔJ³)`, a quadratic form `Δπᵀ M Δπ`
//! in the ten parameters (`Δπ = π − π̂`, `J` linear in π). It is the
//! [`super::Regularizer::Pullback`] prior, and the entropic prior's
//! quadratic in the friction law's Gram solves (`identify::law_scores`).

use super::error::IdentifyError;
use crate::moments::InertialParams;
use nalgebra::{Matrix4, SMatrix};

/// Per body of `prior` (10 values each, `bodies` its names), `M = ½ H`
/// with `H_kl = tr(Ĵ⁻¹ J(e_k) Ĵ⁻¹ J(e_l))` (symmetric positive definite:
/// `J` is injective). A prior body not strictly consistent is an error
/// naming it.
pub(crate) fn metric(
    prior: &[f64],
    bodies: &[String],
) -> Result<Vec<SMatrix<f64, 10, 10>>, IdentifyError> {
    let basis: Vec<Matrix4<f64>> = (0..10)
        .map(|k| {
            let mut e = [0.0; 10];
            e[k] = 1.0;
            InertialParams(e).pseudo_inertia()
        })
        .collect();
    (prior.chunks(10).enumerate())
        .map(|(b, p)| {
            let j = InertialParams(p.try_into().expect("chunks of 10")).pseudo_inertia();
            let not_consistent = || IdentifyError::PriorNotConsistent {
                body: bodies.get(b).cloned().unwrap_or_default(),
                min_eig: j.symmetric_eigenvalues().min(),
            };
            let ji = j.cholesky().ok_or_else(not_consistent)?.inverse();
            let a: Vec<Matrix4<f64>> = basis.iter().map(|e| ji * e).collect();
            Ok(SMatrix::from_fn(|k, l| 0.5 * (a[k] * a[l]).trace()))
        })
        .collect()
}

/// Per body, `Lᵀ` with `M = L Lᵀ` ([`metric`]'s Cholesky factor): the
/// prior's term is `Σ_b ‖Lᵀ_b (π_b − π̂_b)‖²`, ten squares per body.
pub(crate) fn factors(
    prior: &[f64],
    bodies: &[String],
) -> Result<Vec<SMatrix<f64, 10, 10>>, IdentifyError> {
    (metric(prior, bodies)?.into_iter().enumerate())
        .map(|(b, m)| {
            m.cholesky().map(|c| c.l().transpose()).ok_or_else(|| {
                IdentifyError::PriorNotConsistent {
                    body: bodies.get(b).cloned().unwrap_or_default(),
                    min_eig: 0.0,
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moments::entropic_divergence;

    /// The quadratic is the divergence's second-order term: for a step `h Δπ`
    /// the divergence less the quadratic shrinks as h³ (halving h divides
    /// it by about 8); the factors rebuild M.
    #[test]
    fn the_quadratic_is_the_divergences_second_order_term() {
        // a box of 2 kg, half-sides 0.1, 0.05, 0.04 m, CoM at (0.1, 0, 0.05)
        let prior = crate::moments::InertialParams::from_mass_com_inertia(
            2.0,
            nalgebra::Vector3::new(0.1, 0.0, 0.05),
            nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(
                2.0 * (0.05f64.powi(2) + 0.04f64.powi(2)) / 3.0,
                2.0 * (0.1f64.powi(2) + 0.04f64.powi(2)) / 3.0,
                2.0 * (0.1f64.powi(2) + 0.05f64.powi(2)) / 3.0,
            )),
        );
        let m = metric(&prior.0, &["box".into()]).unwrap()[0];
        let dir = [0.1, 0.01, -0.02, 0.005, 1e-3, -2e-3, 5e-4, 1e-4, 0.0, -3e-4];
        let gap = |h: f64| {
            let d = nalgebra::SVector::<f64, 10>::from_fn(|k, _| h * dir[k]);
            let moved = InertialParams(std::array::from_fn(|k| prior.0[k] + d[k]));
            let exact = entropic_divergence(&moved, &prior).unwrap();
            (
                (exact - (d.transpose() * m * d)[0]).abs(),
                (d.transpose() * m * d)[0],
            )
        };
        let ((g1, q1), (g2, _)) = (gap(0.02), gap(0.01));
        assert!(q1 > 0.0);
        let ratio = g1 / g2;
        assert!((7.0..9.0).contains(&ratio), "third order: ratio {ratio}");
        let l = factors(&prior.0, &["box".into()]).unwrap()[0];
        assert!((l.transpose() * l - m).norm() < 1e-9 * m.norm());
    }
}
