//! # `diagnose`: where the sim-to-real gap lies and which effect explains it
//!
//! Given a nominal model (parameters + friction) and measured data, the data
//! are split in time (training first, held-out last). **Where:** the
//! held-out residual `τ − τ̂` per joint, by motion regime, position,
//! frequency band and time, with whiteness and cross-correlation checks
//! ([`where_`]). **Which:** every candidate effect of the library
//! ([`candidates`]) is an addition to the current model, fitted on the
//! training part only; it is scored by its held-out RMS reduction, a block
//! test on the held-out part (robust to correlated residuals) and ΔBIC on
//! the training part. Forward selection accepts the best significant one,
//! adds it, and repeats. Candidates within noise of the best are reported
//! as tied. **How far:** held-out RMS per joint before and after, the share
//! of the gap above the noise floor that is closed, and whether a remainder
//! is left unexplained.
//!
//! See `docs/diagnosis.md` for the method in full and the confusion table
//! of the withheld-effect benchmark.

pub mod candidates;
pub mod compliance;
mod error;
mod fit;
mod select;
mod split;
pub mod where_;

pub use error::{DiagnoseError, FitError};

use crate::data::Dataset;
use crate::dynamics::params_file::Friction;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Effect, Model};
use candidates::{Candidate, Columns, build, flat};
use rayon::prelude::*;
use select::{Evaluation, choose, evaluate};
use serde::Serialize;
use split::{Split, rms_per_joint};
use where_::{JointWhere, analyse_joint, summarise};

/// The fewest samples a diagnosis takes.
pub const MIN_SAMPLES: usize = 100;

/// Options, validated at construction ([`DiagnoseOptions::new`]).
#[derive(Clone, Debug, PartialEq)]
pub struct DiagnoseOptions {
    train_fraction: f64,
    max_effects: usize,
    blocks: usize,
    max_memory_bytes: u64,
}

/// The memory a diagnosis may plan for by default (8 GiB).
pub const DEFAULT_MAX_MEMORY_BYTES: u64 = 8 << 30;

impl Default for DiagnoseOptions {
    /// 60 % training, at most 4 effects, 20 held-out blocks, 8 GiB.
    fn default() -> Self {
        Self {
            train_fraction: 0.6,
            max_effects: 4,
            blocks: 20,
            max_memory_bytes: DEFAULT_MAX_MEMORY_BYTES,
        }
    }
}

/// What a diagnosis of `samples` samples of `model` will hold (bytes), by
/// part of the candidate library: one value per sample, joint and column
/// (twice: the columns and their fitted copies), and the compliance
/// searches' linearisation (per sample: M, ∂τ/∂q, ∂τ/∂q̇ and one ∂M/∂sᵢ
/// per joint, n³ in all) and the node sets its simulations are solved on
/// ([`compliance::NODE_SETS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Friction, offset, gain, delay, cogging and payload columns (~12 per joint).
    pub base: u64,
    /// The link and rotor inertia candidates (10 columns per body).
    pub inertial: u64,
    /// The elasticity and backlash searches' linearisation.
    pub compliance: u64,
}

/// The [`MemoryEstimate`] of diagnosing `samples` samples of `model`.
pub fn memory_estimate(model: &Model, samples: usize) -> MemoryEstimate {
    let (n, nb) = (model.dof() as u64, model.num_bodies() as u64);
    let per_column = 8 * 2 * samples as u64 * n;
    MemoryEstimate {
        base: per_column * (12 * n + 10),
        inertial: per_column * 10 * nb,
        compliance: 8
            * samples as u64
            * (3 * n * n
                + n * n * n
                + n * n
                + 4 * n
                + compliance::NODE_SETS * compliance::node_values(n as usize)),
    }
}

/// Which parts of the library fit in `limit` bytes: the base must, the
/// inertial candidates and then the compliance searches are left out (with
/// a warning each) when they do not.
fn plan(
    est: MemoryEstimate,
    limit: u64,
    warnings: &mut Vec<String>,
) -> Result<(bool, bool), DiagnoseError> {
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    if est.base > limit {
        return Err(DiagnoseError::TooLarge {
            needed_gib: gib(est.base),
            limit_gib: gib(limit),
        });
    }
    let inertial = est.base + est.inertial <= limit;
    let used = est.base + if inertial { est.inertial } else { 0 };
    let compliance = used + est.compliance <= limit;
    let mut skip = |what: &str, bytes: u64| {
        warnings.push(format!(
            "{what}: not considered: it needs {:.2} GiB beyond the {:.2} GiB limit (fewer samples or joints, or a higher limit)",
            gib(bytes),
            gib(limit)
        ));
    };
    if !inertial {
        skip("link_inertia, rotor_inertia", est.inertial);
    }
    if !compliance {
        skip("elasticity, backlash", est.compliance);
    }
    Ok((inertial, compliance))
}

