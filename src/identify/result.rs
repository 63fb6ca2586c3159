//! End-to-end identification from data sets, and its report.

use super::builder::Identification;
use super::error::IdentifyError;
use super::options::{CHECK_TOL, IdentifyOptions, Level, Regularizer};
use super::reduce::{Reduced, reduce_samples, reduce_with_load};
use super::warning::IdentifyWarning;
use super::weighting::{self, JointWeighting};

/// A solution, when the joints were weighted by their noise each joint's
/// σ̂ (N·m) that weighted it, and a warning when σ̂ did not settle.
type Weighted = (
    super::solved::Solved,
    Option<Vec<f64>>,
    Option<IdentifyWarning>,
);
use crate::data::Dataset;
use crate::dynamics::params_file::{BodyParams, ParamsFile};
use crate::dynamics::{Data, Model, Samples, rnea};
use crate::dynamics::{Friction, FrictionTerm};
use crate::moments::{
    ConsistencyReport, DEGENERATE_TOL, DegenerateShape, InertialParams, RealizabilityReport,
    check_consistency, check_realizable, degenerate_shape, entropic_divergence,
};
use serde::Serialize;

/// One body's identified parameters and physical summary.
#[derive(Clone, Debug, Serialize)]
pub struct BodyResult {
    /// Body name.
    pub name: String,
    /// Its constraint level.
    pub level: Level,
    /// π in the paper's order.
    pub params: [f64; 10],
    /// Mass (kg).
    pub mass: f64,
    /// CoM (m), body frame; `None` when the mass is not positive (no CoM).
    pub com: Option<[f64; 3]>,
    /// Principal moments about the CoM (kg·m²; about the body origin when
    /// the mass is not positive).
    pub principal_moments: [f64; 3],
    /// Covariance-ellipsoid semi-axes √(μᵢ/m) (m); `None` when the body is
    /// not semi-consistent (a negative μᵢ or mass has no ellipsoid).
    pub covariance_semi_axes: Option<[f64; 3]>,
    /// `J(π) ⪰ 0` as checked by `moments` (tolerance [`CHECK_TOL`]).
    pub consistent: bool,
    /// The full consistency report.
    pub consistency: ConsistencyReport,
    /// Realizability in the body's ellipsoid, when one is given.
    pub realizability: Option<RealizabilityReport>,
    /// The entropic divergence `d(J(π) ‖ J(π̂))` from the prior
    /// (dimensionless), with either regulariser; `None` without a prior or
    /// when π or π̂ is not strictly consistent (the divergence is infinite).
    pub divergence_from_prior: Option<f64>,
    /// Whether the body has collapsed to a point mass, a rod or a plate
    /// (physically consistent, but no real link), against the size of its
    /// prior or bounding ellipsoid; `None` when it has spread.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub degenerate: Option<Degenerate>,
}

/// A body identified as a point mass, a rod or a plate, and what to do.
#[derive(Clone, Debug, Serialize)]
pub struct Degenerate {
    /// The shape.
    pub shape: DegenerateShape,
    /// Its covariance semi-axes √(μᵢ/m) (m).
    pub semi_axes: [f64; 3],
    /// The length they were measured against (m): the prior's or the
    /// bounding ellipsoid's largest semi-axis.
    pub length: f64,
    /// What to do about it.
    pub advice: String,
}

/// Advice for a degenerate body.
pub const DEGENERATE_ADVICE: &str = "the data do not determine this body's spread: bound it (the ellipsoid level with a bounding volume), hold it to its prior (the entropic regulariser with a weight of 1e-3 to 1e-1), or excite it more";

/// Torque contributions on the validation data (Fig. 5 of the paper).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Contributions {
    /// Link inertia (incl. gravity) per sample per joint (N·m).
    pub links: Samples,
    /// Rotor inertia per sample per joint.
    pub rotors: Samples,
    /// Friction per sample per joint.
    pub friction: Samples,
}

/// What reading did to the files of an identification.
#[derive(Clone, Debug, Default, Serialize)]
pub struct DataPreparation {
    /// The training files.
    pub training: Vec<crate::data::FileReport>,
    /// The validation files.
    pub validation: Vec<crate::data::FileReport>,
}

impl DataPreparation {
    /// Whether no file is reported.
    pub fn is_empty(&self) -> bool {
        self.training.is_empty() && self.validation.is_empty()
    }
}

