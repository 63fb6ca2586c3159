//! Which segments of the training data repeat one motion.
//!
//! Cross-validation that holds out one run of a trajectory and fits on
//! another run of the same trajectory measures the robot's repeatability,
//! not how the model carries to other motion: every held-out sample has a
//! twin in the fit. The model choices (`identify::friction_choice`,
//! `identify::choose_weight`) therefore hold the repeats of one motion out
//! together (`choose_weight::held_out`).
//!
//! Two segments repeat one motion when they have the same sampling step
//! (within 1 %), the same length (within 10 %), and over the shorter one,
//! aligned at their first samples, their positions differ by at most
//! [`REPEAT_SHARE`] of the motion: `‖RMS_j(q_a − q_b)‖ ≤ 0.1 ‖std_j(q_a)‖`
//! (norms over the joints, rad). A repeat of a commanded trajectory
//! differs by its tracking error (milliradians on a position-controlled
//! arm); two motions differ by about their own spread, two orders more.
//! Logs started at different moments of one trajectory are not aligned
//! and count as different motions.

use crate::data::Dataset;
use std::ops::Range;

/// The share of the motion's spread under which two segments' positions
/// are one motion repeated (module doc).
pub const REPEAT_SHARE: f64 = 0.1;

/// Per segment of `d` ([`Dataset::segment_ranges`]), the index of its
/// motion: the first segment repeating it, in order (0 for the first).
pub fn motions(d: &Dataset) -> Vec<usize> {
    let segments = d.segment_ranges();
    let mut motion: Vec<usize> = Vec::with_capacity(segments.len());
    for (i, s) in segments.iter().enumerate() {
        let first = (0..i).find(|&k| motion[k] == k && repeats(d, &segments[k], s));
        motion.push(first.unwrap_or(i));
    }
    motion
}

/// Whether segments `a` and `b` of `d` repeat one motion (module doc).
fn repeats(d: &Dataset, a: &Range<usize>, b: &Range<usize>) -> bool {
    let (la, lb) = (a.len(), b.len());
    if la < 2 || lb < 2 || la.abs_diff(lb) as f64 > 0.1 * la.max(lb) as f64 {
        return false;
    }
    let step = |r: &Range<usize>| (d.t[r.end - 1] - d.t[r.start]) / (r.len() - 1) as f64;
    let (sa, sb) = (step(a), step(b));
    // written so that a NaN step is not a repeat
    let same_step = (sa - sb).abs() <= 0.01 * sa.max(sb);
    if !same_step {
        return false;
    }
    let (n, w) = (la.min(lb), d.q.width());
    let q = d.q.as_flat();
    let row = |r: &Range<usize>, i: usize| &q[(r.start + i) * w..(r.start + i + 1) * w];
    let (mut diff2, mut mean, mut sq) = (0.0, vec![0.0; w], vec![0.0; w]);
    for i in 0..n {
        let (x, y) = (row(a, i), row(b, i));
        for j in 0..w {
            diff2 += (x[j] - y[j]).powi(2);
            mean[j] += x[j];
            sq[j] += x[j] * x[j];
        }
    }
    let nf = n as f64;
    let spread2: f64 = (0..w)
        .map(|j| (sq[j] / nf - (mean[j] / nf).powi(2)).max(0.0))
        .sum();
    diff2 / nf <= REPEAT_SHARE.powi(2) * spread2 && spread2 > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::Samples;

    /// Segments of two joints sampled at `dt`, each `q(t) = (a sin t, a cos
    /// 2t) + shift`.
    fn data(segs: &[(usize, f64, f64, f64)]) -> Dataset {
        let mut d = Dataset::empty(&["j0", "j1"]);
        for &(n, dt, a, shift) in segs {
            let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
            let rows: Vec<[f64; 2]> = (t.iter())
                .map(|t| [a * t.sin() + shift, a * (2.0 * t).cos()])
                .collect();
            let s = Samples::from_rows(&rows);
            d.append_segment(Dataset {
                joints: d.joints.clone(),
                t,
                q: s.clone(),
                qd: s.clone(),
                qdd: s.clone(),
                tau: s,
                segments: vec![],
                base: None,
                contacts: vec![],
            });
        }
        d
    }

    #[test]
    fn repeats_of_one_motion_share_a_motion_and_other_motions_do_not() {
        // run 2 repeats run 1 within 0.01 rad; run 3 is the motion at half
        // the amplitude (differs by about its spread)
        let d = data(&[
            (500, 0.01, 1.0, 0.0),
            (490, 0.01, 1.0, 0.01),
            (500, 0.01, 0.5, 0.0),
        ]);
        assert_eq!(motions(&d), vec![0, 0, 2]);
    }

    /// The folds of the model choices: repeats of one motion are held out
    /// together, by blocks of time when they are the only motion.
    #[test]
    fn repeats_are_held_out_together() {
        use crate::identify::choose_weight::{Folds, held_out};
        let d = data(&[(500, 0.01, 1.0, 0.0), (500, 0.01, 1.0, 0.01)]);
        let (kind, folds) = held_out(&d, 5);
        assert_eq!((kind, folds.len()), (Folds::Time, 5));
        assert_eq!(
            folds[1],
            vec![100..200, 600..700],
            "the same block of each run"
        );
        let d = data(&[
            (500, 0.01, 1.0, 0.0),
            (500, 0.01, 0.5, 0.0),
            (500, 0.01, 1.0, 0.01),
        ]);
        let (kind, folds) = held_out(&d, 5);
        assert_eq!((kind, folds.len()), (Folds::Segments, 2));
        assert_eq!(
            folds[0],
            vec![0..500, 500..500, 1000..1500],
            "run 1 with its repeat"
        );
        assert_eq!(folds[1], vec![0..0, 500..1000, 1000..1000]);
    }

    #[test]
    fn another_rate_another_length_or_a_shift_of_the_spread_is_another_motion() {
        let d = data(&[(500, 0.01, 1.0, 0.0), (500, 0.02, 1.0, 0.0)]);
        assert_eq!(motions(&d), vec![0, 1], "another step");
        let d = data(&[(500, 0.01, 1.0, 0.0), (400, 0.01, 1.0, 0.0)]);
        assert_eq!(motions(&d), vec![0, 1], "20 % shorter");
        // spread ‖std‖ ≈ 1 rad: a 0.08 rad offset is a repeat, 0.2 is not
        let d = data(&[(500, 0.01, 1.0, 0.0), (500, 0.01, 1.0, 0.08)]);
        assert_eq!(motions(&d), vec![0, 0]);
        let d = data(&[(500, 0.01, 1.0, 0.0), (500, 0.01, 1.0, 0.2)]);
        assert_eq!(motions(&d), vec![0, 1]);
    }
}
