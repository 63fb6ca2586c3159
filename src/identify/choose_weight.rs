//! The prior's weight chosen by held-out error (`--weight auto`).
//!
//! Each weight of a grid is scored by cross-validation on the training
//! data: with several segments (files, or one file's pieces between gaps)
//! of different motions each segment is held out in turn, with its
//! repeats ([`super::repeats`]), and the rest fitted; with one segment, or
//! segments that all repeat one motion, [`TIME_FOLDS`] contiguous blocks of
//! each are held out in turn (K-fold in time: a block and its neighbours
//! share no samples, though they share the trajectory's style). A weight's score is the mean over joints of
//! the held-out RMS pooled over the folds (each joint's squared errors
//! summed over every held-out sample); the strongest prior whose score is
//! within the noise of the lowest's wins (the friction law's parsimony
//! rule, [`within_noise`]: the paired per-fold differences' mean at most
//! their standard error or 1 % of the lowest), the whole curve is kept
//! ([`WeightChoice`]). Every fit is the identification as
//! set (levels, regulariser, friction terms, weighting), so the choice
//! costs `grid × folds` fits.
//!
//! What cross-validation cannot see it cannot choose for: a fold's
//! held-out data share the trajectory's style with its training data, so
//! a trajectory of other speeds may still want a stronger prior than the
//! curve's (docs/real-robot.md).

use super::builder::Identification;
use super::error::IdentifyError;
use super::warning::IdentifyWarning;
use crate::data::Dataset;
use serde::Serialize;

/// The weights tried by default (the regulariser's, either kind).
pub const WEIGHT_GRID: [f64; 7] = [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0];

/// The blocks of K-fold cross-validation in time.
pub const TIME_FOLDS: usize = 5;

/// The fewest samples a fold's training or held-out part may have.
pub const MIN_FOLD_SAMPLES: usize = 50;

/// How the training data were split.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Folds {
    /// Each segment (a file, or a file's piece between gaps) held out in
    /// turn, with the segments that repeat its motion.
    Segments,
    /// Contiguous blocks in time held out in turn (one segment, or
    /// segments that all repeat one motion).
    Time,
}

/// The least share of the best's score a term must gain to be kept: a
/// gain under it is within the noise whatever the folds say (1 % of the
/// RMS, about the 2 % of the mean square the diagnosis asks of an effect:
/// the diagnosis' `MIN_SHARE`).
pub const MIN_GAIN: f64 = 0.01;

/// The parsimony rule's test (the friction law's and the weight's): whether a candidate whose
/// per-fold scores are `fold` is within the noise of the best's
/// (`best_fold`, pooled score `best`): the mean of the paired per-fold
/// differences at most their standard error or [`MIN_GAIN`] of `best`.
pub fn within_noise(fold: &[f64], best_fold: &[f64], best: f64) -> bool {
    let k = fold.len().max(1);
    let d: Vec<f64> = fold.iter().zip(best_fold).map(|(a, b)| a - b).collect();
    let mean = d.iter().sum::<f64>() / k as f64;
    let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (k.max(2) - 1) as f64;
    mean <= (var / k as f64).sqrt().max(MIN_GAIN * best)
}

/// The weight chosen and the curve it was chosen from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WeightChoice {
    /// How the data were split.
    pub folds: Folds,
    /// Number of folds.
    pub k: usize,
    /// The weights tried, increasing.
    pub weights: Vec<f64>,
    /// Per weight, each joint's held-out RMS pooled over the folds (N·m).
    pub heldout_rms: Vec<Vec<f64>>,
    /// Per weight, the mean over joints of `heldout_rms` (N·m).
    pub mean_rms: Vec<f64>,
    /// The weight chosen: the largest whose per-fold scores are within
    /// the noise of the lowest's ([`within_noise`], the friction law's
    /// parsimony rule).
    pub chosen: f64,
    /// The weight of the lowest `mean_rms`.
    pub lowest: f64,
    /// What the folds' fits reported (their warnings, their degenerate
    /// bodies), each with its weight and fold: a curve point scored on
    /// doubtful fits is named, not hidden.
    pub fold_notes: Vec<String>,
}

