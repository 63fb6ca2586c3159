//! Choosing, within the training part, the joints a hypothesis is fitted
//! on. A hypothesis whose columns lie one joint each (an offset, a
//! friction term, a gain per joint) is fitted on every joint at once; on
//! real data a joint whose residual drifts over the record gets a
//! coefficient that fits the training part and hurts the held-out one,
//! and that loss can hide a clear gain on the joint that has the effect.
//! So each joint's columns are kept only if, fitted on the first two
//! thirds of the training samples, they lower that joint's mean square on
//! the last third by at least 1 %. The held-out part is not looked at: its
//! test stays a test.

use super::candidate::Variant;
use super::error::FitError;
use super::fit::least_squares;
use super::split::Split;

/// The share of the training samples the screening fit uses.
const SCREEN_FIT: f64 = 2.0 / 3.0;
/// The least relative decrease of a joint's mean square on the rest.
const SCREEN_GAIN: f64 = 0.01;

/// The columns of `v` to fit on the residual `r`: for a plain variant
/// whose columns lie one joint each, those of the joints that pass the
/// screening (all, when none does); every column otherwise.
pub fn screened_columns(v: &Variant, split: &Split, r: &[f64]) -> Result<Vec<usize>, FitError> {
    let c = &v.columns;
    let all: Vec<usize> = (0..c.cols.len()).collect();
    let n = split.joints;
    let Some(joints) = per_joint(v, n) else {
        return Ok(all);
    };
    let cut = (split.first_heldout as f64 * SCREEN_FIT) as usize * n;
    let (fit, rest) = (split.train.start..cut, cut..split.train.end);
    if fit.is_empty() || rest.is_empty() {
        return Ok(all);
    }
    let beta = least_squares(v, fit, r)?;
    // per joint, Σ r² and Σ (r − Xβ)² over the rest, in one pass over it
    let mut sums = vec![(0.0, 0.0); n];
    for row in rest {
        let mut after = r[row];
        for (col, b) in c.cols.iter().zip(&beta) {
            after -= b * col[row];
        }
        let s = &mut sums[row % n];
        s.0 += r[row] * r[row];
        s.1 += after * after;
    }
    let kept: Vec<usize> = (0..n)
        .filter(|&i| sums[i].1 < (1.0 - SCREEN_GAIN) * sums[i].0)
        .collect();
    let on: Vec<usize> = all
        .into_iter()
        .filter(|&a| kept.contains(&joints[a]))
        .collect();
    Ok(if on.is_empty() {
        (0..c.cols.len()).collect()
    } else {
        on
    })
}

/// The joint of each column of `v` when it is a plain variant (no bodies,
/// no sign constraint) whose columns lie in one joint each: the fit then
/// separates into one independent fit per joint.
pub fn per_joint(v: &Variant, n: usize) -> Option<&[usize]> {
    let c = &v.columns;
    (c.bodies.is_empty() && !c.nonneg)
        .then(|| v.column_joints(n))
        .flatten()
}

#[cfg(test)]
mod tests {
    use super::screened_columns;
    use crate::diagnose::candidate::Variant;
    use crate::diagnose::split::Split;
    use crate::effects::Columns;

    /// Two joints, an offset column each: joint 0 has a steady offset,
    /// joint 1 one that flips sign halfway through the training part (a
    /// drift a fit cannot carry forward). Only joint 0's column is kept; a
    /// column spanning both joints is not screened.
    #[test]
    fn only_the_joints_whose_fit_carries_forward_are_kept() {
        let (n, samples) = (2, 600);
        let split = Split::new(samples, n, 0.6);
        let noise = |k: usize| 0.1 * ((k * 7919 % 101) as f64 / 50.0 - 1.0);
        let mut r = vec![0.0; samples * n];
        for k in 0..samples {
            r[k * n] = 0.5 + noise(k);
            r[k * n + 1] = if k < 180 { 0.5 } else { -0.5 } + noise(k + 3);
        }
        let col = |i: usize| -> Vec<f64> {
            (0..samples * n)
                .map(|row| (row % n == i) as u8 as f64)
                .collect()
        };
        let v = Variant::new(Columns::linear(vec![col(0), col(1)]));
        assert_eq!(screened_columns(&v, &split, &r).unwrap(), [0]);
        let both = Variant::new(Columns::linear(vec![vec![1.0; samples * n]]));
        assert_eq!(screened_columns(&both, &split, &r).unwrap(), [0]);
        assert_eq!(both.column_joints(n), None);
    }
}
