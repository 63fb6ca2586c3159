//! A floating-base robot's diagnosis: where its nominal model's residual
//! (`measured − Y θ`, every row of [`identify::floating`](crate::identify::floating))
//! rises above the noise floor, and which unmodelled effect explains it.
//! Each log is split in time (the first 70 % to fit, the rest held out);
//! each candidate adds columns to the nominal model, fitted by weighted
//! least squares (each row by 1/floor²) on the fitting part, and is scored
//! on the held-out part by the share of the gap above the floor it closes.
//! The candidates ([`FloatingEffect`]): joint friction (viscous and Coulomb
//! per joint), a constant offset of each contact wrench, a payload on the
//! base (its ten parameters), and every body's parameters (the catch-all:
//! the CAD is off). Forward selection: in each round every candidate not
//! yet accepted is fitted together with those accepted, and the simplest
//! (fewest parameters) whose closure is within 90 % of the round's best is
//! accepted if it closes at least half of the gap the round began with,
//! while that gap is one (on average `(rms/floor)² − 1 ≥ 0.05` a row).

use super::error::DiagnoseError;
use crate::data::Dataset;
use crate::dynamics::{ContactWrench, DEFAULT_STRIBECK_VELOCITY, Data, FrictionTerm, Model};
use crate::identify::floating_fit::residual;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// The joint friction candidate's terms (the simulator's
/// [`FloatingEffects::joint_friction`](crate::sim::floating::FloatingEffects)).
const JOINT_FRICTION: [FrictionTerm; 2] = [FrictionTerm::Viscous, FrictionTerm::Coulomb];

/// The unmodelled effects a floating-base diagnosis tries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FloatingEffect {
    /// Viscous and Coulomb friction of every joint (the joint rows).
    JointFriction,
    /// A constant bias of every contact's measured wrench.
    WrenchOffset,
    /// The base's ten parameters off (a battery, a payload).
    Payload,
    /// Every body's parameters off.
    BodyParameters,
}

impl FloatingEffect {
    /// Every candidate (tried, then ranked by their number of parameters:
    /// the simplest first).
    pub const ALL: [FloatingEffect; 4] = [
        FloatingEffect::WrenchOffset,
        FloatingEffect::Payload,
        FloatingEffect::JointFriction,
        FloatingEffect::BodyParameters,
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            FloatingEffect::JointFriction => "joint_friction",
            FloatingEffect::WrenchOffset => "wrench_offset",
            FloatingEffect::Payload => "payload",
            FloatingEffect::BodyParameters => "body_parameters",
        }
    }
}

/// One candidate's fit and score.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FloatingCandidate {
    /// The effect.
    pub effect: FloatingEffect,
    /// Its parameters, by name, as fitted.
    pub values: Vec<(String, f64)>,
    /// Held-out residual RMS per row with it added (to the effects
    /// accepted in earlier rounds).
    pub held_out: Vec<f64>,
    /// The share of the nominal model's held-out gap above the floor that
    /// it and the effects accepted before close together (≤ 1).
    pub gap_closed: f64,
}

/// One round of the forward selection.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FloatingRound {
    /// Every candidate tried, the best closure first.
    pub candidates: Vec<FloatingCandidate>,
    /// The one accepted, if any (the last round accepts none).
    pub accepted: Option<FloatingEffect>,
}

/// A floating-base diagnosis.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FloatingDiagnosis {
    /// The rows diagnosed: `base_force_<x|y|z>`, `base_moment_<…>`, then
    /// `tau_<joint>` when every log has joint torques.
    pub rows: Vec<String>,
    /// Per row, the noise floor: the RMS of the residual's first
    /// differences over √2 (white noise; a lower bound on filtered data).
    pub floor: Vec<f64>,
    /// Per row, the nominal model's held-out residual RMS.
    pub held_out: Vec<f64>,
    /// Samples fitted on and held out.
    pub samples: [usize; 2],
    /// The forward selection's rounds.
    pub rounds: Vec<FloatingRound>,
    /// The effects accepted, in order.
    pub accepted: Vec<FloatingEffect>,
}