/// The result of [`identify`].
#[derive(Clone, Debug, Serialize)]
pub struct IdentifyResult {
    /// Robot name.
    pub robot: String,
    /// Joint names.
    pub joints: Vec<String>,
    /// Parameter order, stated.
    pub parameter_order: String,
    /// Constraint level of the bodies (each body's own is in `bodies`).
    pub constraints: Level,
    /// Regularisation weight.
    pub weight: f64,
    /// The extra weight on the masses' distance from the prior's.
    pub prior_mass_weight: f64,
    /// How the prior entered the objective.
    pub regularizer: Regularizer,
    /// Bodies.
    pub bodies: Vec<BodyResult>,
    /// Friction.
    pub friction: Friction,
    /// How the joints' rows were weighted.
    pub joint_weighting: JointWeighting,
    /// When the weight was chosen by cross-validation
    /// ([`Identification::choose_weight`]): the curve and the choice (the
    /// caller sets it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight_choice: Option<super::WeightChoice>,
    /// With [`JointWeighting::Noise`]: each joint's noise σ̂_j (N·m, the
    /// residual RMS of the previous weighted solve, iterated until it
    /// settles) whose `1/σ̂_j²` weighted the final solve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint_noise: Option<Vec<f64>>,
    /// Every body satisfies what it was asked for (checked by `moments`).
    pub constraints_satisfied: bool,
    /// Every body is physically consistent (`J ⪰ 0`), whatever its level:
    /// at the `none` level the constraints are satisfied by definition, and
    /// this says whether the result is a physical robot.
    pub all_bodies_consistent: bool,
    /// The bodies that are not.
    pub inconsistent_bodies: Vec<String>,
    /// The bodies identified as point masses, rods or plates.
    pub degenerate_bodies: Vec<String>,
    /// Solver status.
    pub status: String,
    /// What the caller should know (an inaccurate solve, …).
    #[serde(serialize_with = "crate::warning::with_messages")]
    pub warnings: Vec<IdentifyWarning>,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Numerical rank of the regressor / number of parameters.
    pub rank: usize,
    /// Number of parameters.
    pub num_parameters: usize,
    /// Parameter directions the data do not excite.
    pub unidentifiable_directions: Vec<String>,
    /// Training samples.
    pub training_samples: usize,
    /// Training RMS per joint (N·m).
    pub training_rms: Vec<f64>,
    /// Validation RMS per joint (N·m), with validation data.
    pub validation_rms: Option<Vec<f64>>,
    /// Validation samples.
    pub validation_samples: usize,
    /// SDP (or direct least-squares) solve time (s).
    pub solve_time_s: f64,
    /// Regressor + reduction time (s).
    pub reduce_time_s: f64,
    /// Whole identification in the process, reading excluded (s); the CLI adds reading.
    pub total_time_s: f64,
    /// What reading did to the training and validation files (each step
    /// of the preparation of raw logs); empty when the caller read no file.
    #[serde(skip_serializing_if = "DataPreparation::is_empty")]
    pub data_preparation: DataPreparation,
    /// Validation predictions per sample (not serialised).
    #[serde(skip)]
    pub validation_prediction: Samples,
    /// Contributions on the validation data (not serialised).
    #[serde(skip)]
    pub contributions: Contributions,
    /// θ (not serialised; in `bodies` and `friction`).
    #[serde(skip)]
    pub theta: Vec<f64>,
}

impl BodyResult {
    /// π as [`InertialParams`].
    pub fn params(&self) -> InertialParams {
        InertialParams(self.params)
    }
}

