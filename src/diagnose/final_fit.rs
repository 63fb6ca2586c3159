//! The final model: the nominal friction law and the accepted effects
//! refit together on the fitting part with every constraint kept (a
//! friction coefficient ≥ 0, a payload's pseudo-inertia ⪰ 0, a corrected
//! link consistent), its held-out residual, and each fitted size with a
//! 95 % interval from a delete-one-block jackknife over the fitting part.

use super::candidate::Candidate;
use super::error::FitError;
use super::folds::Folds;
use super::forward::{Accepted, full_beta};
use super::law::Law;
use super::refit::{Fit, Group, fit_normal};
use super::report::SizeReport;
use super::store::Store;
use crate::dynamics::Model;
use crate::effects::{Size, SizeContext};
use faer::Mat;

/// Blocks of the jackknife over the fitting part.
pub const JACKKNIFE_BLOCKS: usize = 20;
/// Student's t, 97.5 % quantile, 19 degrees of freedom (20 blocks).
const T_19: f64 = 2.093;

/// The final fit.
pub struct Final {
    /// Coefficients: the law's columns, then each accepted group's.
    pub beta: Vec<f64>,
    /// The held-out part's residual with the law alone refit.
    pub refit: Vec<f64>,
    /// Per law column, its refit coefficient (nominal + change) with an
    /// interval.
    pub law: Vec<SizeReport>,
    /// Per accepted effect, its sizes with intervals.
    pub sizes: Vec<Vec<SizeReport>>,
    /// A constrained fit solved only to reduced tolerances.
    pub inaccurate: bool,
    /// Why the constrained fit failed, when least squares without the
    /// constraints stands in for it.
    pub unconstrained: Option<String>,
}

/// What the final fit needs.
pub struct FinalSetup<'a> {
    /// The columns.
    pub store: &'a Store,
    /// The folds (the first `fit` fit, the rest are held out).
    pub folds: &'a Folds,
    /// The nominal law.
    pub law: &'a Law,
    /// The candidates.
    pub candidates: &'a [Candidate],
    /// The nominal model.
    pub model: &'a Model,
}

