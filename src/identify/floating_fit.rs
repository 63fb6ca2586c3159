//! A floating-base identification end to end: training logs reduced on the
//! chosen [`Rows`], solved ([`Identification::for_free_flyer`]), the
//! fitted robot's residuals by row group on the training and held-out
//! logs, every body's consistency and the whole robot's mass, CoM and
//! centroidal inertia. What `momentlmi identify --floating-base` reports.

use super::builder::Identification;
use super::error::IdentifyError;
use super::floating::{Rows, measured, reduce_floating_weighted};
use super::reduce::Reduced;
use super::solved::Solved;
use crate::data::Dataset;
use crate::dynamics::{Data, Friction, Model};
use crate::moments::InertialParams;
use rayon::prelude::*;

/// A model's residual RMS on a floating-base log, by row group.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FloatingRms {
    /// Samples.
    pub samples: usize,
    /// The base's three force rows (N).
    pub base_force: f64,
    /// The base's three moment rows (N·m).
    pub base_moment: f64,
    /// Per joint (N·m); empty when the log has no joint torques.
    pub joints: Vec<f64>,
}

/// The whole robot at one configuration, in base coordinates.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct WholeBody {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass (m).
    pub com: [f64; 3],
    /// Rotational inertia about the CoM (kg·m²), row by row.
    pub centroidal_inertia: [[f64; 3]; 3],
}

/// A floating-base identification's result.
#[derive(Clone, Debug)]
pub struct FloatingFit {
    /// The rows fitted.
    pub rows: Rows,
    /// The solver's answer (θ, names, identifiability).
    pub solved: Solved,
    /// The robot with the identified bodies.
    pub model: Model,
    /// The identified friction (zero with the base rows alone).
    pub friction: Friction,
    /// Per body (base first): the smallest eigenvalue of its pseudo-inertia
    /// J (kg·m²; ≥ 0 consistent).
    pub min_eigenvalues: Vec<f64>,
    /// Per body (base first): mass, CoM, principal moments, consistency,
    /// degeneracy — the fixed base's summary
    /// ([`IdentifyResult::bodies`](super::IdentifyResult::bodies)).
    pub bodies: Vec<super::BodyResult>,
    /// Every body satisfies its constraint level (checked by `moments`).
    pub constraints_satisfied: bool,
    /// The whole robot at the first training sample's configuration.
    pub whole_body: WholeBody,
    /// Residuals on the training logs.
    pub train: FloatingRms,
    /// Residuals on the held-out logs, if any.
    pub validation: Option<FloatingRms>,
    /// Every row's weight (6 + n) with [`Rows::All`]: 1/σ̂² of its group
    /// (base force, base moment, each joint) from an unweighted fit first.
    pub row_weights: Option<Vec<f64>>,
    /// What the caller should know (the solver's reduced tolerances).
    pub warnings: Vec<super::IdentifyWarning>,
}

/// 1/σ̂² per row from a fit's residuals by group (a zero σ̂ weighs as the
/// smallest positive one).
fn group_weights(r: &FloatingRms) -> Vec<f64> {
    let mut sigma = vec![r.base_force; 3];
    sigma.extend([r.base_moment; 3]);
    sigma.extend(&r.joints);
    let least = sigma
        .iter()
        .copied()
        .filter(|s| *s > 0.0)
        .fold(f64::INFINITY, f64::min);
    let least = if least.is_finite() { least } else { 1.0 };
    sigma.iter().map(|s| 1.0 / s.max(least).powi(2)).collect()
}

/// Every training log reduced on `rows` (each row weighted by `weights`,
/// if given), the Gram matrices summed.
pub fn reduce_floating_logs(
    ff: &Model,
    logs: &[Dataset],
    rows: Rows,
    weights: Option<&[f64]>,
) -> Result<Reduced, IdentifyError> {
    let mut total: Option<Reduced> = None;
    for log in logs {
        let red = reduce_floating_weighted(ff, log, rows, weights)?;
        total = Some(match total {
            None => red,
            Some(t) => Reduced {
                row_range: t.row_range,
                ..Reduced::from_gram(t.gram + red.gram, t.samples + red.samples)?
            },
        });
    }
    total.ok_or(IdentifyError::NoTrainingData {
        samples: 0,
        torques: 0,
    })
}

