//! The friction law chosen from the training data (`--friction auto`).
//!
//! Every law of viscous + Coulomb friction with or without a torque
//! offset, load-dependent friction and Stribeck friction (its velocity one
//! of [`STRIBECK_VELOCITIES`]) is scored by cross-validation on the
//! training data alone — each file (segment) held out in turn when there
//! are several, else [`TIME_FOLDS`] blocks of time — as the identification
//! would fit it without constraints: the links' parameters and the law's
//! coefficients by least squares, `(1/n_s) Σ‖Y θ − τ‖² + w ‖π − π̂‖²` with
//! the prior and weight of the identification. One pass over the data
//! (`identify::choice_pass`) builds each fold's and joint's Gram matrix over
//! every candidate column (a joint's row has its links' columns and its
//! own friction columns); each law is then a solve of the folds' sums,
//! scored on the held-out fold by its quadratic form
//! (`identify::law_scores`). A law's score is the mean over joints of the
//! held-out RMS pooled over the folds. The chosen law's reduction comes
//! from the same pass ([`super::Identification::reduce_chosen`]).
//!
//! **Parsimony**: the law with the fewest terms whose score is within the
//! noise of the best's is chosen — within the noise when the mean over the
//! folds of its per-fold score minus the best's is at most the standard
//! error of those differences (the one-standard-error rule, applied to
//! paired differences) or [`MIN_GAIN`] of the best's score, whichever is
//! larger. The load term's basis is the size of the rigid torque of the
//! model's own bodies (the prior's, as given; the identification then
//! iterates it on its fit's): the measured torque would carry the held-out
//! fold's noise into its own prediction.

use super::choice_pass::{ChoicePass, Sums};
use super::choose_weight::{Folds, MIN_FOLD_SAMPLES, MIN_GAIN, TIME_FOLDS, held_out, within_noise};
use super::error::IdentifyError;
pub use super::law_scores::PriorTerm;
use super::law_scores::law_sse;
use super::warning::IdentifyWarning;
use crate::data::Dataset;
use crate::dynamics::{FrictionTerm, Model, regressor_row_columns};
use nalgebra::SMatrix;
use rayon::prelude::*;
use serde::Serialize;

/// The Stribeck velocities (rad/s) tried: a drive's breakaway region is a
/// few hundredths to a few tenths of a rad/s wide.
pub const STRIBECK_VELOCITIES: [f64; 4] = [0.02, 0.05, 0.1, 0.2];
/// The prior weights tried with each law when the weight is chosen too
/// (`--weight auto`): half-decades from 1e-6 to 1 (N²·m², the
/// regulariser's units).
pub const WEIGHTS: [f64; 13] = [
    1e-6, 3.16e-6, 1e-5, 3.16e-5, 1e-4, 3.16e-4, 1e-3, 3.16e-3, 1e-2, 3.16e-2, 1e-1, 3.16e-1, 1.0,
];
/// The candidate friction columns per joint, in order.
pub(crate) fn bases() -> Vec<(FrictionTerm, f64)> {
    let mut b = vec![
        (FrictionTerm::Viscous, 0.0),
        (FrictionTerm::Coulomb, 0.0),
        (FrictionTerm::Offset, 0.0),
        (FrictionTerm::Load, 0.0),
    ];
    b.extend(STRIBECK_VELOCITIES.map(|v| (FrictionTerm::Stribeck, v)));
    b
}

/// One candidate law and its cross-validated error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawScore {
    /// Its terms.
    pub terms: Vec<String>,
    /// Its Stribeck velocity (rad/s), with a Stribeck term.
    pub stribeck_velocity: Option<f64>,
    /// The prior's weight it was fitted with (N²·m², the regulariser's).
    pub weight: f64,
    /// Per joint, the held-out RMS pooled over the folds (N·m).
    pub heldout_rms: Vec<f64>,
    /// The mean over joints of `heldout_rms` (N·m).
    pub mean_rms: f64,
    /// Per fold, the mean over joints of that fold's held-out RMS (N·m).
    pub fold_rms: Vec<f64>,
}