impl IdentifyResult {
    /// The body named `name`.
    pub fn body(&self, name: &str) -> Result<&BodyResult, IdentifyError> {
        self.bodies
            .iter()
            .find(|b| b.name == name)
            .ok_or_else(|| IdentifyError::UnknownName {
                what: "body",
                name: name.into(),
                valid: self
                    .bodies
                    .iter()
                    .map(|b| b.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// Joint `joint`'s friction `(viscous B, Coulomb B_c)`.
    pub fn friction(&self, joint: &str) -> Result<(f64, f64), IdentifyError> {
        let i = self.joints.iter().position(|j| j == joint).ok_or_else(|| {
            IdentifyError::UnknownName {
                what: "joint",
                name: joint.into(),
                valid: self.joints.join(", "),
            }
        })?;
        Ok((self.friction.viscous[i], self.friction.coulomb[i]))
    }

    /// `model` with the identified inertial parameters (bodies matched by
    /// name), and the identified friction: the nominal model a diagnosis or a
    /// prediction starts from.
    pub fn applied_to(&self, model: &Model) -> Result<(Model, Friction), IdentifyError> {
        let mut m = model.clone();
        let f = self
            .params_file()
            .apply(&mut m, "the identification result")?;
        Ok((m, f))
    }

    /// The parameter file part (what `predict --params` reads).
    pub fn params_file(&self) -> ParamsFile {
        ParamsFile {
            robot: self.robot.clone(),
            joints: self.joints.clone(),
            parameter_order: self.parameter_order.clone(),
            bodies: self
                .bodies
                .iter()
                .map(|b| BodyParams {
                    name: b.name.clone(),
                    params: b.params,
                })
                .collect(),
            friction: self.friction.clone(),
        }
    }
}

/// `Y θ` per sample, split into links / rotors / friction.
pub fn predict_split(
    model: &Model,
    theta: &[f64],
    d: &Dataset,
) -> Result<(Samples, Contributions), IdentifyError> {
    let c = sample_parts(model, theta, d)?;
    let mut total = c.links.clone();
    for (k, t) in total.iter_mut().enumerate() {
        for (i, v) in t.iter_mut().enumerate() {
            *v += c.rotors[k][i] + c.friction[k][i];
        }
    }
    Ok((total, c))
}

/// Per sample, `Y θ` split into the links', the rotors' and friction's
/// columns (n each), in parallel over blocks of samples: the links' and the
/// rotors' parts by RNEA on the model with only those bodies' parameters
/// (τ is linear in them), friction from its basis.
fn sample_parts(model: &Model, theta: &[f64], d: &Dataset) -> Result<Contributions, IdentifyError> {
    use rayon::prelude::*;
    const BLOCK: usize = 512;
    let (n, nl, nb) = (model.dof(), 10 * model.dof(), 10 * model.num_bodies());
    let only = |range: std::ops::Range<usize>| -> Result<Model, IdentifyError> {
        let p: Vec<f64> = (0..nb)
            .map(|k| if range.contains(&k) { theta[k] } else { 0.0 })
            .collect();
        let mut m = model.clone();
        m.set_params(&p)?;
        Ok(m)
    };
    let (links, rotors) = (only(0..nl)?, only(nl..nb)?);
    let has_rotors = nb > nl;
    let basis = (model.friction_terms(), model.stribeck_velocity());
    let law = Friction::from_terms(n, basis, |k, i| theta[nb + k * n + i]);
    let mut c = Contributions {
        links: Samples::zeros(d.len(), n),
        rotors: Samples::zeros(d.len(), n),
        friction: Samples::zeros(d.len(), n),
    };
    let block = (BLOCK * n).max(1);
    (c.links.as_flat_mut().par_chunks_mut(block))
        .zip(c.rotors.as_flat_mut().par_chunks_mut(block))
        .zip(c.friction.as_flat_mut().par_chunks_mut(block))
        .enumerate()
        .try_for_each_init(
            || Data::new(model),
            |data, (b, ((l, r), f))| -> Result<(), IdentifyError> {
                for (j, k) in (b * BLOCK..).take(l.len() / n.max(1)).enumerate() {
                    let (q, qd, qdd) = (&d.q[k], &d.qd[k], &d.qdd[k]);
                    let at = j * n..(j + 1) * n;
                    l[at.clone()].copy_from_slice(rnea(&links, data, q, qd, qdd)?.as_slice());
                    if has_rotors {
                        r[at.clone()].copy_from_slice(rnea(&rotors, data, q, qd, qdd)?.as_slice());
                    }
                    for (i, v) in f[at.clone()].iter_mut().enumerate() {
                        *v = law.torque(i, qd[i], l[at.start + i] + r[at.start + i]);
                    }
                }
                Ok(())
            },
        )?;
    Ok(c)
}

/// RMS per joint of the training residual: from each joint's Gram matrix
/// when the reduction kept them (no second pass over the samples), else by
/// predicting again.
fn training_rms(
    model: &Model,
    theta: &[f64],
    train: &Dataset,
    red: &super::reduce::Reduced,
) -> Result<Vec<f64>, IdentifyError> {
    Ok(match red.joint_rss(theta) {
        Some(rss) => (rss.iter())
            .map(|r| (r / train.len() as f64).sqrt())
            .collect(),
        None => rms(&predict_split(model, theta, train)?.0, &train.tau),
    })
}

/// The names of the bodies that `keep` accepts.
fn names_where(bodies: &[BodyResult], keep: impl Fn(&BodyResult) -> bool) -> Vec<String> {
    bodies
        .iter()
        .filter(|b| keep(b))
        .map(|b| b.name.clone())
        .collect()
}

/// RMS per joint of `a − b` (rows: samples).
pub fn rms(a: &Samples, b: &Samples) -> Vec<f64> {
    let n = a.width();
    (0..n)
        .map(|j| crate::data::rms(a.iter().zip(b).map(|(x, y)| x[j] - y[j])))
        .collect()
}

/// Each body's summary and whether it satisfies its level (checked by
/// `moments`, tolerance [`CHECK_TOL`]).
fn body_results(id: &Identification, theta: &[f64]) -> (Vec<BodyResult>, bool) {
    let mut bodies = Vec::new();
    let mut ok = true;
    for (b, name) in id.model().body_names().into_iter().enumerate() {
        let pi = InertialParams(std::array::from_fn(|k| theta[10 * b + k]));
        let rep = check_consistency(&pi, CHECK_TOL);
        let (level, ellipsoid) = id.body_spec(b);
        let real = ellipsoid.map(|e| check_realizable(&pi, &e, CHECK_TOL));
        ok &= match level {
            Level::None => true,
            Level::Semi => rep.semi_consistent && pi.mass() > 0.0,
            Level::Consistent => rep.consistent,
            Level::Ellipsoid => real.as_ref().is_some_and(|r| r.realizable),
        };
        let finite = |v: [f64; 3]| v.iter().all(|x| x.is_finite()).then_some(v);
        let com = (pi.mass() > 0.0).then(|| pi.com().into()).and_then(finite);
        let cov = pi.covariance_ellipsoid();
        let cov = finite(cov.semi_axes.into()).filter(|_| pi.mass() > 0.0);
        bodies.push(BodyResult {
            name,
            level,
            params: pi.0,
            mass: pi.mass(),
            com,
            principal_moments: rep.principal_moments,
            covariance_semi_axes: cov,
            consistent: rep.consistent,
            consistency: rep,
            realizability: real,
            divergence_from_prior: id
                .prior_body(b)
                .and_then(|prior| entropic_divergence(&pi, &prior).ok()),
            degenerate: degeneracy(id, b, &pi, ellipsoid),
        });
    }
    (bodies, ok)
}

/// Body `b`'s degeneracy against its prior's size (else its bounding
/// ellipsoid's; neither: not judged).
fn degeneracy(
    id: &Identification,
    b: usize,
    pi: &InertialParams,
    ellipsoid: Option<crate::moments::Ellipsoid>,
) -> Option<Degenerate> {
    let from_prior = id
        .prior_body(b)
        .filter(|p| p.mass() > 0.0)
        .map(|p| p.covariance_ellipsoid().semi_axes.max())
        .filter(|l| l.is_finite() && *l > 0.0);
    let length = from_prior.or(ellipsoid.map(|e| e.semi_axes.max()))?;
    let (shape, semi_axes) = degenerate_shape(pi, length, DEGENERATE_TOL)?;
    Some(Degenerate {
        shape,
        semi_axes,
        length,
        advice: DEGENERATE_ADVICE.into(),
    })
}

/// Checks that a data set has torques for every sample.
fn with_torques(d: &Dataset) -> Result<(), IdentifyError> {
    if d.tau.len() != d.len() || d.is_empty() {
        return Err(IdentifyError::NoTrainingData {
            samples: d.len(),
            torques: d.tau.len(),
        });
    }
    Ok(())
}

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
    /// The planned memory of `samples` samples is within the limit.
    fn check_memory(&self, samples: usize) -> Result<(), IdentifyError> {
        let need = crate::identify::cost(self.model(), samples).bytes;
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
        Ok(r)
    }

    /// Reduces `train`, solves and checks every body (no validation: see
    /// [`IdentifyResult::validate`], e.g. once held-out data read meanwhile
    /// are in). [`reduce`](Self::reduce) then [`fit_reduced`](Self::fit_reduced).
    pub fn fit(&self, train: &Dataset) -> Result<IdentifyResult, IdentifyError> {
        self.fit_reduced(train, &self.reduce(train)?)
    }

    /// Solves on `red`; with a load friction term
    /// ([`FrictionTerm::Load`]), whose first reduction scales the column by
    /// the measured torque, solves again on `train` reduced with the load
    /// the law means (the previous solution's rigid torque), until that
    /// load settles (relative RMS change ≤ 1e-6, at most
    /// [`LOAD_PASSES`] passes; else a warning). The last reduction is
    /// returned.
    fn solve_loaded(
        &self,
        train: &Dataset,
        red: &Reduced,
    ) -> Result<(Weighted, Option<Reduced>, Option<IdentifyWarning>), IdentifyError> {
        let mut solved = self.solve_weighted(red)?;
        let model = self.model();
        if !model.friction_terms().contains(&FrictionTerm::Load) {
            return Ok((solved, None, None));
        }
        let (mut last, mut reduced, mut change) = (train.tau.clone(), None, f64::INFINITY);
        for _ in 0..LOAD_PASSES {
            let load = self.rigid_torques(&solved.0.theta, train)?;
            change = relative_change(&last, &load);
            if change <= 1e-6 {
                return Ok((solved, reduced, None));
            }
            let (q, qd, qdd) = (&train.q, &train.qd, &train.qdd);
            let red = reduce_with_load(model, [q, qd, qdd, &train.tau], &load, 256)?;
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
        with_torques(train)?;
        self.check_memory(train.len())?;
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
        let model = self.model();
        let t0 = std::time::Instant::now();
        if red.samples != train.len() {
            return Err(IdentifyError::SampleCount {
                what: "the reduction",
                expected: train.len(),
                found: red.samples,
            });
        }
        let (solved, reloaded, load_warning) = self.solve_loaded(train, red)?;
        let (solved, joint_noise, weights_warning) = solved;
        let red = reloaded.as_ref().unwrap_or(red);
        let theta = &solved.theta;
        let (bodies, ok) = body_results(self, theta);
        let inconsistent_bodies = names_where(&bodies, |b| !b.consistent);
        let degenerate_bodies = names_where(&bodies, |b| b.degenerate.is_some());
        let friction = solved.friction_law(model.stribeck_velocity());
        let training_rms = training_rms(model, theta, train, red)?;
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
            weight_choice: None,
            joint_noise,
            constraints_satisfied: ok,
            all_bodies_consistent: inconsistent_bodies.is_empty(),
            inconsistent_bodies,
            degenerate_bodies,
            status: status.as_str().into(),
            warnings: (status == crate::conic::Status::SolvedInaccurately)
                .then_some(IdentifyWarning::Inaccurate {
                    iterations: solved.iterations,
                })
                .into_iter()
                .chain(self.mass_weight_warning())
                .chain(self.prior_outside_warning())
                .chain(load_warning)
                .chain(weights_warning)
                .collect(),
            iterations: solved.iterations,
            rank: solved.rank,
            num_parameters: theta.len(),
            unidentifiable_directions: solved.unidentifiable.clone(),
            training_samples: train.len(),
            training_rms,
            validation_rms: None,
            validation_samples: 0,
            solve_time_s: solved.solve_time_s,
            reduce_time_s: red.reduce_time_s,
            total_time_s: red.reduce_time_s + t0.elapsed().as_secs_f64(),
            data_preparation: DataPreparation::default(),
            validation_prediction: Samples::default(),
            contributions: Contributions::default(),
            theta: solved.theta,
        })
    }
}

impl IdentifyResult {
    /// Validates on held-out data `v` (with torques) for the `model` it was
    /// identified on: the prediction, its parts and the RMS error per joint.
    pub fn validate(&mut self, model: &Model, v: &Dataset) -> Result<(), IdentifyError> {
        with_torques(v)?;
        if self.theta.len() != model.regressor_columns() {
            return Err(IdentifyError::Columns {
                expected: model.regressor_columns(),
                found: self.theta.len(),
            });
        }
        let (pred, c) = predict_split(model, &self.theta, v)?;
        let r = rms(&pred, &v.tau);
        if !r.iter().all(|x| x.is_finite()) {
            return Err(IdentifyError::Overflow {
                what: "the held-out RMS errors",
            });
        }
        self.validation_rms = Some(r);
        self.validation_samples = v.len();
        self.validation_prediction = pred;
        self.contributions = c;
        Ok(())
    }
}

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
