//! Scoring one candidate in one round: its cross-validated residual with
//! the current model (the friction law and the effects accepted so far,
//! all refit with it), the joints it is kept on, and what the acceptance
//! rule reads of it.

use super::candidate::Candidate;
use super::cv::{
    Cv, best_variant, cross_validate, cross_validate_each, ids_of, sse, sse_on, training,
};
use super::folds::Folds;
use super::refit::Group;
use super::rule::{Refusal, Rule, Scores, block_bootstrap_z, block_gains};
use super::store::Store;
use super::warning::DiagnoseWarning;

/// Why a coefficient of `group` (variant `v` of `c`, coefficients
/// `beta`) on joint `joint` (any joint: `None`) is implausible, if one is.
fn implausible_on(
    c: &Candidate,
    v: usize,
    group: &Group,
    beta: &[f64],
    joint: Option<usize>,
) -> Option<String> {
    let var = &c.variants[v];
    (group.ids.iter().zip(beta)).find_map(|(id, b)| {
        let col = var.group.ids.iter().position(|x| x == id)?;
        if joint.is_some() && var.col_joints[col] != joint {
            return None;
        }
        c.effect.implausible(&var.columns, col, *b)
    })
}

/// A round: the current model and its cross-validation.
pub struct Round<'a> {
    /// Its number (1-based).
    pub number: usize,
    /// The columns.
    pub store: &'a Store,
    /// The folds.
    pub folds: &'a Folds,
    /// The current model's groups: the law and the accepted effects.
    pub base: Vec<&'a Group>,
    /// Its cross-validated residual.
    pub without: Cv,
    /// Its `[fold][joint]` sums of squares.
    pub sse_without: Vec<Vec<f64>>,
    /// The acceptance rule for this round.
    pub rule: Rule,
    /// Joint names.
    pub names: &'a [String],
    /// Blocks of the block bootstrap.
    pub blocks: usize,
    /// `[k][j][joint]`: the current model fitted on the folds but j and k,
    /// its sum of squares on fold j (empty for j = k): the inner folds a
    /// per-joint hypothesis' joints are chosen on within fold k's
    /// training part.
    pub inner_without: Vec<Vec<Vec<f64>>>,
}

/// One candidate scored in one round.
pub struct Evaluation {
    /// The candidate's index.
    pub candidate: usize,
    /// The variants' groups on the joints kept.
    pub groups: Vec<Group>,
    /// The variant the whole data choose, and its coefficients there.
    pub variant: usize,
    /// Its coefficients fitted on every fold (with the current model).
    pub beta: Vec<f64>,
    /// Its cross-validated residual.
    pub cv: Cv,
    /// What the rule reads.
    pub scores: Scores,
    /// Per-block mean-square gains over every joint (for ties).
    pub all_blocks: Vec<f64>,
    /// The pooled mean-square gain over every joint (per sample).
    pub gain: f64,
    /// Fitted parameters: columns kept plus the variant's nonlinear ones.
    pub params: usize,
    /// Why it is accepted, or why not.
    pub verdict: Result<String, Refusal>,
}