/// The friction law chosen and the table it was chosen from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrictionChoice {
    /// How the training data were split.
    pub folds: Folds,
    /// Number of folds.
    pub k: usize,
    /// Every law tried.
    pub laws: Vec<LawScore>,
    /// The index of the lowest `mean_rms`.
    pub best: usize,
    /// The index of the law chosen.
    pub chosen: usize,
    /// Why, in words.
    pub rule: String,
    /// The pass over the training data the laws were scored from, whence
    /// the chosen law's reduction ([`super::Identification::reduce_chosen`]).
    #[serde(skip)]
    pub(crate) pass: Pass,
}

/// A [`FrictionChoice`]'s pass over its training data: kept to reduce the
/// chosen law's data without a second pass; not part of the choice's value
/// (choices compare equal whatever their passes).
#[derive(Clone, Default)]
pub(crate) struct Pass(pub(crate) Option<std::sync::Arc<ChoicePass>>);

impl PartialEq for Pass {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for Pass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            Some(p) => write!(f, "{p:?}"),
            None => write!(f, "no pass kept"),
        }
    }
}

impl FrictionChoice {
    /// The chosen law's terms.
    pub fn terms(&self) -> Vec<FrictionTerm> {
        (self.laws[self.chosen].terms.iter())
            .filter_map(|t| FrictionTerm::parse(t))
            .collect()
    }

    /// The chosen law's Stribeck velocity, if it has the term.
    pub fn stribeck_velocity(&self) -> Option<f64> {
        self.laws[self.chosen].stribeck_velocity
    }

    /// `model` with the chosen law's terms and Stribeck velocity.
    pub fn apply(&self, model: Model) -> Result<Model, crate::dynamics::DynamicsError> {
        let model = model.with_friction_terms(&self.terms());
        match self.stribeck_velocity() {
            Some(v) => model.with_stribeck_velocity(v),
            None => Ok(model),
        }
    }

    /// The prior's weight chosen with the law.
    pub fn weight(&self) -> f64 {
        self.laws[self.chosen].weight
    }

    /// Whether more than one weight was tried.
    pub fn weight_chosen(&self) -> bool {
        self.laws.iter().any(|l| l.weight != self.laws[0].weight)
    }

    /// The chosen law as indices of [`bases`].
    fn law_indices(&self) -> Vec<usize> {
        let law = &self.laws[self.chosen];
        let b = bases();
        (law.terms.iter())
            .filter_map(|name| {
                b.iter().position(|(t, v)| {
                    t.name() == name
                        && (*t != FrictionTerm::Stribeck || Some(*v) == law.stribeck_velocity)
                })
            })
            .collect()
    }
}

impl super::Identification<'_> {
    /// [`choose_friction`] for this identification's model, prior,
    /// regulariser and weight (the prior's when one is set, else none).
    pub fn choose_friction(&self, train: &Dataset) -> Result<FrictionChoice, IdentifyError> {
        self.choose_model(train, &[self.weight])
    }

    /// The weights [`Self::choose_model`] should try: [`WEIGHTS`] when the
    /// weight is to be chosen (`weight_auto`), else none (this
    /// identification's own). The Gram solves are a quadratic prior's
    /// objective exactly (Euclidean, pullback) and an entropic prior's
    /// second-order term at the prior (its pullback): the parsimony rule
    /// takes the strongest weight within the noise, where the fit stays
    /// nearest the prior and the quadratic is closest to the divergence.
    pub fn model_weights(&self, weight_auto: bool) -> &'static [f64] {
        match weight_auto {
            true => &WEIGHTS,
            false => &[],
        }
    }

    /// [`choose_friction`] with the prior's weight chosen with the law from
    /// `weights` (each > 0): the fewest terms first, then the strongest
    /// prior, within the noise of the best (module doc). Without a prior
    /// the weight is moot and only this identification's is tried.
    pub fn choose_model(
        &self,
        train: &Dataset,
        weights: &[f64],
    ) -> Result<FrictionChoice, IdentifyError> {
        self.fixed_base("Identification::choose_model")?;
        if let Some(&w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
            return Err(IdentifyError::WeightGrid {
                what: format!("{} is not positive and finite", crate::numfmt::short(w)),
            });
        }
        let own = [self.weight];
        let weights = match self.prior.is_empty() || weights.is_empty() {
            true => &own[..],
            false => weights,
        };
        let metric = match self.regularizer {
            super::Regularizer::Entropic | super::Regularizer::Pullback
                if !self.prior.is_empty() =>
            {
                super::pullback::metric(&self.prior, &self.layout.bodies)?
            }
            _ => vec![SMatrix::<f64, 10, 10>::identity(); self.prior.len() / 10],
        };
        let prior = PriorTerm {
            values: &self.prior,
            metric,
            mass_weight: self.mass_weight(),
        };
        choose_friction(self.model, train, &prior, weights)
    }

    /// [`choose_model`](Self::choose_model) as a default that may stand
    /// down: training data too short for the folds
    /// ([`IdentifyError::FoldTooSmall`]) keep the model's own law at this
    /// identification's weight, with the warning that says so, where an
    /// explicit choice would be an error.
    pub fn choose_model_or_keep(
        &self,
        train: &Dataset,
        weights: &[f64],
    ) -> Result<LawChoice, IdentifyError> {
        match self.choose_model(train, weights) {
            Ok(c) => Ok(LawChoice::Chosen(c)),
            Err(e @ IdentifyError::FoldTooSmall { .. }) => {
                let terms = self.model.friction_terms().iter();
                Ok(LawChoice::Kept(IdentifyWarning::LawNotChosen {
                    reason: e.to_string(),
                    terms: terms.map(|t| t.name().to_string()).collect(),
                    weight: self.weight,
                }))
            }
            Err(e) => Err(e),
        }
    }
}

