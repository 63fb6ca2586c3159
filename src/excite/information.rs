//! The information a motion gives about the base parameters: with `Y_b`
//! the regressor's base columns ([`crate::identify::Identifiability`] of
//! the regressor on random states: the structural base) each scaled to unit
//! RMS over those states, `F = Y_bᵀ Y_b / rows` (per sample, so that motions
//! of any length compare).

use super::design::Criterion;
use super::error::ExciteError;
use crate::dynamics::{FrictionTerm, Model, regressor_batch};
use crate::identify::identifiability::on_random_states;
use faer::Mat;

/// The base columns of a model's regressor and their scales.
#[derive(Clone, Debug)]
pub struct InfoBasis {
    /// The model the regressor is taken of (a load friction term dropped:
    /// it needs torques).
    pub model: Model,
    /// The base columns (indices into θ).
    pub base: Vec<usize>,
    /// Each base column's RMS on the random states.
    pub scale: Vec<f64>,
}

impl InfoBasis {
    /// The structural base of `model`: the identifiability of its
    /// regressor on 400 random states (positions within the limits or ±1,
    /// velocities and accelerations ±2).
    pub fn of(model: &Model) -> Result<Self, ExciteError> {
        let terms: Vec<FrictionTerm> = (model.friction_terms().iter())
            .copied()
            .filter(|t| *t != FrictionTerm::Load)
            .collect();
        let model = model.clone().with_friction_terms(&terms);
        let (id, rms) = on_random_states(&model)?;
        let scale = id.base_columns.iter().map(|&j| rms[j]).collect();
        Ok(Self {
            model,
            base: id.base_columns,
            scale,
        })
    }

    /// Number of base parameters.
    pub fn len(&self) -> usize {
        self.base.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.base.is_empty()
    }

    /// `F` of the states (flat q, q̇, q̈, n per sample).
    pub fn information(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<Mat<f64>, ExciteError> {
        let y = regressor_batch(&self.model, q, qd, qdd)?;
        let p = self.model.regressor_columns();
        let rows = (y.len() / p).max(1);
        let k = self.base.len();
        let yb = Mat::from_fn(rows, k, |i, j| y[i * p + self.base[j]] / self.scale[j]);
        Ok(Mat::from_fn(k, k, |a, b| {
            (0..rows).map(|i| yb[(i, a)] * yb[(i, b)]).sum::<f64>() / rows as f64
        }))
    }
}

/// The criterion's value of `f` (larger is better): `log det F` (D; −∞
/// when singular), `λ_min` (E), `−log₁₀ cond F` (cond).
pub fn score(f: &Mat<f64>, criterion: Criterion) -> f64 {
    let Ok(ev) = f.self_adjoint_eigenvalues(faer::Side::Lower) else {
        return f64::NEG_INFINITY;
    };
    let (lo, hi) = ev
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    match criterion {
        Criterion::D if lo > 0.0 => ev.iter().map(|v| v.ln()).sum(),
        Criterion::E => lo,
        Criterion::Cond if lo > 0.0 => -(hi / lo).log10(),
        _ => f64::NEG_INFINITY,
    }
}

/// The condition number of `f`'s square root (that of the scaled base
/// regressor); ∞ when singular.
pub fn condition_number(f: &Mat<f64>) -> f64 {
    let Ok(ev) = f.self_adjoint_eigenvalues(faer::Side::Lower) else {
        return f64::INFINITY;
    };
    let (lo, hi) = ev
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    if lo > 0.0 {
        (hi / lo).sqrt()
    } else {
        f64::INFINITY
    }
}