impl Round<'_> {
    /// `c` (index `at`) scored against the current model; `None` when no
    /// fit of it succeeds (each failure a warning). A per-joint hypothesis
    /// is kept on the joints where the rule passes on its own and its
    /// coefficients are plausible ([`crate::effects::Effect::implausible`]);
    /// its held-out scores are those of a cross-validation in which each
    /// fold's joints are chosen within its training part ([`Self::screened`]),
    /// so choosing joints is not tested on the data that chose them.
    /// Another hypothesis with an implausible coefficient is not accepted.
    pub fn evaluate(
        &self,
        c: &Candidate,
        at: usize,
        warnings: &mut Vec<DiagnoseWarning>,
    ) -> Option<Evaluation> {
        let n = self.store.joints();
        let all: Vec<usize> = (0..n).collect();
        let groups = c.groups();
        let cv = self.cv(c, &groups, warnings)?;
        let (groups, cv, joints, doubt, variant, beta) = if c.per_joint() {
            let (groups, cv, joints, doubt) = self.keep_joints(c, groups, cv)?;
            let (variant, beta) = self.whole(&groups)?;
            (groups, cv, joints, doubt, variant, beta)
        } else {
            let (groups, cv, doubt, variant, beta) =
                self.drop_implausible(c, groups, cv, warnings)?;
            (groups, cv, all.clone(), doubt, variant, beta)
        };
        let scores = self.scores(&cv, joints);
        let params = groups[variant].ids.len() + c.variants[variant].columns.nonlinear;
        let verdict = match doubt {
            Some(why) => Err(Refusal::Implausible(why)),
            None => self.rule.verdict(&scores, params, self.folds, self.names),
        };
        Some(Evaluation {
            all_blocks: block_gains(&self.without.resid, &cv.resid, n, &all, self.blocks),
            candidate: at,
            verdict,
            gain: (0..n).map(|i| scores.joint_gains[i]).sum(),
            params,
            groups,
            variant,
            beta,
            cv,
            scores,
        })
    }

    /// A per-joint candidate kept on the joints where the rule passes on
    /// its own and its coefficients are plausible, with the nested
    /// cross-validation of that choice; the joints kept and, when none is
    /// plausible, why.
    fn keep_joints(
        &self,
        c: &Candidate,
        mut groups: Vec<Group>,
        cv: Cv,
    ) -> Option<(Vec<Group>, Cv, Vec<usize>, Option<String>)> {
        let n = self.store.joints();
        let after = sse(self.folds, n, &cv.resid);
        let samples = self.samples();
        let passing: Vec<usize> = (0..n)
            .filter(|&i| {
                self.rule
                    .joint_passes(&self.sse_without, &after, i, samples)
            })
            .collect();
        let (v, beta) = self.whole(&groups)?;
        let why = |i: usize| implausible_on(c, v, &groups[v], &beta, Some(i));
        let kept: Vec<usize> = passing
            .iter()
            .copied()
            .filter(|&i| why(i).is_none())
            .collect();
        let doubt = (kept.is_empty() && !passing.is_empty())
            .then(|| why(passing[0]))
            .flatten();
        let mut joints: Vec<usize> = (0..n).collect();
        if !kept.is_empty() && kept.len() < n {
            groups = c.restricted(&kept);
            joints = kept;
        }
        let nested =
            cross_validate_each(self.store, self.folds, &self.base, &|k| self.screened(c, k));
        Some((groups, nested.ok()?, joints, doubt))
    }

    /// A plain hypothesis of one variant loses its implausible columns (an
    /// encoder offset on a joint whose angle the torques barely depend
    /// on); any other is not accepted with one. The groups, their
    /// cross-validation, the doubt left, and the whole-data fit.
    #[allow(clippy::type_complexity)]
    fn drop_implausible(
        &self,
        c: &Candidate,
        mut groups: Vec<Group>,
        mut cv: Cv,
        warnings: &mut Vec<DiagnoseWarning>,
    ) -> Option<(Vec<Group>, Cv, Option<String>, usize, Vec<f64>)> {
        let (mut variant, mut beta) = self.whole(&groups)?;
        let mut doubt = None;
        for _ in 0..3 {
            doubt = implausible_on(c, variant, &groups[variant], &beta, None);
            let plain = groups.len() == 1 && !groups[0].constrained();
            let Some(keep) = doubt
                .as_ref()
                .filter(|_| plain)
                .map(|_| self.plausible(c, &groups[0], &beta))
            else {
                break;
            };
            if keep.is_empty() {
                break;
            }
            groups = vec![groups[0].only(&keep)];
            cv = self.cv(c, &groups, warnings)?;
            (variant, beta) = self.whole(&groups)?;
        }
        Some((groups, cv, doubt, variant, beta))
    }

    /// The positions in `group` (of `c`'s only variant, coefficients
    /// `beta`) whose coefficients are plausible.
    fn plausible(&self, c: &Candidate, group: &Group, beta: &[f64]) -> Vec<usize> {
        let v = &c.variants[0];
        (0..group.ids.len())
            .filter(|&a| {
                let col = v
                    .group
                    .ids
                    .iter()
                    .position(|x| *x == group.ids[a])
                    .unwrap_or(0);
                c.effect.implausible(&v.columns, col, beta[a]).is_none()
            })
            .collect()
    }

    /// Fold k's variants of a per-joint candidate `c`, on the joints where
    /// the rule passes within fold k's training part (each other fold held
    /// out in turn); none when no joint does.
    fn screened(&self, c: &Candidate, k: usize) -> Vec<Group> {
        let groups = c.groups();
        let (mut before, mut after, mut samples) = (vec![], vec![], 0);
        for (j, range) in self
            .folds
            .ranges
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != k)
        {
            let on: Vec<bool> = (0..self.folds.len()).map(|x| x != j && x != k).collect();
            let Ok((v, f)) = best_variant(self.store, &self.base, &groups, &on).0 else {
                return vec![];
            };
            let ids = ids_of(&self.base, v.map(|v| &groups[v]));
            after.push(sse_on(self.store, &ids, &f.beta, range.clone()));
            before.push(self.inner_without[k][j].clone());
            samples += range.len();
        }
        let n = self.store.joints();
        let kept: Vec<usize> = (0..n)
            .filter(|&i| self.rule.joint_passes(&before, &after, i, samples))
            .collect();
        match kept.is_empty() {
            true => vec![],
            false => c.restricted(&kept),
        }
    }

    /// The variant the whole data choose among `groups` (with the current
    /// model) and its coefficients.
    fn whole(&self, groups: &[Group]) -> Option<(usize, Vec<f64>)> {
        let on = training(self.folds.len(), None);
        let (whole, _) = best_variant(self.store, &self.base, groups, &on);
        let (variant, fit) = whole.ok()?;
        let base_len: usize = self.base.iter().map(|g| g.ids.len()).sum();
        Some((variant.unwrap_or(0), fit.beta[base_len..].to_vec()))
    }

    /// The samples in all.
    fn samples(&self) -> usize {
        self.folds.ranges.last().map_or(0, |r| r.end)
    }

    /// The cross-validation of the base with `groups`, its failures
    /// warnings.
    fn cv(
        &self,
        c: &Candidate,
        groups: &[Group],
        warnings: &mut Vec<DiagnoseWarning>,
    ) -> Option<Cv> {
        let result = cross_validate(self.store, self.folds, &self.base, groups);
        let detail = |v: usize| c.variants[v].columns.detail.clone();
        match result {
            Ok(cv) => {
                for (v, _, why) in cv.failed.iter().take(1) {
                    warnings.push(DiagnoseWarning::FitFailed {
                        round: self.number,
                        effect: c.name().into(),
                        variant: detail(*v),
                        reason: why.clone(),
                    });
                }
                if cv.inaccurate {
                    warnings.push(DiagnoseWarning::Inaccurate {
                        round: self.number,
                        effect: c.name().into(),
                        variant: String::new(),
                    });
                }
                Some(cv)
            }
            Err(e) => {
                warnings.push(DiagnoseWarning::FitFailed {
                    round: self.number,
                    effect: c.name().into(),
                    variant: String::new(),
                    reason: e.to_string(),
                });
                None
            }
        }
    }

    /// What the rule reads of a cross-validation kept on `joints`.
    pub fn scores(&self, cv: &Cv, joints: Vec<usize>) -> Scores {
        let n = self.store.joints();
        let after = sse(self.folds, n, &cv.resid);
        let samples = self.samples();
        let fold_gains = (self.sse_without.iter().zip(&after).zip(&self.folds.ranges))
            .map(|((b, a), r)| {
                joints.iter().map(|&i| b[i] - a[i]).sum::<f64>() / r.len().max(1) as f64
            })
            .collect();
        let joint_gains = (0..n)
            .map(|i| self.rule.gain(&self.sse_without, &after, i, samples))
            .collect();
        let blocks = block_gains(&self.without.resid, &cv.resid, n, &joints, self.blocks);
        Scores {
            z: block_bootstrap_z(&blocks),
            joints,
            fold_gains,
            joint_gains,
            block_gains: blocks,
        }
    }
}