/// The largest weight (index, the weights increasing) whose per-fold
/// scores are within the noise of the lowest's (index `best`).
fn strongest_within_noise(fold_rms: &[Vec<f64>], mean_rms: &[f64], best: usize) -> usize {
    (0..mean_rms.len())
        .rev()
        .find(|&i| within_noise(&fold_rms[i], &fold_rms[best], mean_rms[best]))
        .unwrap_or(best)
}

/// The (training, held-out) pairs of `d`'s cross-validation: by segment
/// when it has several, else `k` blocks in time ([`held_out`]).
pub fn folds(d: &Dataset, k: usize) -> (Folds, Vec<(Dataset, Dataset)>) {
    let segments = d.segment_ranges();
    let joints: Vec<&str> = d.joints.iter().map(String::as_str).collect();
    let (kind, held) = held_out(d, k);
    let pairs = (held.iter())
        .map(|h| {
            let (mut train, mut out) = (Dataset::empty(&joints), Dataset::empty(&joints));
            for (s, h) in segments.iter().zip(h) {
                for part in [s.start..h.start, h.end..s.end] {
                    if !part.is_empty() {
                        train.append_segment(d.slice(part));
                    }
                }
                if !h.is_empty() {
                    out.append_segment(d.slice(h.clone()));
                }
            }
            (train, out)
        })
        .collect();
    (kind, pairs)
}

/// Per fold of `d`'s cross-validation, the samples it holds out of each
/// segment (an empty range: none of it): each motion in turn (a segment
/// with its repeats, [`super::repeats`]) when there are several, else `k`
/// contiguous blocks in time, the same block of every segment held out
/// together (so a repeat's twin of a held-out block is held out too).
pub fn held_out(d: &Dataset, k: usize) -> (Folds, Vec<Vec<std::ops::Range<usize>>>) {
    let segments = d.segment_ranges();
    let motion = super::repeats::motions(d);
    let mut distinct = motion.clone();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() >= 2 {
        let held = (distinct.iter())
            .map(|&m| {
                let one = |(i, s): (usize, &std::ops::Range<usize>)| match motion[i] == m {
                    true => s.clone(),
                    false => s.start..s.start,
                };
                segments.iter().enumerate().map(one).collect()
            })
            .collect();
        return (Folds::Segments, held);
    }
    let held = (0..k)
        .map(|f| {
            let block = |s: &std::ops::Range<usize>| {
                let len = s.end - s.start;
                s.start + f * len / k..s.start + (f + 1) * len / k
            };
            segments.iter().map(block).collect()
        })
        .collect();
    (Folds::Time, held)
}

