//! Keeping a per-joint hypothesis off the joints where it does not carry
//! forward. A hypothesis whose columns lie one joint each (an offset, a
//! friction term, a gain per joint) is fitted joint by joint; on real data
//! a joint whose residual changes between the training and the held-out
//! part (a torque sensor's offset drifting over the run) passes the
//! training-part screening and then makes the held-out part clearly worse,
//! which can hide a clear gain on the joint that has the effect. Such a
//! joint's columns are dropped before the candidate is scored: the
//! effect is not claimed there, and the other joints' coefficients stay as
//! they are (their fits are independent).
//!
//! This looks at the held-out part, so it only removes, and only what is
//! clearly worse: a joint is dropped when the fit raises its held-out mean
//! square by at least 1 % (the mirror of the screening's 1 % gain; a
//! column with no effect behind it costs ~1/N there, far less); joints
//! are never added, and the block test that follows still has to find a
//! gain on the joints kept.

use super::candidate::Variant;
use super::fit::apply;
use super::screen::per_joint;
use super::split::Split;

/// The relative rise of a joint's held-out mean square at which the fit
/// hurts there (the mirror of the screening's 1 % gain).
const HURTS: f64 = 0.01;

/// Zeroes in `beta` (the coefficients of `v`'s columns fitted on `r`) the
/// columns of the joints where the fit makes the held-out part clearly
/// worse, unless that would leave none; returns how many fitted
/// (nonzero) coefficients it zeroed.
pub fn drop_hurting(v: &Variant, split: &Split, r: &[f64], beta: &mut [f64]) -> usize {
    let n = split.joints;
    let Some(joints) = per_joint(v, n) else {
        return 0;
    };
    let after = apply(&v.columns.cols, beta, r);
    let fitted = |j: usize| (0..beta.len()).any(|a| joints[a] == j && beta[a] != 0.0);
    let hurts: Vec<usize> = (0..n)
        .filter(|&j| fitted(j) && worse(split, r, &after, j))
        .collect();
    let keeps = (0..n).any(|j| fitted(j) && !hurts.contains(&j));
    if hurts.is_empty() || !keeps {
        return 0;
    }
    let mut zeroed = 0;
    for (a, b) in beta.iter_mut().enumerate() {
        if hurts.contains(&joints[a]) && *b != 0.0 {
            *b = 0.0;
            zeroed += 1;
        }
    }
    zeroed
}

/// Whether `after` has a held-out mean square on joint `j` at least
/// [`HURTS`] larger than `r`'s.
fn worse(split: &Split, r: &[f64], after: &[f64], j: usize) -> bool {
    let rows = (split.heldout.start + j..split.heldout.end).step_by(split.joints);
    let (before, now) = rows.fold((0.0, 0.0), |(b, a), i| {
        (b + r[i] * r[i], a + after[i] * after[i])
    });
    now > (1.0 + HURTS) * before
}

#[cfg(test)]
mod tests {
    use super::drop_hurting;
    use crate::diagnose::candidate::Variant;
    use crate::diagnose::fit::least_squares;
    use crate::diagnose::split::Split;
    use crate::effects::Columns;

    /// Two joints, an offset column each: joint 0's offset holds on the
    /// held-out part, joint 1's flips sign there. Joint 1's column is
    /// dropped and joint 0's coefficient kept; with joint 0 steady at zero
    /// too (every fitted joint hurts), nothing is dropped.
    #[test]
    fn a_joint_whose_fit_does_not_carry_forward_is_dropped() {
        let (n, samples) = (2, 600);
        let split = Split::new(samples, n, 0.6);
        let noise = |k: usize| 0.1 * ((k * 7919 % 101) as f64 / 50.0 - 1.0);
        let col = |i: usize| -> Vec<f64> {
            (0..samples * n)
                .map(|row| (row % n == i) as u8 as f64)
                .collect()
        };
        let v = Variant::new(Columns::linear(vec![col(0), col(1)]));
        let offset = |flips: bool, k: usize| match (flips, k < split.first_heldout) {
            (true, false) => -0.5,
            _ => 0.5,
        };
        let residual = |flips0: bool| -> Vec<f64> {
            let mut r = vec![0.0; samples * n];
            for k in 0..samples {
                r[k * n] = offset(flips0, k) + noise(k);
                r[k * n + 1] = offset(true, k) + noise(k + 3);
            }
            r
        };
        let r = residual(false);
        let mut beta = least_squares(&v, split.train.clone(), &r).unwrap();
        let fitted = beta.clone();
        assert_eq!(drop_hurting(&v, &split, &r, &mut beta), 1);
        assert_eq!(beta, [fitted[0], 0.0]);
        // joint 0 flips as well: dropping both would leave nothing
        let r = residual(true);
        let mut beta = least_squares(&v, split.train.clone(), &r).unwrap();
        let fitted = beta.clone();
        assert_eq!(drop_hurting(&v, &split, &r, &mut beta), 0);
        assert_eq!(beta, fitted);
    }
}