impl FloatingDiagnosis {
    /// The last accepted effect's fit (fitted with every effect accepted
    /// before it), if any effect is accepted.
    pub fn final_fit(&self) -> Option<&FloatingCandidate> {
        let round = self.rounds.iter().rev().find(|r| r.accepted.is_some())?;
        round
            .candidates
            .iter()
            .find(|c| Some(c.effect) == round.accepted)
    }

    /// Each accepted effect's fit, in order of acceptance.
    pub fn accepted_fits(&self) -> Vec<&FloatingCandidate> {
        (self.rounds.iter())
            .filter_map(|r| r.candidates.iter().find(|c| Some(c.effect) == r.accepted))
            .collect()
    }
}

/// The share of each log fitted on.
const TRAIN_SHARE: f64 = 0.7;
/// The smallest gap a round looks into: the mean over the rows of
/// `max(0, (rms/floor)² − 1)`.
const MIN_GAP: f64 = 0.05;
/// The fewest samples a log may have (10 held out).
const MIN_SAMPLES: usize = 32;

/// The data as the diagnosis sees them: per log, every sample's nominal
/// residual (its first `rows` rows) and where the held-out part starts.
struct Split<'a> {
    ff: &'a Model,
    logs: &'a [Dataset],
    rows: usize,
    residuals: Vec<Vec<DVector<f64>>>,
    cuts: Vec<usize>,
    /// 1 / floor² per row.
    weights: Vec<f64>,
}

/// Diagnoses `logs` against the nominal model `ff` whose regressor
/// parameters are `theta` (bodies then friction columns).
pub fn diagnose_floating(
    ff: &Model,
    theta: &[f64],
    logs: &[Dataset],
) -> Result<FloatingDiagnosis, DiagnoseError> {
    let mut split = Split::new(ff, theta, logs)?;
    let floor = split.floor();
    split.weights = floor.iter().map(|f| 1.0 / f.max(1e-9).powi(2)).collect();
    let held_out = split.held_out_rms(|_, _, _| Ok(None))?;
    let (joints, contacts) = (split.rows > 6, !logs[0].contacts.is_empty());
    let applicable: Vec<FloatingEffect> = (FloatingEffect::ALL.iter().copied())
        .filter(|e| joints || *e != FloatingEffect::JointFriction)
        .filter(|e| contacts || *e != FloatingEffect::WrenchOffset)
        .collect();
    let (mut rounds, mut accepted, mut closed) = (vec![], vec![], 0.0);
    loop {
        let round = split.round(&applicable, &accepted, (&floor, &held_out), closed)?;
        let next = round.accepted;
        rounds.push(round);
        match next {
            Some(e) => {
                accepted.push(e);
                let r = rounds.last().expect("just pushed");
                closed = r
                    .candidates
                    .iter()
                    .find(|c| c.effect == e)
                    .map_or(closed, |c| c.gap_closed);
            }
            None => break,
        }
    }
    Ok(FloatingDiagnosis {
        rows: row_names(ff, split.rows),
        floor,
        held_out,
        samples: split.samples(),
        rounds,
        accepted,
    })
}

/// The contacts of a log, by frame and axes.
fn contacts_of(l: &Dataset) -> Vec<(String, crate::dynamics::WrenchFrame)> {
    (l.contacts.iter())
        .map(|c| (c.frame.clone(), c.expressed))
        .collect()
}