impl DiagnoseOptions {
    /// `train_fraction` of the samples (from the start) fit, in [0.1, 0.9];
    /// at most `max_effects` (≥ 1) effects are accepted; the held-out block
    /// test uses `blocks` (2 … 1000) blocks.
    pub fn new(
        train_fraction: f64,
        max_effects: usize,
        blocks: usize,
    ) -> Result<Self, DiagnoseError> {
        if !(train_fraction >= 0.1 && train_fraction <= 0.9) {
            return Err(DiagnoseError::Option {
                option: "train_fraction",
                value: train_fraction,
                message: "must be in [0.1, 0.9] (both parts need samples)",
            });
        }
        if max_effects == 0 {
            return Err(DiagnoseError::Option {
                option: "max_effects",
                value: 0.0,
                message: "must be at least 1",
            });
        }
        if !(2..=1000).contains(&blocks) {
            return Err(DiagnoseError::Option {
                option: "blocks",
                value: blocks as f64,
                message: "must be in 2 … 1000",
            });
        }
        Ok(Self {
            train_fraction,
            max_effects,
            blocks,
            max_memory_bytes: DEFAULT_MAX_MEMORY_BYTES,
        })
    }

    /// Fraction of the samples (from the start) used for fitting.
    pub fn train_fraction(&self) -> f64 {
        self.train_fraction
    }

    /// At most this many effects are accepted.
    pub fn max_effects(&self) -> usize {
        self.max_effects
    }

    /// Blocks of the held-out block test.
    pub fn blocks(&self) -> usize {
        self.blocks
    }

    /// The memory the diagnosis may plan for ([`memory_estimate`]): beyond
    /// it the inertial candidates and the compliance searches are left out
    /// (with a warning each) and, if the rest of the library does not fit,
    /// the diagnosis is refused before it starts.
    pub fn with_max_memory(mut self, bytes: u64) -> Self {
        self.max_memory_bytes = bytes;
        self
    }

    /// The memory limit (bytes).
    pub fn max_memory(&self) -> u64 {
        self.max_memory_bytes
    }
}

/// One candidate's evaluation in one round.
#[derive(Clone, Debug, Serialize)]
pub struct EffectReport {
    /// Effect name.
    pub effect: String,
    /// The chosen nonlinear parameter, if any (for `joint_offset`, the
    /// offsets fitted).
    pub detail: String,
    /// `joint_offset` only: the encoder zero offset δ_j fitted per joint
    /// (rad, or m for a prismatic joint; true q = measured q + δ).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint_offsets: Option<Vec<f64>>,
    /// Selection round (1-based).
    pub round: usize,
    /// Joints whose held-out RMS it reduces by more than 1 %.
    pub joints: Vec<String>,
    /// Number of fitted parameters.
    pub params: usize,
    /// Held-out RMS per joint before (current model) (N·m).
    pub heldout_rms_before: Vec<f64>,
    /// Held-out RMS per joint with the effect added (N·m).
    pub heldout_rms_after: Vec<f64>,
    /// ΔBIC on the training part (negative: better).
    pub delta_bic: f64,
    /// Block-test z score of the held-out improvement.
    pub z: f64,
    /// Accepted into the model.
    pub accepted: bool,
    /// Candidates that explain the same within noise.
    pub tied_with: Vec<String>,
    /// Why its fitted parameters are physically doubtful, if they are: a
    /// nonlinear parameter at the edge of its grid, an encoder offset beyond
    /// 0.2 rad. An accepted effect with a flag is also a warning.
    pub implausible: Option<String>,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// Joint names.
    pub joints: Vec<String>,
    /// Where the gap lies (held-out residual of the nominal model).
    #[serde(rename = "where")]
    pub where_: Vec<JointWhere>,
    /// One line per joint.
    pub summary: Vec<String>,
    /// Candidates per round, best first.
    pub ranked_effects: Vec<EffectReport>,
    /// Accepted effects in order.
    pub accepted: Vec<String>,
    /// Held-out RMS per joint of the nominal model (N·m).
    pub heldout_rms_nominal: Vec<f64>,
    /// Held-out RMS per joint after the accepted effects (N·m).
    pub heldout_rms_final: Vec<f64>,
    /// Noise floor per joint (N·m).
    pub noise_floor: Vec<f64>,
    /// Share of the gap above the noise floor closed, per joint.
    pub gap_closed: Vec<f64>,
    /// A remainder above the noise floor is left that no candidate explains.
    pub unexplained: bool,
    /// Where the unexplained remainder lies.
    pub unexplained_where: Vec<String>,
    /// Candidates that could not be evaluated and why (a failed fit, a
    /// compliance hypothesis that did not simulate).
    pub warnings: Vec<String>,
    /// Held-out signals and residuals for plots (not serialised).
    #[serde(skip)]
    pub heldout: HeldOut,
}