impl super::Identification<'_> {
    /// [`reduce`](Self::reduce) of `train` for this identification, whose
    /// model has the law `choice` chose on the same `train`: made from the
    /// choice's pass over it (when `train` and the model's bodies are the
    /// ones the pass was made from, by a fingerprint of their values, and
    /// it kept what the law needs
    /// (`identify::choice_pass`)), else by a reduction. The pass is taken
    /// from `choice` (its rows freed once the reduction has what it needs).
    pub fn reduce_chosen(
        &self,
        train: &Dataset,
        choice: Option<&mut FrictionChoice>,
    ) -> Result<super::Reduced, IdentifyError> {
        let Some(c) = choice else {
            return self.reduce(train);
        };
        let law = c.law_indices();
        let links = self.model().clone().with_friction_terms(&[]);
        match c.pass.0.take() {
            Some(pass) if pass.made_from(&links, train) => {
                self.fixed_base("Identification::reduce_chosen")?;
                self.check_memory(train.len())?;
                match pass.reduced(self.model(), &law)? {
                    Some(red) => Ok(red),
                    None => self.reduce(train),
                }
            }
            _ => self.reduce(train),
        }
    }
}

/// The law [`choose_model_or_keep`](super::Identification::choose_model_or_keep) chose, or why the
/// model's own was kept.
#[derive(Clone, Debug, PartialEq)]
pub enum LawChoice {
    /// Chosen from the data.
    Chosen(FrictionChoice),
    /// The model's own law kept at the identification's weight
    /// ([`IdentifyWarning::LawNotChosen`]).
    Kept(IdentifyWarning),
}

/// A law: which of [`bases`] it has.
fn laws() -> Vec<Vec<usize>> {
    let mut out = vec![];
    for offset in [false, true] {
        for load in [false, true] {
            for stribeck in [None, Some(4), Some(5), Some(6), Some(7)] {
                let mut l = vec![0, 1];
                l.extend(offset.then_some(2));
                l.extend(load.then_some(3));
                l.extend(stribeck);
                out.push(l);
            }
        }
    }
    out
}

