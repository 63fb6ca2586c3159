//! Cross-validation of a set of groups: each fold's rows predicted by the
//! fit on the other folds. A candidate with a grid of variants takes, on
//! each fold, the variant that fits that fold's training part best, so the
//! held-out error stays a test of the whole hypothesis.

use super::error::FitError;
use super::folds::Folds;
use super::refit::{Fit, Group, fit};
use super::store::Store;

/// A cross-validated residual.
#[derive(Clone, Debug)]
pub struct Cv {
    /// Each fold's rows, predicted by the fit on the other folds
    /// (sample-major, every sample).
    pub resid: Vec<f64>,
    /// The variant each fold's training part chose (none: no variants).
    pub variant: Vec<Option<usize>>,
    /// Fits that failed (variant, fold, why); a fold with no variant left
    /// is an error.
    pub failed: Vec<(usize, usize, String)>,
    /// A constrained fit solved only to reduced tolerances.
    pub inaccurate: bool,
}

/// The folds but `k`, or all (`None`).
pub fn training(folds: usize, k: Option<usize>) -> Vec<bool> {
    (0..folds).map(|j| Some(j) != k).collect()
}

/// The fit of `base` with `variant` (its constraints enforced, the
/// base's not: they are kept by the final model's fit) on the folds `on`.
pub fn fit_with(
    store: &Store,
    base: &[&Group],
    variant: Option<&Group>,
    on: &[bool],
) -> Result<Fit, FitError> {
    let mut groups: Vec<&Group> = base.to_vec();
    groups.extend(variant);
    let mut enforce = vec![false; base.len()];
    enforce.extend(variant.map(|_| true));
    fit(store, &groups, on, &enforce)
}

/// The ids of `base` and `variant`, in a fit's order.
pub fn ids_of(base: &[&Group], variant: Option<&Group>) -> Vec<usize> {
    (base.iter().copied().chain(variant))
        .flat_map(|g| g.ids.iter().copied())
        .collect()
}

/// The variant of `variants` whose fit with `base` on `on` leaves the
/// least training residual (none without variants), with its fit; the
/// failures as (variant, why).
pub fn best_variant(
    store: &Store,
    base: &[&Group],
    variants: &[Group],
    on: &[bool],
) -> (Result<(Option<usize>, Fit), FitError>, Vec<(usize, String)>) {
    if variants.is_empty() {
        return (fit_with(store, base, None, on).map(|f| (None, f)), vec![]);
    }
    let (mut best, mut failed, mut last_err): (Option<(usize, Fit)>, Vec<(usize, String)>, _) =
        (None, vec![], None);
    for (v, g) in variants.iter().enumerate() {
        match fit_with(store, base, Some(g), on) {
            Ok(f) if best.as_ref().is_none_or(|(_, b)| f.rss < b.rss) => best = Some((v, f)),
            Ok(_) => {}
            Err(e) => {
                failed.push((v, e.to_string()));
                last_err = Some(e);
            }
        }
    }
    let out = best
        .map(|(v, f)| (Some(v), f))
        .ok_or_else(|| last_err.unwrap_or(FitError::Factorisation));
    (out, failed)
}

/// The cross-validated residual of `base` with the best of `variants`
/// (none: `base` alone) over `folds`.
pub fn cross_validate(
    store: &Store,
    folds: &Folds,
    base: &[&Group],
    variants: &[Group],
) -> Result<Cv, FitError> {
    cross_validate_each(store, folds, base, &|_| variants.to_vec())
}

/// [`cross_validate`] with the variants each fold's training part gives
/// (`variants_of(k)` for fold k; none: `base` alone there).
pub fn cross_validate_each(
    store: &Store,
    folds: &Folds,
    base: &[&Group],
    variants_of: &dyn Fn(usize) -> Vec<Group>,
) -> Result<Cv, FitError> {
    let n = store.joints();
    let samples = folds.ranges.last().map_or(0, |r| r.end);
    let mut cv = Cv {
        resid: vec![0.0; samples * n],
        variant: vec![],
        failed: vec![],
        inaccurate: false,
    };
    for (k, range) in folds.ranges.iter().enumerate() {
        let on = training(folds.len(), Some(k));
        let variants = variants_of(k);
        let variants = variants.as_slice();
        let (best, failed) = best_variant(store, base, variants, &on);
        cv.failed
            .extend(failed.into_iter().map(|(v, why)| (v, k, why)));
        let (v, f) = best?;
        cv.inaccurate |= f.inaccurate;
        let ids = ids_of(base, v.map(|v| &variants[v]));
        let r = store.residual_on(&ids, &f.beta, range.clone());
        cv.resid[range.start * n..range.end * n].copy_from_slice(&r);
        cv.variant.push(v);
    }
    Ok(cv)
}

/// Per joint, the sum of squares over the samples `range` of the residual
/// of the fit `beta` of `ids`.
pub fn sse_on(
    store: &Store,
    ids: &[usize],
    beta: &[f64],
    range: std::ops::Range<usize>,
) -> Vec<f64> {
    joint_ss(&store.residual_on(ids, beta, range), store.joints())
}

/// `[fold][joint]`: the sum of squares of `resid`'s rows.
pub fn sse(folds: &Folds, n: usize, resid: &[f64]) -> Vec<Vec<f64>> {
    (folds.ranges.iter())
        .map(|f| joint_ss(&resid[f.start * n..f.end * n], n))
        .collect()
}

/// Per joint, the sum of squares of sample-major `rows` (n per sample).
fn joint_ss(rows: &[f64], n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| rows.iter().skip(i).step_by(n).map(|x| x * x).sum())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{cross_validate, sse};
    use crate::diagnose::folds::Folds;
    use crate::diagnose::refit::Group;
    use crate::diagnose::store::Store;

    /// A residual `0.5 x` plus a little noise: the column's cross-validated
    /// residual is the noise on every fold; of two variants, the one that
    /// is in the data is chosen on every fold.
    #[test]
    fn each_fold_is_predicted_by_the_others() {
        let samples = 300;
        let x: Vec<f64> = (0..samples).map(|k| (k as f64 * 0.2).sin()).collect();
        let y: Vec<f64> = (0..samples).map(|k| (k as f64 * 0.013).cos()).collect();
        let noise = |k: usize| 0.01 * (((k * 7919) % 97) as f64 / 48.0 - 1.0);
        let r: Vec<f64> = (0..samples).map(|k| 0.5 * x[k] + noise(k)).collect();
        let folds = Folds {
            ranges: vec![0..100, 100..200, 200..300],
            fit: 2,
            by_file: false,
        };
        let mut s = Store::new(r.clone(), 1, &folds);
        let (gx, gy) = (Group::plain(vec![s.add(x)]), Group::plain(vec![s.add(y)]));
        let none = cross_validate(&s, &folds, &[], &[]).unwrap();
        assert_eq!(none.resid, r);
        let cv = cross_validate(&s, &folds, &[], &[gy, gx]).unwrap();
        assert_eq!(cv.variant, [Some(1); 3]);
        for (k, e) in cv.resid.iter().enumerate() {
            assert!((e - noise(k)).abs() < 2e-3, "{k}: {e}");
        }
        let per_fold = sse(&folds, 1, &cv.resid);
        assert!(per_fold.iter().all(|f| f[0] < 0.02));
    }
}