/// Solves `id` (a [`Identification::for_free_flyer`] of `ff` on `rows`)
/// on the training logs and reports the fit on them and on `validate`.
pub fn fit_floating(
    id: &Identification,
    ff: &Model,
    rows: Rows,
    train: &[Dataset],
    validate: &[Dataset],
) -> Result<FloatingFit, IdentifyError> {
    if let Some(empty) = train.iter().find(|l| l.is_empty()) {
        return Err(IdentifyError::NoTrainingData {
            samples: empty.len(),
            torques: 0,
        });
    }
    let red = reduce_floating_logs(ff, train, rows, None)?;
    for v in validate {
        v.check(ff)?;
    }
    let mut solved = id.solve(&red)?;
    let mut row_weights = None;
    if rows == Rows::All {
        // N and N·m rows of unlike noise: each group weighted by 1/σ̂², σ̂
        // its residual RMS of the unweighted fit (once: the weights settle)
        let r = floating_rms_of(ff, &solved.theta, train)?;
        let w = group_weights(&r);
        solved = id.solve(&reduce_floating_logs(ff, train, rows, Some(&w))?)?;
        row_weights = Some(w);
    }
    if rows == Rows::Base {
        // no friction acts on the base rows: pinned to 0, exactly (the
        // solver's equality holds to its tolerance)
        solved.theta[10 * ff.num_bodies()..].fill(0.0);
    }
    let mut model = ff.clone();
    model.set_params(&solved.theta[..10 * ff.num_bodies()])?;
    let friction = solved.friction_law(ff.stribeck_velocity());
    let warnings = super::IdentifyWarning::of_status(solved.status, solved.iterations)
        .into_iter()
        .collect();
    let min_eigenvalues = (0..ff.num_bodies())
        .map(|b| {
            let p = InertialParams(std::array::from_fn(|k| solved.theta[10 * b + k]));
            p.pseudo_inertia().symmetric_eigenvalues().min()
        })
        .collect();
    let (bodies, constraints_satisfied) = super::result::body_results(id, &solved.theta);
    let (q0, _, _) = train[0].state(0);
    let whole_body = whole_body(&model, &q0)?;
    // a millionth of the URDF's mass is no robot: the fit collapsed
    let described = self::whole_body(ff, &q0)?.mass;
    if !(whole_body.mass > 1e-6 * described && whole_body.com.iter().all(|c| c.is_finite())) {
        return Err(IdentifyError::NoWholeMass {
            mass: whole_body.mass,
        });
    }
    let train_rms = floating_rms_of(ff, &solved.theta, train)?;
    let validation = if validate.is_empty() {
        None
    } else {
        Some(floating_rms_of(ff, &solved.theta, validate)?)
    };
    Ok(FloatingFit {
        rows,
        solved,
        model,
        friction,
        min_eigenvalues,
        bodies,
        constraints_satisfied,
        whole_body,
        train: train_rms,
        validation,
        row_weights,
        warnings,
    })
}

/// The whole robot `ff` at configuration `q`.
pub fn whole_body(ff: &Model, q: &[f64]) -> Result<WholeBody, IdentifyError> {
    let mut data = Data::new(ff);
    let (mass, com, inertia) = ff.centroidal(&mut data, q)?;
    Ok(WholeBody {
        mass,
        com: [com.x, com.y, com.z],
        centroidal_inertia: std::array::from_fn(|i| std::array::from_fn(|j| inertia[(i, j)])),
    })
}

/// [`floating_rms`] over several logs together.
pub fn floating_rms_of(
    ff: &Model,
    theta: &[f64],
    logs: &[Dataset],
) -> Result<FloatingRms, IdentifyError> {
    let n = ff.dof();
    let mut sums = vec![0.0; 6 + n];
    let (mut samples, mut torques) = (0, true);
    for log in logs {
        let s = squared_residuals(ff, theta, log)?;
        sums.iter_mut().zip(&s).for_each(|(a, b)| *a += b);
        samples += log.len();
        torques &= log.has_torques();
    }
    let rms = |range: std::ops::Range<usize>| {
        let k = (range.len() * samples) as f64;
        (sums[range].iter().sum::<f64>() / k).sqrt()
    };
    Ok(FloatingRms {
        samples,
        base_force: rms(0..3),
        base_moment: rms(3..6),
        joints: if torques {
            (6..6 + n).map(|i| rms(i..i + 1)).collect()
        } else {
            vec![]
        },
    })
}