/// Chooses the friction law for `model`'s links and rotors (its own
/// friction terms ignored) on `train` (module doc), with the
/// identification's `prior` and each of `weights` (one law per weight).
pub fn choose_friction(
    model: &Model,
    train: &Dataset,
    prior: &PriorTerm,
    weights: &[f64],
) -> Result<FrictionChoice, IdentifyError> {
    if train.tau.len() != train.len() || train.is_empty() {
        return Err(IdentifyError::NoTrainingData {
            samples: train.len(),
            torques: train.tau.len(),
        });
    }
    let links = model.clone().with_friction_terms(&[]);
    let (kind, ranges) = held_out(train, TIME_FOLDS);
    let lens: Vec<usize> = (ranges.iter())
        .map(|parts| parts.iter().map(|r| r.len()).sum())
        .collect();
    if let Some((fold, &h)) = (lens.iter().enumerate()).find(|(_, h)| **h < MIN_FOLD_SAMPLES) {
        return Err(IdentifyError::FoldTooSmall {
            fold,
            training: train.len() - h,
            held_out: h,
            min: MIN_FOLD_SAMPLES,
        });
    }
    let cols = regressor_row_columns(&links);
    let pass = ChoicePass::new(&links, train, &ranges, (&cols, bases()))?;
    let pb = 10 * links.num_bodies();
    let scored = (laws().par_iter())
        .map(|l| score(l, &pass.sums, &cols, (pb, prior, weights)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut choice = conclude(kind, ranges.len(), scored.into_iter().flatten().collect());
    choice.pass = Pass(Some(std::sync::Arc::new(pass)));
    Ok(choice)
}

/// The cross-validated scores of `law` (indices of [`bases`]), one per
/// weight.
fn score(
    law: &[usize],
    sums: &[Vec<Sums>],
    cols: &[Vec<usize>],
    (pb, prior, weights): (usize, &PriorTerm, &[f64]),
) -> Result<Vec<LawScore>, IdentifyError> {
    let (n, k) = (cols.len(), sums.len());
    let sse = law_sse(law, sums, cols, (pb, prior, weights))?;
    let rows: Vec<usize> = sums.iter().map(|s| s[0].rows).collect();
    let b = bases();
    let total: usize = rows.iter().sum();
    Ok((weights.iter().zip(&sse))
        .map(|(&weight, sse)| {
            let heldout_rms: Vec<f64> = (0..n)
                .map(|j| (sse.iter().map(|s| s[j]).sum::<f64>() / total.max(1) as f64).sqrt())
                .collect();
            let fold_rms = (0..k)
                .map(|f| {
                    (0..n)
                        .map(|j| (sse[f][j] / rows[f].max(1) as f64).sqrt())
                        .sum::<f64>()
                        / n as f64
                })
                .collect();
            LawScore {
                terms: law.iter().map(|&t| b[t].0.name().to_string()).collect(),
                stribeck_velocity: (law.iter())
                    .find(|&&t| b[t].0 == FrictionTerm::Stribeck)
                    .map(|&t| b[t].1),
                weight,
                mean_rms: heldout_rms.iter().sum::<f64>() / n as f64,
                heldout_rms,
                fold_rms,
            }
        })
        .collect())
}

/// The best law, and the one the parsimony rule chooses (module doc).
fn conclude(kind: Folds, k: usize, laws: Vec<LawScore>) -> FrictionChoice {
    let best = (0..laws.len())
        .min_by(|&a, &b| laws[a].mean_rms.total_cmp(&laws[b].mean_rms))
        .unwrap_or(0);
    let within =
        |i: usize| within_noise(&laws[i].fold_rms, &laws[best].fold_rms, laws[best].mean_rms);
    let chosen = (0..laws.len())
        .filter(|&i| i == best || within(i))
        .min_by(|&a, &b| {
            (laws[a].terms.len().cmp(&laws[b].terms.len()))
                .then(laws[b].weight.total_cmp(&laws[a].weight))
                .then(laws[a].mean_rms.total_cmp(&laws[b].mean_rms))
        })
        .unwrap_or(best);
    let rule = match chosen == best {
        true => format!(
            "the lowest cross-validated error ({:.4} N·m)",
            laws[best].mean_rms
        ),
        false => format!(
            "the fewest terms within the noise of the lowest (one standard error over the {k} folds, paired, or {:.0} % of it; lowest {:.4} N·m with {}): {:.4} N·m",
            100.0 * MIN_GAIN,
            laws[best].mean_rms,
            laws[best].terms.join("+"),
            laws[chosen].mean_rms
        ),
    };
    FrictionChoice {
        folds: kind,
        k,
        laws,
        best,
        chosen,
        rule,
        pass: Pass(None),
    }
}