impl Identification<'_> {
    /// Chooses the prior's weight from `grid` (> 0 each) by
    /// cross-validation on `train` (module doc) and sets it; the curve is
    /// returned. Needs the prior ([`Self::prior`]); a fold's failed fit is
    /// an error naming the weight, and a fold of under
    /// [`MIN_FOLD_SAMPLES`] training or held-out samples an error before
    /// any fit.
    pub fn choose_weight(
        &mut self,
        train: &Dataset,
        grid: &[f64],
    ) -> Result<WeightChoice, IdentifyError> {
        self.fixed_base("Identification::choose_weight")?;
        let nb = self.layout.num_bodies();
        if self.prior.len() != 10 * nb {
            return Err(IdentifyError::NoPrior {
                body: self.layout.bodies.first().cloned().unwrap_or_default(),
            });
        }
        let mut weights: Vec<f64> = grid.to_vec();
        weights.sort_by(f64::total_cmp);
        if let Some(&w) = weights.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
            return Err(IdentifyError::WeightGrid {
                what: format!("{} is not positive and finite", crate::numfmt::short(w)),
            });
        }
        if weights.is_empty() {
            return Err(IdentifyError::WeightGrid {
                what: "none given".into(),
            });
        }
        let (kind, pairs) = folds(train, TIME_FOLDS);
        for (fold, (t, h)) in pairs.iter().enumerate() {
            if t.len().min(h.len()) < MIN_FOLD_SAMPLES {
                return Err(IdentifyError::FoldTooSmall {
                    fold,
                    training: t.len(),
                    held_out: h.len(),
                    min: MIN_FOLD_SAMPLES,
                });
            }
        }
        // each fold's training data reduced once, whatever the weight
        let reduced = self.fold_reductions(&pairs, weights[0])?;
        let (mut heldout_rms, mut fold_rms, mut fold_notes) = (vec![], vec![], vec![]);
        for &w in &weights {
            self.weight = w;
            let (pooled, per_fold) = self.pooled_heldout_rms(&pairs, &reduced, &mut fold_notes)?;
            heldout_rms.push(pooled);
            fold_rms.push(per_fold);
        }
        let mean_rms: Vec<f64> = (heldout_rms.iter())
            .map(|r| r.iter().sum::<f64>() / r.len().max(1) as f64)
            .collect();
        let best = (0..weights.len())
            .min_by(|&a, &b| mean_rms[a].total_cmp(&mean_rms[b]))
            .unwrap_or(0);
        let chosen = strongest_within_noise(&fold_rms, &mean_rms, best);
        self.weight = weights[chosen];
        Ok(WeightChoice {
            folds: kind,
            k: pairs.len(),
            chosen: weights[chosen],
            lowest: weights[best],
            weights,
            heldout_rms,
            mean_rms,
            fold_notes,
        })
    }

    /// Each fold's training part reduced (a failure named with `weight`,
    /// the grid's first); every fold's reduction is kept, not a load term's
    /// rows (its passes keep them for one fit at a time).
    fn fold_reductions(
        &self,
        pairs: &[(Dataset, Dataset)],
        weight: f64,
    ) -> Result<Vec<super::Reduced>, IdentifyError> {
        (pairs.iter().enumerate())
            .map(|(fold, (t, _))| {
                let mut red = self.reduce(t).map_err(|e| IdentifyError::Fold {
                    weight,
                    fold,
                    source: Box::new(e),
                })?;
                red.load_rows = None;
                Ok(red)
            })
            .collect()
    }

    /// Each joint's held-out RMS pooled over `pairs` (fitted at the weight
    /// set on their training parts' reductions `reduced`), and per fold
    /// the mean over joints of its held-out RMS.
    fn pooled_heldout_rms(
        &self,
        pairs: &[(Dataset, Dataset)],
        reduced: &[super::Reduced],
        notes: &mut Vec<String>,
    ) -> Result<(Vec<f64>, Vec<f64>), IdentifyError> {
        let n = self.model.dof();
        let (mut sum, mut count, mut per_fold) = (vec![0.0; n], 0usize, vec![]);
        for (fold, ((train, held), red)) in pairs.iter().zip(reduced).enumerate() {
            let failed = |e| IdentifyError::Fold {
                weight: self.weight,
                fold,
                source: Box::new(e),
            };
            let mut r = self.fit_reduced(train, red).map_err(failed)?;
            r.validate(self.model, held).map_err(failed)?;
            let at = |what: String| format!("weight {:e}, fold {fold}: {what}", self.weight);
            // (the prior's own warnings are the final fit's too)
            let own = |w: &&IdentifyWarning| {
                !matches!(
                    w,
                    IdentifyWarning::PriorOutsideEllipsoid { .. }
                        | IdentifyWarning::MassWeightLow { .. }
                )
            };
            notes.extend(r.warnings.iter().filter(own).map(|w| at(w.to_string())));
            if !r.degenerate_bodies.is_empty() {
                notes.push(at(format!("degenerate {}", r.degenerate_bodies.join(", "))));
            }
            let rms = r.validation_rms.iter().flatten();
            per_fold.push(rms.clone().sum::<f64>() / n.max(1) as f64);
            for (s, rms) in sum.iter_mut().zip(rms) {
                *s += rms * rms * held.len() as f64;
            }
            count += held.len();
        }
        let pooled = sum.iter().map(|s| (s / count.max(1) as f64).sqrt());
        Ok((pooled.collect(), per_fold))
    }
}