/// The residual RMS of the model `theta` (the regressor's columns) on
/// `log`, by row group.
pub fn floating_rms(
    ff: &Model,
    theta: &[f64],
    log: &Dataset,
) -> Result<FloatingRms, IdentifyError> {
    floating_rms_of(ff, theta, std::slice::from_ref(log))
}

/// Per row (6 + n), the sum over the samples of `(measured − Y θ)²`.
fn squared_residuals(ff: &Model, theta: &[f64], log: &Dataset) -> Result<Vec<f64>, IdentifyError> {
    log.check(ff)?;
    let chunks: Vec<usize> = (0..log.len()).step_by(256).collect();
    let parts = (chunks.par_iter())
        .map(|&s0| {
            let mut data = Data::new(ff);
            let mut sums = vec![0.0; ff.nv()];
            for k in s0..(s0 + 256).min(log.len()) {
                let r = residual(ff, &mut data, theta, log, k)?;
                sums.iter_mut().zip(r.iter()).for_each(|(s, x)| *s += x * x);
            }
            Ok(sums)
        })
        .collect::<Result<Vec<_>, IdentifyError>>()?;
    let mut sums = vec![0.0; ff.nv()];
    for p in parts {
        sums.iter_mut().zip(&p).for_each(|(a, b)| *a += b);
    }
    Ok(sums)
}

/// Sample k's `measured − Y θ` (6 + n).
pub fn residual(
    ff: &Model,
    data: &mut Data,
    theta: &[f64],
    log: &Dataset,
    k: usize,
) -> Result<nalgebra::DVector<f64>, IdentifyError> {
    if theta.len() != ff.regressor_columns() {
        return Err(IdentifyError::Columns {
            expected: ff.regressor_columns(),
            found: theta.len(),
        });
    }
    let b = measured(ff, data, log, k)?;
    let y = super::floating::sample_regressor(ff, data, log, k)?;
    Ok(b - y * nalgebra::DVector::from_column_slice(theta))
}

impl FloatingFit {
    /// The parameters the fitted rows determine on their own.
    pub fn determined_alone(&self) -> Vec<String> {
        let id = &self.solved.identifiability;
        let names = (self.model)
            .layout_of_rows(self.rows.range(self.model.dof()))
            .parameter_names();
        (names.into_iter().enumerate())
            .filter(|(k, _)| id.determined_alone(*k))
            .map(|(_, n)| n)
            .collect()
    }

    /// The report as `identify --json` writes it: a parameter file
    /// (robot, joints, bodies, friction; `predict --params` reads it) with
    /// the fit beside it; each body as the fixed base's report has it
    /// (name, params, mass, CoM, principal moments, consistency,
    /// degeneracy).
    pub fn to_json(&self) -> serde_json::Value {
        let file = crate::dynamics::params_file::ParamsFile::from_model(
            &self.model,
            self.friction.clone(),
        );
        let mut v = serde_json::to_value(file).unwrap_or_default();
        let names = |keep: fn(&super::BodyResult) -> bool| -> Vec<&str> {
            (self.bodies.iter().filter(|b| keep(b)))
                .map(|b| b.name.as_str())
                .collect()
        };
        let inconsistent = names(|b| !b.consistent);
        let warnings: Vec<String> = self.warnings.iter().map(|w| w.to_string()).collect();
        let fields = [
            ("bodies", serde_json::json!(self.bodies)),
            ("all_bodies_consistent", inconsistent.is_empty().into()),
            ("inconsistent_bodies", serde_json::json!(inconsistent)),
            (
                "degenerate_bodies",
                serde_json::json!(names(|b| b.degenerate.is_some())),
            ),
            ("constraints_satisfied", self.constraints_satisfied.into()),
            ("floating_base", true.into()),
            ("rows", self.rows.as_str().into()),
            ("status", format!("{:?}", self.solved.status).into()),
            ("warnings", serde_json::json!(warnings)),
            ("min_eigenvalues", serde_json::json!(self.min_eigenvalues)),
            ("whole_body", serde_json::json!(self.whole_body)),
            ("train_rms", serde_json::json!(self.train)),
            ("validation_rms", serde_json::json!(self.validation)),
            (
                "determined_alone",
                serde_json::json!(self.determined_alone()),
            ),
            (
                "identifiability",
                serde_json::json!(self.solved.identifiability),
            ),
        ];
        if let Some(m) = v.as_object_mut() {
            m.extend(fields.into_iter().map(|(k, x)| (k.to_string(), x)));
        }
        v
    }
}
