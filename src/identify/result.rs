//! End-to-end identification from data sets, and its report.

use super::builder::Identification;
use super::error::IdentifyError;
use super::options::{CHECK_TOL, Level, Regularizer};
use super::warning::IdentifyWarning;
use super::weighting::JointWeighting;
use crate::data::Dataset;
use crate::dynamics::Friction;
use crate::dynamics::params_file::{BodyParams, ParamsFile};
use crate::dynamics::{Data, Model, Samples, rnea};
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
    /// The raw logs' low-pass cut-off chosen by held-out torque error, and
    /// its curve (when none was given and a training log was raw).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cutoff_choice: Option<super::cutoff::CutoffCurve>,
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
    /// Effects held at a diagnosis' values while identifying (their
    /// torques taken off the data's), carried so that a model file of this
    /// result applies them (none by default).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<crate::dynamics::params_file::FittedEffect>,
    /// How the joints' rows were weighted.
    pub joint_weighting: JointWeighting,
    /// When the weight was chosen by cross-validation
    /// ([`Identification::choose_weight`]): the curve and the choice (the
    /// caller sets it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight_choice: Option<super::WeightChoice>,
    /// The friction law chosen by cross-validation (`--friction auto`) and
    /// the table it was chosen from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_selection: Option<super::friction_choice::FrictionChoice>,
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
    /// What the data can tell: the rank of the regressor, its base
    /// parameters with their standard deviations, the parameters that
    /// enter no torque and the directions the data do not excite.
    pub identifiability: super::identifiability::Identifiability,
    /// Each parameter's range over the models that fit almost as well
    /// ([`Identification::parameter_bounds`]; the caller sets it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bounds: Option<super::bounds::ParameterBounds>,
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
    /// Each stage's time.
    pub timings: Timings,
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

/// Each stage's time (s). A stage run by itself is timed by the wall
/// clock; reading and filtering, which run per file in parallel (and,
/// when the training logs are streamed, per block beside the reduction),
/// are summed over the files or blocks, so that the stages can add up to
/// more than `total_s`. A stage that did not run is 0.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Timings {
    /// Reading and parsing the training files.
    pub read_s: f64,
    /// Preparing them: the low-pass filter, the derivatives, resampling.
    pub filter_s: f64,
    /// The regressor and its reduction to the Gram matrix (when streamed,
    /// the wall time of reading and reducing together).
    pub reduce_s: f64,
    /// The SDP (or the direct least-squares solve), with its set-up.
    pub solve_s: f64,
    /// Every body checked by `moments`, the training RMS.
    pub check_s: f64,
    /// The held-out prediction and its RMS (the held-out files' reading not
    /// included: it runs beside the solve).
    pub validate_s: f64,
    /// The whole identification, by the wall clock.
    pub total_s: f64,
    /// Whether the training logs were reduced while they were read.
    pub streamed: bool,
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
            effects: vec![],
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
pub(super) fn training_rms(
    model: &Model,
    theta: &[f64],
    train: Option<&Dataset>,
    red: &super::reduce::Reduced,
) -> Result<Vec<f64>, IdentifyError> {
    Ok(match (red.joint_rss(theta), train) {
        (Some(rss), _) => (rss.iter())
            .map(|r| (r / red.samples as f64).sqrt())
            .collect(),
        (None, Some(train)) => rms(&predict_split(model, theta, train)?.0, &train.tau),
        (None, None) => {
            return Err(IdentifyError::JointGramsMissing {
                joints: model.dof(),
                kept: red.joint_grams.len(),
            });
        }
    })
}

/// The names of the bodies that `keep` accepts.
pub(super) fn names_where(
    bodies: &[BodyResult],
    keep: impl Fn(&BodyResult) -> bool,
) -> Vec<String> {
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
pub(super) fn body_results(id: &Identification, theta: &[f64]) -> (Vec<BodyResult>, bool) {
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
pub(super) fn with_torques(d: &Dataset) -> Result<(), IdentifyError> {
    if d.tau.len() != d.len() || d.is_empty() {
        return Err(IdentifyError::NoTrainingData {
            samples: d.len(),
            torques: d.tau.len(),
        });
    }
    Ok(())
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
        let t0 = std::time::Instant::now();
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
        self.timings.validate_s = t0.elapsed().as_secs_f64();
        Ok(())
    }
}