impl Diagnosis {
    /// The first report of `effect` in [`Self::ranked_effects`] (listed by
    /// round: its report of round 1), if it was evaluated.
    pub fn effect(&self, effect: &str) -> Option<&EffectReport> {
        self.ranked_effects.iter().find(|e| e.effect == effect)
    }
}

/// The held-out part's signals and residuals, per joint (for plots).
#[derive(Clone, Debug, Default)]
pub struct HeldOut {
    /// Time (s).
    pub t: Vec<f64>,
    /// Positions per joint.
    pub q: Vec<Vec<f64>>,
    /// Velocities per joint.
    pub qd: Vec<Vec<f64>>,
    /// Residual of the nominal model per joint.
    pub nominal: Vec<Vec<f64>>,
    /// Residual after the accepted effects per joint.
    pub after: Vec<Vec<f64>>,
}

/// The where-analysis of every joint's held-out residual.
fn where_of(split: &Split, data: &Dataset, r: &[f64]) -> Vec<JointWhere> {
    let val = data.slice(split.first_heldout..split.samples);
    let fs = (split.samples - 1) as f64 / (data.t[split.samples - 1] - data.t[0]);
    (0..split.joints)
        .map(|i| {
            let col = |v: &Vec<Vec<f64>>| v.iter().map(|x| x[i]).collect::<Vec<f64>>();
            analyse_joint(
                &data.joints[i],
                &split.heldout_of(r, i),
                &col(&val.q),
                &col(&val.qd),
                &col(&val.qdd),
                &col(&val.tau),
                fs,
            )
        })
        .collect()
}

/// The candidate library's columns for this data. The compliance
/// hypotheses are nonlinear: fitted once, to the nominal residual on the
/// training part, then offered as per-joint columns; one that cannot be
/// fitted is left out with a warning.
fn library(
    model: &Model,
    friction: &Friction,
    data: &Dataset,
    (r, split, (with_inertial, with_compliance)): (&[f64], &Split, (bool, bool)),
    warnings: &mut Vec<String>,
) -> Result<Vec<Vec<Columns>>, DiagnoseError> {
    let applies = Candidate::Effect(Effect::Elasticity)
        .inapplicable(model)
        .is_none();
    let lin = if with_compliance && applies {
        compliance::Linearisation::new(model, data).map_err(|e| {
            warnings.push(format!(
                "elasticity, backlash: no linearisation of the link dynamics: {e}"
            ));
        })
    } else {
        Err(())
    };
    let proposed: Vec<Candidate> = Candidate::ALL
        .iter()
        .copied()
        .filter(|c| match c.inapplicable(model) {
            Some(why) => {
                warnings.push(format!("{}: {why}", c.name()));
                false
            }
            None => true,
        })
        .collect();
    let one = |c: Candidate| -> Built {
        let inertial = matches!(
            c,
            Candidate::LinkInertia | Candidate::Effect(Effect::RotorInertia)
        );
        if inertial && !with_inertial {
            return (Ok(vec![]), None);
        }
        if !c.is_compliance() {
            return (build(c, model, friction, data), None);
        }
        let Ok(lin) = &lin else {
            return (Ok(vec![]), None);
        };
        let backlash = c == Candidate::Effect(Effect::Backlash);
        let fitted = compliance::fit(lin, r, split.first_heldout, backlash)
            .and_then(|f| compliance::columns(c, lin, &f));
        let warning = fitted.is_none().then(|| {
            format!(
                "{}: {}",
                c.name(),
                FitError::Compliance("no hypothesis of the search could be simulated")
            )
        });
        (Ok(fitted.into_iter().collect()), warning)
    };
    let built = build_all(&proposed, |c| {
        let (columns, warning) = one(c);
        // the Gram matrices the selection rounds reuse, while cores are free
        let columns = columns.inspect(|vs| vs.iter().for_each(|v| v.warm_gram(&split.train)));
        (columns, warning)
    });
    // the warnings are kept in the library's order
    built
        .into_iter()
        .map(|(columns, warning)| {
            warnings.extend(warning);
            columns
        })
        .collect()
}

