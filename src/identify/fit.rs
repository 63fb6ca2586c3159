//! Fitting: the training data reduced (or a reduction made while they
//! were read), the SDP solved (again while a load friction term's load
//! settles, or while the joints' noise weights settle), every body checked
//! and the report ([`IdentifyResult`]) assembled.

use super::builder::Identification;
use super::error::IdentifyError;
use super::load_passes::{reduced_from, with_load};
use super::load_rows::LoadRows;
use super::options::IdentifyOptions;
use super::reduce::{Reduced, reduce_samples, reduce_with_load};
use super::result::{
    Contributions, DataPreparation, IdentifyResult, Timings, body_results, names_where,
    training_rms, with_torques,
};
use super::warning::IdentifyWarning;
use super::weighting::{self, JointWeighting};
use crate::data::Dataset;
use crate::dynamics::{Friction, FrictionTerm, Model, Samples};

/// A solution, when the joints were weighted by their noise each joint's
/// σ̂ (N·m) that weighted it, and a warning when σ̂ did not settle.
type Weighted = (
    super::solved::Solved,
    Option<Vec<f64>>,
    Option<IdentifyWarning>,
);

/// Identifies `model`'s parameters from `train` (its current parameters are
/// only used for names), optionally validating on `validate` (which then
/// needs torques too), with the options' set-up
/// ([`Identification::from_options`]).
pub fn identify(
    model: &Model,
    train: &Dataset,
    validate: Option<&Dataset>,
    opts: &IdentifyOptions,
) -> Result<IdentifyResult, IdentifyError> {
    Identification::from_options(model, opts)?.identify(train, validate)
}