impl<'a> Split<'a> {
    /// Every log's nominal residual (all rows when every log has joint
    /// torques, else the base's) and its split; the logs must have the same
    /// contacts and at least 34 samples each.
    fn new(ff: &'a Model, theta: &[f64], logs: &'a [Dataset]) -> Result<Self, DiagnoseError> {
        let first = logs.first().ok_or(DiagnoseError::NoLogs)?;
        let joints = logs.iter().all(Dataset::has_torques);
        let rows = if joints { ff.nv() } else { 6 };
        let mut split = Split {
            ff,
            logs,
            rows,
            residuals: vec![],
            cuts: vec![],
            weights: vec![],
        };
        for (i, log) in logs.iter().enumerate() {
            let l = i + 1;
            log.check(ff)
                .map_err(|source| DiagnoseError::Log { log: l, source })?;
            if contacts_of(log) != contacts_of(first) {
                return Err(DiagnoseError::Contacts {
                    log: l,
                    found: format!("{:?}", contacts_of(log)),
                    first: format!("{:?}", contacts_of(first)),
                });
            }
            let mut data = Data::new(ff);
            let r = (0..log.len())
                .map(|k| {
                    residual(ff, &mut data, theta, log, k).map(|r| r.rows(0, rows).into_owned())
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(|source| DiagnoseError::Residual { log: l, source })?;
            if log.len() < MIN_SAMPLES {
                return Err(DiagnoseError::ShortLog {
                    log: l,
                    found: log.len(),
                    needed: MIN_SAMPLES,
                });
            }
            let cut = (TRAIN_SHARE * log.len() as f64).round() as usize;
            split.residuals.push(r);
            split.cuts.push(cut);
        }
        Ok(split)
    }
}

/// `base_force_x…`, `base_moment_x…`, `tau_<joint>…` (the first `rows`).
fn row_names(ff: &Model, rows: usize) -> Vec<String> {
    let mut v: Vec<String> = ["force", "moment"]
        .iter()
        .flat_map(|k| ["x", "y", "z"].map(|a| format!("base_{k}_{a}")))
        .collect();
    v.extend(ff.joint_names().iter().map(|j| format!("tau_{j}")));
    v.truncate(rows);
    v
}

/// The share of the gap above the floor: `Σ max(0, rms² − floor²) / floor²`.
fn excess(rms: &[f64], floor: &[f64]) -> f64 {
    (rms.iter().zip(floor))
        .map(|(r, f)| (r * r - f * f).max(0.0) / f.max(1e-9).powi(2))
        .sum()
}

impl Split<'_> {
    fn samples(&self) -> [usize; 2] {
        let train: usize = self.cuts.iter().sum();
        let all: usize = self.logs.iter().map(|l| l.len()).sum();
        [train, all - train]
    }

    /// Per row, RMS of the residual's first differences / √2 (every sample).
    fn floor(&self) -> Vec<f64> {
        let (mut sum, mut count) = (vec![0.0; self.rows], 0usize);
        for r in &self.residuals {
            for w in r.windows(2) {
                sum.iter_mut()
                    .zip((&w[1] - &w[0]).iter())
                    .for_each(|(s, d)| *s += d * d);
                count += 1;
            }
        }
        sum.iter()
            .map(|s| (s / count.max(1) as f64 / 2.0).sqrt())
            .collect()
    }
}

impl Split<'_> {
    /// Every (log, first sample, end) chunk of the fitting (`train`) or
    /// held-out part.
    fn chunks(&self, train: bool) -> Vec<(usize, usize, usize)> {
        let mut v = vec![];
        for (l, log) in self.logs.iter().enumerate() {
            let range = if train {
                0..self.cuts[l]
            } else {
                self.cuts[l]..log.len()
            };
            for s in range.clone().step_by(256) {
                v.push((l, s, (s + 256).min(range.end)));
            }
        }
        v
    }

    /// Per row, the held-out RMS of the residual less `fix(log, k)`'s
    /// correction (`None`: none).
    fn held_out_rms<F>(&self, fix: F) -> Result<Vec<f64>, DiagnoseError>
    where
        F: Fn(&mut Data, usize, usize) -> Result<Option<DVector<f64>>, DiagnoseError> + Sync,
    {
        let parts = (self.chunks(false).par_iter())
            .map(|&(l, s0, s1)| {
                let mut sum = vec![0.0; self.rows];
                let mut data = Data::new(self.ff);
                for k in s0..s1 {
                    let mut r = self.residuals[l][k].clone();
                    if let Some(c) = fix(&mut data, l, k)? {
                        r -= c;
                    }
                    sum.iter_mut().zip(r.iter()).for_each(|(s, x)| *s += x * x);
                }
                Ok(sum)
            })
            .collect::<Result<Vec<_>, DiagnoseError>>()?;
        let n = self.samples()[1] as f64;
        let mut sum = vec![0.0; self.rows];
        for p in parts {
            sum.iter_mut().zip(&p).for_each(|(a, b)| *a += b);
        }
        Ok(sum.iter().map(|s| (s / n).sqrt()).collect())
    }