/// A candidate's columns, or why not, and a warning.
type Built = (Result<Vec<Columns>, DiagnoseError>, Option<String>);

/// `one` of every candidate, in parallel, returned in `proposed`'s order.
/// The compliance searches, which take most of the time, start first (the
/// backlash search, the longest, before elasticity); the other candidates
/// are built on whichever core is free.
fn build_all(proposed: &[Candidate], one: impl Fn(Candidate) -> Built + Sync) -> Vec<Built> {
    let mut order: Vec<usize> = (0..proposed.len()).collect();
    order.sort_by_key(|&j| {
        let c = proposed[j];
        (!c.is_compliance(), c != Candidate::Effect(Effect::Backlash))
    });
    let slots: Vec<std::sync::OnceLock<Built>> =
        (0..proposed.len()).map(|_| Default::default()).collect();
    rayon::scope_fifo(|s| {
        for &j in &order {
            let (one, slots) = (&one, &slots);
            s.spawn_fifo(move |_| {
                let _ = slots[j].set(one(proposed[j]));
            });
        }
    });
    // (the scope waits for every job, so each slot is set)
    let unset = |c: Candidate| (Ok(vec![]), Some(format!("{}: not built", c.name())));
    slots
        .into_iter()
        .zip(proposed)
        .map(|(s, &c)| s.into_inner().unwrap_or_else(|| unset(c)))
        .collect()
}

/// Forward selection: each round scores every candidate not yet accepted
/// against the current residual and accepts the chosen one (updating the
/// residual) until nothing is significant. Returns the ranked reports, the
/// accepted names and the final residual.
fn forward_selection(
    library: &[Vec<Columns>],
    mut r: Vec<f64>,
    split: &Split,
    opts: &DiagnoseOptions,
    names: &[String],
    warnings: &mut Vec<String>,
) -> (Vec<EffectReport>, Vec<String>, Vec<f64>) {
    let mut ranked = vec![];
    let mut accepted: Vec<String> = vec![];
    for round in 1..=opts.max_effects {
        let before = rms_per_joint(&r[split.heldout.clone()], split.joints);
        // scored in parallel; the warnings are kept in the library's order
        let scored: Vec<(Option<Evaluation>, Vec<String>)> = library
            .par_iter()
            .filter(|v| {
                v.first()
                    .is_some_and(|c| !accepted.iter().any(|a| a == c.name()))
            })
            .map(|v| {
                let mut w = vec![];
                (evaluate(v, split, &r, round, opts.blocks, names, &mut w), w)
            })
            .collect();
        let mut evals: Vec<Evaluation> = vec![];
        for (e, w) in scored {
            warnings.extend(w);
            evals.extend(e);
        }
        let Some((chosen, tied)) = choose(&mut evals, &before) else {
            ranked.extend(evals.into_iter().map(|e| e.report));
            break;
        };
        let tied_names = tied
            .iter()
            .map(|&j| evals[j].report.effect.clone())
            .collect();
        let e = &mut evals[chosen];
        if let Some(why) = &e.report.implausible {
            warnings.push(format!(
                "round {round}: accepted '{}' although {why}",
                e.report.effect
            ));
        }
        e.report.accepted = true;
        e.report.tied_with = tied_names;
        r = e.after.clone();
        accepted.push(e.report.effect.clone());
        ranked.push(e.report.clone());
        ranked.extend(
            evals
                .into_iter()
                .enumerate()
                .filter(|(j, _)| *j != chosen)
                .map(|(_, e)| e.report),
        );
    }
    (ranked, accepted, r)
}