impl Identification<'_> {
    /// The planned memory of `samples` samples (the reduction's, and a load
    /// term's kept rows) is within the limit.
    pub(crate) fn check_memory(&self, samples: usize) -> Result<(), IdentifyError> {
        let rows = LoadRows::bytes(self.model(), samples) as u64;
        let need = crate::identify::cost(self.model(), samples).bytes + rows;
        if need > self.memory_limit() {
            return Err(IdentifyError::TooLarge {
                needed_gib: need as f64 / (1u64 << 30) as f64,
                limit_gib: self.memory_limit() as f64 / (1u64 << 30) as f64,
            });
        }
        Ok(())
    }

    /// Reduces `train`, solves, checks every body and validates on
    /// `validate` (which then needs torques too).
    pub fn identify(
        &self,
        train: &Dataset,
        validate: Option<&Dataset>,
    ) -> Result<IdentifyResult, IdentifyError> {
        let t0 = std::time::Instant::now();
        if let Some(v) = validate {
            with_torques(v)?;
        }
        let mut r = self.fit(train)?;
        if let Some(v) = validate {
            r.validate(self.model(), v)?;
        }
        r.total_time_s = t0.elapsed().as_secs_f64();
        r.timings.total_s = r.total_time_s;
        Ok(r)
    }

    /// Reduces `train`, solves and checks every body (no validation: see
    /// [`IdentifyResult::validate`], e.g. once held-out data read meanwhile
    /// are in). [`reduce`](Self::reduce) then [`fit_reduced`](Self::fit_reduced).
    pub fn fit(&self, train: &Dataset) -> Result<IdentifyResult, IdentifyError> {
        self.fit_reduced(train, &self.reduce(train)?)
    }

    /// [`solve_loaded`](Self::solve_loaded), the model's structural rank
    /// (random states, an SVD) computed meanwhile on another thread (the
    /// SDP is solved on one core) when it is not yet known.
    fn solve_ranked(
        &self,
        train: Option<&Dataset>,
        red: &Reduced,
    ) -> Result<(Weighted, Option<Reduced>, Option<IdentifyWarning>), IdentifyError> {
        let model = self.model;
        let (loaded, rank) = std::thread::scope(|s| {
            let rank = (self.structural_rank.get().is_none())
                .then(|| s.spawn(move || super::identifiability::structural_rank(model)));
            (self.solve_loaded(train, red), rank.map(|r| r.join()))
        });
        // the solve's error first
        let loaded = loaded?;
        if let Some(rank) = rank {
            let rank = rank.map_err(|_| IdentifyError::Factorisation {
                what: "the structural rank's computation (its thread panicked)",
            })??;
            let _ = self.structural_rank.set(rank);
        }
        Ok(loaded)
    }

    /// Solves on `red`; with a load friction term
    /// ([`FrictionTerm::Load`]), whose first reduction scales the column by
    /// the measured torque (or, made from the friction law's choice, by the
    /// model's own bodies' rigid torque), solves again on `train` reduced with the load
    /// the law means (the previous solution's rigid torque), until that
    /// load settles (relative RMS change ≤ [`LOAD_SETTLED`], at most
    /// [`LOAD_PASSES`] passes; else a warning). The last reduction is
    /// returned.
    fn solve_loaded(
        &self,
        train: Option<&Dataset>,
        red: &Reduced,
    ) -> Result<(Weighted, Option<Reduced>, Option<IdentifyWarning>), IdentifyError> {
        let mut solved = self.solve_weighted(red)?;
        let model = self.model();
        if !model.friction_terms().contains(&FrictionTerm::Load) {
            return Ok((solved, None, None));
        }
        let Some(train) = train else {
            return Err(IdentifyError::LoadNeedsSamples);
        };
        // the rows kept, when they fit: a pass then replaces the load column
        // (and the load `red` was made with)
        let (rows, mut last) = match &red.load_rows {
            Some(rows) if rows.samples() == train.len() => {
                (Some(rows.clone()), rows.load().clone())
            }
            _ => (
                LoadRows::new(model, train)?.map(std::sync::Arc::new),
                train.tau.clone(),
            ),
        };
        let (mut reduced, mut change) = (None, f64::INFINITY);
        let bodies_end = 10 * model.num_bodies();
        for _ in 0..LOAD_PASSES {
            let load = match &rows {
                Some(rows) => rows.rigid_torques(&solved.0.theta, bodies_end),
                None => self.rigid_torques(&solved.0.theta, train)?,
            };
            change = relative_change(&last, &load);
            if change <= LOAD_SETTLED {
                return Ok((solved, reduced, None));
            }
            let (q, qd, qdd) = (&train.q, &train.qd, &train.qdd);
            let red = match &rows {
                Some(rows) => with_load(rows, red, &load)?,
                None => reduce_with_load(model, [q, qd, qdd, &train.tau], &load, 256)?,
            };
            solved = self.solve_weighted(&red)?;
            (last, reduced) = (load, Some(red));
        }
        let warning = IdentifyWarning::LoadNotSettled {
            passes: LOAD_PASSES,
            change,
        };
        Ok((solved, reduced, Some(warning)))
    }

    /// Solves on `red` with the joints weighted as set
    /// ([`super::weighting`]): equally, or (iterated feasible weighted
    /// least squares) equally first, then with each joint's rows by
    /// `1/σ̂_j²`, σ̂_j the last solution's residual RMS, until σ̂ changes by
    /// under 1 % ([`weighting::PASSES`] at most; the σ̂ used is returned).
    fn solve_weighted(&self, red: &Reduced) -> Result<Weighted, IdentifyError> {
        let mut solved = self.solve(red)?;
        if self.joint_weighting == JointWeighting::Equal {
            return Ok((solved, None, None));
        }
        let n = self.model().dof();
        let mut sigma = weighting::joint_rms(red, &solved.theta, n)?;
        for _ in 0..weighting::PASSES {
            let w = weighting::noise_weights(&sigma);
            solved = self.solve(&weighting::weighted(red, &w)?)?;
            let next = weighting::joint_rms(red, &solved.theta, n)?;
            if weighting::settled(&sigma, &next) {
                return Ok((solved, Some(sigma), None));
            }
            sigma = next;
        }
        // the last solve was weighted by the σ̂ before `sigma`: solve once
        // more with the σ̂ reported
        let w = weighting::noise_weights(&sigma);
        solved = self.solve(&weighting::weighted(red, &w)?)?;
        let warning = IdentifyWarning::WeightsNotSettled {
            passes: weighting::PASSES,
        };
        Ok((solved, Some(sigma), Some(warning)))
    }

    /// The rigid model's torques (links and rotors at `theta`'s bodies, no
    /// friction) at every sample of `d`.
    fn rigid_torques(&self, theta: &[f64], d: &Dataset) -> Result<Samples, IdentifyError> {
        let model = self.model();
        let mut rigid = model.clone();
        rigid.set_params(&theta[..10 * model.num_bodies()])?;
        let none = Friction::zeros(model.dof());
        Ok(crate::dynamics::predict::predict_torques(
            &rigid, &none, &d.q, &d.qd, &d.qdd,
        )?)
    }

    /// The first half of [`fit`](Self::fit): `train`'s regressor reduced to
    /// its Gram matrix (in parallel; the memory limit checked first).
    pub fn reduce(&self, train: &Dataset) -> Result<Reduced, IdentifyError> {
        self.fixed_base("Identification::reduce")?;
        with_torques(train)?;
        self.check_memory(train.len())?;
        // a load term's passes need the rows again: kept, when they fit
        let t0 = std::time::Instant::now();
        if let Some(rows) = LoadRows::new(self.model(), train)? {
            return reduced_from(rows, self.model().regressor_columns(), t0);
        }
        reduce_samples(
            self.model(),
            &train.q,
            &train.qd,
            &train.qdd,
            &train.tau,
            256,
        )
    }

    /// The second half of [`fit`](Self::fit): solves on `red`, the
    /// [`reduce`](Self::reduce) of `train` (the training RMS comes from its
    /// per-joint Gram matrices, else from `train` predicted again), and
    /// checks every body. The solve uses one core: a caller can read its
    /// held-out data meanwhile.
    pub fn fit_reduced(
        &self,
        train: &Dataset,
        red: &Reduced,
    ) -> Result<IdentifyResult, IdentifyError> {
        if red.samples != train.len() {
            return Err(IdentifyError::SampleCount {
                what: "the reduction",
                expected: train.len(),
                found: red.samples,
            });
        }
        self.fit_on(Some(train), red)
    }

    /// [`fit_reduced`](Self::fit_reduced) without the samples: for a
    /// reduction made while the data were read
    /// ([`reduce_logs`](super::reduce_logs)). It needs each joint's Gram
    /// matrix (for the training RMS), and a load friction term, whose
    /// refit predicts every sample again, is an error.
    pub fn fit_streamed(&self, red: &Reduced) -> Result<IdentifyResult, IdentifyError> {
        self.check_memory(red.samples)?;
        self.fit_on(None, red)
    }

    fn fit_on(
        &self,
        train: Option<&Dataset>,
        red: &Reduced,
    ) -> Result<IdentifyResult, IdentifyError> {
        self.fixed_base("Identification::fit")?;
        let model = self.model();
        let t0 = std::time::Instant::now();
        let (solved, reloaded, load_warning) = self.solve_ranked(train, red)?;
        let (solved, joint_noise, weights_warning) = solved;
        let red = reloaded.as_ref().unwrap_or(red);
        let theta = &solved.theta;
        let t_check = std::time::Instant::now();
        let (bodies, ok) = body_results(self, theta);
        let inconsistent_bodies = names_where(&bodies, |b| !b.consistent);
        let degenerate_bodies = names_where(&bodies, |b| b.degenerate.is_some());
        let friction = solved.friction_law(model.stribeck_velocity());
        let training_rms = training_rms(model, theta, train, red)?;
        let check_s = t_check.elapsed().as_secs_f64();
        let status = solved.status;
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !(finite(theta) && finite(&training_rms)) {
            return Err(IdentifyError::Overflow {
                what: "the identified parameters or their RMS errors",
            });
        }
        Ok(IdentifyResult {
            robot: model.name.clone(),
            joints: model.joint_names().iter().map(|s| s.to_string()).collect(),
            parameter_order: "m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz".into(),
            constraints: self.common_level(),
            weight: self.weight(),
            prior_mass_weight: self.mass_weight(),
            regularizer: self.regularizer_kind(),
            bodies,
            friction,
            joint_weighting: self.joint_weighting,
            effects: vec![],
            weight_choice: None,
            model_selection: None,
            joint_noise,
            constraints_satisfied: ok,
            all_bodies_consistent: inconsistent_bodies.is_empty(),
            inconsistent_bodies,
            degenerate_bodies,
            status: status.as_str().into(),
            warnings: IdentifyWarning::of_status(status, solved.iterations)
                .into_iter()
                .chain(self.mass_weight_warning())
                .chain(self.prior_outside_warning())
                .chain(load_warning)
                .chain(weights_warning)
                .collect(),
            iterations: solved.iterations,
            identifiability: self.with_structure(&solved)?,
            bounds: None,
            training_samples: red.samples,
            training_rms,
            validation_rms: None,
            validation_samples: 0,
            solve_time_s: solved.solve_time_s,
            reduce_time_s: red.reduce_time_s,
            total_time_s: red.reduce_time_s + t0.elapsed().as_secs_f64(),
            timings: Timings {
                reduce_s: red.reduce_time_s,
                solve_s: solved.solve_time_s,
                check_s,
                total_s: red.reduce_time_s + t0.elapsed().as_secs_f64(),
                ..Timings::default()
            },
            data_preparation: DataPreparation::default(),
            validation_prediction: Samples::default(),
            contributions: Contributions::default(),
            theta: solved.theta,
        })
    }
}