    /// The effect's columns at sample k of log l (`rows` × its parameters).
    fn columns(
        &self,
        effect: FloatingEffect,
        data: &mut Data,
        (l, k): (usize, usize),
    ) -> Result<DMatrix<f64>, DiagnoseError> {
        let (ff, log) = (self.ff, &self.logs[l]);
        let (nv, n) = (ff.nv(), ff.dof());
        let fail = |source| DiagnoseError::Regressor { sample: k, source };
        let (q, v, a) = log.state(k);
        let x = match effect {
            FloatingEffect::JointFriction => {
                let mut x = DMatrix::zeros(nv, 2 * n);
                for (t, term) in JOINT_FRICTION.iter().enumerate() {
                    for j in 0..n {
                        x[(6 + j, t * n + j)] =
                            term.basis(v[6 + j], 0.0, DEFAULT_STRIBECK_VELOCITY);
                    }
                }
                x
            }
            FloatingEffect::WrenchOffset => {
                let mut x = DMatrix::zeros(nv, 6 * log.contacts.len());
                for (c, ch) in log.contacts.iter().enumerate() {
                    let frame = ff.frame_index(&ch.frame).map_err(fail)?;
                    for axis in 0..6 {
                        let mut wrench = [0.0; 6];
                        wrench[axis] = 1.0;
                        let w = ContactWrench {
                            frame,
                            wrench,
                            expressed: ch.expressed,
                        };
                        x.set_column(
                            6 * c + axis,
                            &ff.contact_force(data, &q, &[w]).map_err(fail)?,
                        );
                    }
                }
                x
            }
            FloatingEffect::Payload | FloatingEffect::BodyParameters => {
                let bodies = if effect == FloatingEffect::Payload {
                    1
                } else {
                    ff.num_bodies()
                };
                crate::dynamics::regressor(ff, data, &q, &v, &a)
                    .map_err(fail)?
                    .columns(0, 10 * bodies)
                    .into_owned()
            }
        };
        Ok(x.rows(0, self.rows).into_owned())
    }
}