/// Share of the gap above the noise floor closed, per joint.
fn gap_closed(nominal: &[f64], last: &[f64], floor: &[f64]) -> Vec<f64> {
    (0..nominal.len())
        .map(|i| {
            if nominal[i] > floor[i] {
                ((nominal[i] - last[i]) / (nominal[i] - floor[i])).clamp(-1.0, 1.0)
            } else {
                1.0
            }
        })
        .collect()
}

/// The held-out signals and residuals, per joint, for plots.
fn held_out(split: &Split, data: &Dataset, nominal: &[f64], after: &[f64]) -> HeldOut {
    let val = data.slice(split.first_heldout..split.samples);
    let n = split.joints;
    let per_joint = |r: &[f64]| (0..n).map(|i| split.heldout_of(r, i)).collect();
    HeldOut {
        t: val.t.clone(),
        q: (0..n)
            .map(|i| val.q.iter().map(|x| x[i]).collect())
            .collect(),
        qd: (0..n)
            .map(|i| val.qd.iter().map(|x| x[i]).collect())
            .collect(),
        nominal: per_joint(nominal),
        after: per_joint(after),
    }
}

/// Diagnoses `data` against the nominal `model` + `friction`.
pub fn diagnose(
    model: &Model,
    friction: &Friction,
    data: &Dataset,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    let n = model.dof();
    if data.tau.len() != data.len() || data.len() < MIN_SAMPLES {
        return Err(DiagnoseError::TooFewSamples {
            needed: MIN_SAMPLES,
            found: if data.tau.len() == data.len() {
                data.len()
            } else {
                0
            },
        });
    }
    let names: Vec<String> = model.joint_names().iter().map(|s| s.to_string()).collect();
    if data.joints != names {
        return Err(DiagnoseError::Joints {
            expected: names,
            found: data.joints.clone(),
        });
    }
    if (0..n).all(|i| data.q.iter().all(|q| q[i] == data.q[0][i])) {
        return Err(DiagnoseError::NoMotion);
    }
    let mut warnings = vec![];
    let parts = plan(
        memory_estimate(model, data.len()),
        opts.max_memory_bytes,
        &mut warnings,
    )?;
    let split = Split::new(data.len(), n, opts.train_fraction);
    let pred = predict_torques(model, friction, &data.q, &data.qd, &data.qdd)
        .map_err(DiagnoseError::Predict)?;
    let r_nominal: Vec<f64> = flat(&data.tau)
        .iter()
        .zip(flat(&pred))
        .map(|(a, b)| a - b)
        .collect();
    let where_nominal = where_of(&split, data, &r_nominal);
    let noise_floor: Vec<f64> = where_nominal.iter().map(|w| w.noise_floor).collect();
    let nominal = rms_per_joint(&r_nominal[split.heldout.clone()], n);
    let library = library(
        model,
        friction,
        data,
        (&r_nominal, &split, parts),
        &mut warnings,
    )?;
    let (ranked, accepted, r) = forward_selection(
        &library,
        r_nominal.clone(),
        &split,
        opts,
        &data.joints,
        &mut warnings,
    );
    let final_rms = rms_per_joint(&r[split.heldout.clone()], n);
    let where_final = where_of(&split, data, &r);
    let unexplained: Vec<usize> = (0..n)
        .filter(|&i| final_rms[i] > 1.15 * noise_floor[i] && final_rms[i] - noise_floor[i] > 0.05)
        .collect();
    let numbers = [&nominal, &final_rms, &noise_floor];
    if let Some(k) = numbers
        .iter()
        .position(|v| !v.iter().all(|x| x.is_finite()))
    {
        return Err(DiagnoseError::NonFinite {
            what: ["the nominal RMS", "the final RMS", "the noise floor"][k],
        });
    }
    Ok(Diagnosis {
        joints: data.joints.clone(),
        summary: where_nominal.iter().map(summarise).collect(),
        where_: where_nominal,
        ranked_effects: ranked,
        accepted,
        gap_closed: gap_closed(&nominal, &final_rms, &noise_floor),
        heldout_rms_nominal: nominal,
        heldout_rms_final: final_rms,
        noise_floor,
        unexplained: !unexplained.is_empty(),
        unexplained_where: unexplained
            .iter()
            .map(|&i| summarise(&where_final[i]))
            .collect(),
        warnings,
        heldout: held_out(&split, data, &r_nominal, &r),
    })
}