impl FinalSetup<'_> {
    /// The final fit of the law and `accepted`.
    pub fn fit(&self, accepted: &[Accepted]) -> Result<Final, FitError> {
        let owned: Vec<Group> = std::iter::once(&self.law.group)
            .chain(accepted.iter().map(|a| &a.group))
            .map(Group::reported)
            .collect();
        let groups: Vec<&Group> = owned.iter().collect();
        let mut enforce = vec![true; groups.len()];
        let ids: Vec<usize> = groups.iter().flat_map(|g| g.ids.iter().copied()).collect();
        let end = self.folds.first_heldout();
        let blocks = self.block_normals(&ids, end);
        let sum = |leave| self.store.with_prior(&ids, sum_normals(&blocks, leave));
        let total = sum(None);
        let (full, unconstrained) = match fit_normal(&total.0, &total.1, total.2, &groups, &enforce)
        {
            Ok(f) => (f, None),
            Err(e) => {
                enforce = vec![false; groups.len()];
                let f = fit_normal(&total.0, &total.1, total.2, &groups, &enforce)?;
                (f, Some(e.to_string()))
            }
        };
        let replicates: Vec<Fit> = (0..blocks.len())
            .filter_map(|b| {
                let (g, x, rr) = sum(Some(b));
                fit_normal(&g, &x, rr, &groups, &enforce).ok()
            })
            .collect();
        let samples = self.folds.ranges.last().map_or(0, |r| r.end);
        let law_ids = &self.law.group.ids;
        let law_blocks = self.block_normals(law_ids, end);
        let (lg, lx, lrr) = self
            .store
            .with_prior(law_ids, sum_normals(&law_blocks, None));
        // the law alone (with bodies refit: their LMIs), as the full fit:
        // least squares without the constraints when the conic fit fails
        let mut unconstrained = unconstrained;
        let law_fit = match fit_normal(&lg, &lx, lrr, &[&self.law.group], &[true]) {
            Ok(f) => f,
            Err(e) => {
                unconstrained.get_or_insert(format!("the law alone: {e}"));
                fit_normal(&lg, &lx, lrr, &[&self.law.group], &[false])?
            }
        };
        let refit = self.store.residual_on(law_ids, &law_fit.beta, end..samples);
        Ok(Final {
            law: self.law_sizes(&full, &replicates),
            sizes: self.sizes(accepted, &full, &replicates),
            inaccurate: full.inaccurate,
            unconstrained,
            beta: full.beta,
            refit,
        })
    }

    /// The normal equations of `ids` over [`JACKKNIFE_BLOCKS`] equal blocks
    /// of the samples `0..end`.
    fn block_normals(&self, ids: &[usize], end: usize) -> Vec<(Mat<f64>, Vec<f64>, f64)> {
        let b = JACKKNIFE_BLOCKS.min(end.max(1));
        (0..b)
            .map(|j| self.store.normal_over(ids, j * end / b..(j + 1) * end / b))
            .collect()
    }

    /// `fin`'s sizes (the law's, then each accepted effect's) at the
    /// coefficients `beta` (refined), their intervals' half-widths kept.
    pub fn recentred(
        &self,
        accepted: &[Accepted],
        fin: &Final,
        beta: &[f64],
    ) -> (Vec<SizeReport>, Vec<Vec<SizeReport>>) {
        let at = Fit {
            beta: beta.to_vec(),
            inaccurate: false,
            rss: 0.0,
        };
        let moved = |old: &[SizeReport], new: Vec<SizeReport>| -> Vec<SizeReport> {
            (new.into_iter().zip(old))
                .map(|(n, o)| {
                    let half = 0.5 * (o.high - o.low);
                    SizeReport {
                        low: n.value - half,
                        high: n.value + half,
                        ..n
                    }
                })
                .collect()
        };
        let law = moved(&fin.law, self.law_sizes(&at, &[]));
        let sizes = (fin.sizes.iter().zip(self.sizes(accepted, &at, &[])))
            .map(|(o, n)| moved(o, n))
            .collect();
        (law, sizes)
    }

    /// The law's coefficients: nominal + change, with intervals.
    fn law_sizes(&self, full: &Fit, reps: &[Fit]) -> Vec<SizeReport> {
        let law = self.law;
        let names = |beta: &[f64]| -> Vec<Size> {
            (law.labels.iter().zip(&law.nominal).zip(beta))
                .map(|(((t, i), c0), d)| {
                    let joint = &self.model.joints[*i].name;
                    Size::new(format!("{} friction, {joint}", t.name()), t.unit(), c0 + d)
                })
                .collect()
        };
        let k = law.group.ids.len();
        let reps: Vec<Vec<Size>> = reps.iter().map(|f| names(&f.beta[..k])).collect();
        intervals(&names(&full.beta[..k]), &reps)
    }

    /// Each accepted effect's sizes with intervals.
    fn sizes(&self, accepted: &[Accepted], full: &Fit, reps: &[Fit]) -> Vec<Vec<SizeReport>> {
        let mut at = self.law.group.ids.len();
        (accepted.iter())
            .map(|a| {
                let c = &self.candidates[a.candidate];
                let v = &c.variants[a.variant];
                let len = a.group.ids.len();
                let sizes = |beta: &[f64]| {
                    let all = full_beta(v, &a.group, &beta[at..at + len]);
                    let cx = SizeContext {
                        model: self.model,
                        col_joints: &v.col_joints,
                    };
                    c.effect.sizes(&v.columns, &all, &cx)
                };
                let reps: Vec<Vec<Size>> = reps.iter().map(|f| sizes(&f.beta)).collect();
                let out = intervals(&sizes(&full.beta), &reps);
                at += len;
                out
            })
            .collect()
    }
}

/// The sum of the blocks' normal equations, but block `leave` when given.
fn sum_normals(
    blocks: &[(Mat<f64>, Vec<f64>, f64)],
    leave: Option<usize>,
) -> (Mat<f64>, Vec<f64>, f64) {
    let m = blocks.first().map_or(0, |b| b.1.len());
    let mut out = (Mat::<f64>::zeros(m, m), vec![0.0; m], 0.0);
    for (j, (g, x, rr)) in blocks.iter().enumerate() {
        if Some(j) == leave {
            continue;
        }
        out.0 += g;
        out.1.iter_mut().zip(x).for_each(|(a, b)| *a += b);
        out.2 += rr;
    }
    out
}

/// Each size of `full` with the delete-one-block jackknife's 95 % interval
/// from the replicates `reps` (those of another length are dropped; fewer
/// than two replicates: no width).
fn intervals(full: &[Size], reps: &[Vec<Size>]) -> Vec<SizeReport> {
    let reps: Vec<&Vec<Size>> = reps.iter().filter(|r| r.len() == full.len()).collect();
    let b = reps.len() as f64;
    (full.iter().enumerate())
        .map(|(k, s)| {
            let half = if b >= 2.0 {
                let mean = reps.iter().map(|r| r[k].value).sum::<f64>() / b;
                let var = (b - 1.0) / b
                    * reps
                        .iter()
                        .map(|r| (r[k].value - mean).powi(2))
                        .sum::<f64>();
                T_19 * var.sqrt()
            } else {
                0.0
            };
            SizeReport {
                name: s.name.clone(),
                unit: s.unit.clone(),
                value: s.value,
                low: s.value - half,
                high: s.value + half,
            }
        })
        .collect()
}