impl Identification<'_> {
    /// The solve's identifiability report with the model's structural
    /// rank.
    fn with_structure(
        &self,
        solved: &super::solved::Solved,
    ) -> Result<super::identifiability::Identifiability, IdentifyError> {
        Ok(super::identifiability::Identifiability {
            structural_rank: self.structural_rank()?,
            ..solved.identifiability.clone()
        })
    }

    /// The model's structural rank, computed once per identification.
    fn structural_rank(&self) -> Result<Option<usize>, IdentifyError> {
        if let Some(rank) = self.structural_rank.get() {
            return Ok(*rank);
        }
        let rank = super::identifiability::structural_rank(self.model)?;
        Ok(*self.structural_rank.get_or_init(|| rank))
    }
}

/// The relative RMS change of the load at which a load friction term's
/// passes stop: the load term's torque then moves by μ·1e-3·|τ| (a
/// harmonic drive's μ ≈ 0.05 and |τ| ≤ 100 N·m: 5e-3 N·m), an order below
/// the noise of the best joint torque sensors (~0.05 N·m); each further
/// pass is an SDP solve.
pub const LOAD_SETTLED: f64 = 1e-3;

/// The most passes of a load friction term's identification
/// ([`Identification::fit_reduced`]).
pub const LOAD_PASSES: usize = 20;

/// RMS(b − a) / RMS(b) over every value (0 when both are zero).
fn relative_change(a: &Samples, b: &Samples) -> f64 {
    let (a, b) = (a.as_flat(), b.as_flat());
    let d: f64 = a.iter().zip(b).map(|(x, y)| (y - x).powi(2)).sum();
    let s: f64 = b.iter().map(|y| y * y).sum();
    if d == 0.0 { 0.0 } else { (d / s).sqrt() }
}