impl Split<'_> {
    /// One round: every applicable effect not yet accepted fitted with
    /// those accepted; the simplest within 90 % of the best accepted if it
    /// closes half of the gap left (`closed`: the share closed before).
    fn round(
        &self,
        applicable: &[FloatingEffect],
        accepted: &[FloatingEffect],
        (floor, before): (&[f64], &[f64]),
        closed: f64,
    ) -> Result<FloatingRound, DiagnoseError> {
        let mut candidates = (applicable.iter())
            .filter(|e| !accepted.contains(e))
            .map(|&e| self.candidate(accepted, e, (floor, before)))
            .collect::<Result<Vec<_>, _>>()?;
        candidates.sort_by_key(|c| c.values.len());
        let best = (candidates.iter().map(|c| c.gap_closed)).fold(f64::NEG_INFINITY, f64::max);
        let step = |g: f64| (g - closed) / (1.0 - closed).max(1e-12);
        // half of what is left, when what is left is a gap (on average
        // (rms/floor)² − 1 ≥ 0.05 a row), not the noise in one closed
        let left = (1.0 - closed) * excess(before, floor) / floor.len() as f64;
        let pick = (step(best) >= 0.5 && left >= MIN_GAP)
            .then(|| {
                candidates
                    .iter()
                    .find(|c| step(c.gap_closed) >= 0.9 * step(best))
            })
            .flatten()
            .map(|c| c.effect);
        candidates.sort_by(|a, b| b.gap_closed.total_cmp(&a.gap_closed));
        Ok(FloatingRound {
            candidates,
            accepted: pick,
        })
    }

    /// `effect` fitted with the `accepted` ones on the fitting part
    /// (weighted least squares, the least-norm solution) and scored on the
    /// held-out part; its own parameters reported.
    fn candidate(
        &self,
        accepted: &[FloatingEffect],
        effect: FloatingEffect,
        (floor, before): (&[f64], &[f64]),
    ) -> Result<FloatingCandidate, DiagnoseError> {
        let mut set = accepted.to_vec();
        set.push(effect);
        let names: Vec<String> = set.iter().flat_map(|&e| self.value_names(e)).collect();
        let own = self.value_names(effect).len();
        let width = names.len();
        let parts = (self.chunks(true).par_iter())
            .map(|&(l, s0, s1)| {
                let mut data = Data::new(self.ff);
                let (mut g, mut b) = (DMatrix::zeros(width, width), DVector::zeros(width));
                for k in s0..s1 {
                    let x = self.columns_of(&set, &mut data, (l, k))?;
                    let mut xw = x.clone();
                    for (i, w) in self.weights.iter().enumerate() {
                        xw.row_mut(i).scale_mut(*w);
                    }
                    g += x.transpose() * &xw;
                    b += xw.transpose() * &self.residuals[l][k];
                }
                Ok((g, b))
            })
            .collect::<Result<Vec<_>, DiagnoseError>>()?;
        let (mut g, mut b) = (DMatrix::zeros(width, width), DVector::zeros(width));
        for (pg, pb) in parts {
            g += pg;
            b += pb;
        }
        let delta = least_norm(g, &b)?;
        let after = self
            .held_out_rms(|data, l, k| Ok(Some(self.columns_of(&set, data, (l, k))? * &delta)))?;
        let e0 = excess(before, floor);
        let values = names.into_iter().zip(delta.iter().copied());
        Ok(FloatingCandidate {
            effect,
            values: values.skip(width - own).collect(),
            gap_closed: if e0 > 0.0 {
                1.0 - excess(&after, floor) / e0
            } else {
                0.0
            },
            held_out: after,
        })
    }

    /// The columns of several effects side by side.
    fn columns_of(
        &self,
        effects: &[FloatingEffect],
        data: &mut Data,
        at: (usize, usize),
    ) -> Result<DMatrix<f64>, DiagnoseError> {
        let blocks = (effects.iter())
            .map(|&e| self.columns(e, data, at))
            .collect::<Result<Vec<_>, _>>()?;
        let width = blocks.iter().map(|b| b.ncols()).sum();
        let mut x = DMatrix::zeros(self.rows, width);
        let mut c = 0;
        for b in blocks {
            x.columns_mut(c, b.ncols()).copy_from(&b);
            c += b.ncols();
        }
        Ok(x)
    }

    /// The names of the effect's parameters, in column order.
    fn value_names(&self, effect: FloatingEffect) -> Vec<String> {
        let ff = self.ff;
        let joints = ff.joint_names();
        match effect {
            FloatingEffect::JointFriction => ["viscous", "coulomb"]
                .iter()
                .flat_map(|t| joints.iter().map(move |j| format!("{t}.{j}")))
                .collect(),
            FloatingEffect::WrenchOffset => (self.logs[0].contacts.iter())
                .flat_map(|c| {
                    [
                        "force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z",
                    ]
                    .map(|a| format!("{}.{a}", c.frame))
                })
                .collect(),
            FloatingEffect::Payload | FloatingEffect::BodyParameters => {
                let bodies = if effect == FloatingEffect::Payload {
                    1
                } else {
                    ff.num_bodies()
                };
                let mut names = ff.layout_of_rows(0..0).parameter_names();
                names.truncate(10 * bodies);
                names
            }
        }
    }
}

/// The least-norm solution of `G x = b` (G symmetric ⪰ 0), directions
/// below 1e-10 of its largest eigenvalue dropped.
fn least_norm(g: DMatrix<f64>, b: &DVector<f64>) -> Result<DVector<f64>, DiagnoseError> {
    if g.is_empty() {
        return Ok(DVector::zeros(0));
    }
    let svd = g.svd(true, true);
    let eps = 1e-10 * svd.singular_values.max();
    svd.solve(b, eps).map_err(|_| DiagnoseError::Fit {
        what: "a floating-base candidate's least squares (non-finite columns?)",
        source: super::error::FitError::Factorisation,
    })
}
