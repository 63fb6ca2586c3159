//! The noise floor the gap is measured against: per joint, the torque
//! error no model can beat.
//!
//! - **From repeated runs** ([`repeat_floor`]): two logs of one trajectory,
//!   aligned by their positions (the lag, in samples, that minimises the
//!   positions' RMS difference), give `RMS(τ₁ − τ₂)/√2` per joint — the
//!   sensor noise and whatever else does not repeat (for a model that
//!   reproduces the robot perfectly, its error is one run's share of that
//!   difference).
//! - **From first differences** of the residual, `√(mean Δr² / 2)`: white
//!   noise's level. It holds only where the measurement noise reaches the
//!   Nyquist frequency; a low-pass filter (a reader's, or the logger's)
//!   removes the noise the differences see, and the estimate is then a
//!   lower bound. [`looks_low_passed`] checks the measured torque's
//!   spectrum.
//!
//! The diagnosis uses a repeat floor when it is given
//! ([`super::DiagnoseOptions::with_noise_floor`]), else the first
//! differences, and says which ([`FloorSource`]).

use super::error::DiagnoseError;
use crate::data::Dataset;
use serde::Serialize;

/// Where the noise floor came from.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum FloorSource {
    /// Two runs of one trajectory, aligned by positions.
    Repeats {
        /// What the runs are (e.g. their files), for the report.
        runs: Vec<String>,
        /// The second run's lag behind the first (samples).
        lag: i64,
        /// The positions' RMS difference once aligned (rad or m).
        position_rms: f64,
        /// Samples compared.
        samples: usize,
    },
    /// First differences of the residual; the joints whose residual looks
    /// low-pass filtered, where the estimate is a lower bound, are named.
    FirstDifferences {
        /// Joints whose residual looks low-pass filtered.
        low_passed: Vec<String>,
    },
}

/// A noise floor per joint (N·m) and where it came from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NoiseFloor {
    /// Per joint (N·m).
    pub per_joint: Vec<f64>,
    /// Where it came from.
    pub source: FloorSource,
}

/// The longest lag searched when aligning two runs (s).
pub const MAX_LAG_S: f64 = 2.0;

/// Runs whose aligned positions differ by more than this share of their
/// spread (RMS about the mean) are not repeats of one trajectory.
pub const MAX_POSITION_MISMATCH: f64 = 0.05;

/// The noise floor from runs `a` and `b` of one trajectory (same joints,
/// same sample rate, one segment each; `names` says what they are, for the
/// report): aligned by positions within ±[`MAX_LAG_S`], then
/// `RMS(τ_a − τ_b)/√2` per joint over the samples they share. An error when
/// they are not repeats (their aligned positions differ by more than
/// [`MAX_POSITION_MISMATCH`] of their spread) or cannot be compared.
pub fn repeat_floor(
    a: &Dataset,
    b: &Dataset,
    names: [&str; 2],
) -> Result<NoiseFloor, DiagnoseError> {
    let n = a.joints.len();
    let not = |why: String| DiagnoseError::NotRepeats { why };
    if b.joints != a.joints {
        return Err(not(format!("joints {:?} against {:?}", a.joints, b.joints)));
    }
    let (fa, fb) = (rate(a), rate(b));
    if !(fa > 0.0 && (fa - fb).abs() <= 1e-3 * fa) {
        return Err(not(format!("sample rates {fa} and {fb} Hz differ")));
    }
    if a.tau.len() != a.len() || b.tau.len() != b.len() {
        return Err(not("a run without torques".into()));
    }
    let max_lag = (MAX_LAG_S * fa).round() as i64;
    let (lag, mismatch) = align(a, b, max_lag)?;
    let spread = spread(a);
    if !(mismatch <= MAX_POSITION_MISMATCH * spread) {
        return Err(not(format!(
            "their positions differ by {mismatch:.3e} RMS at the best lag ({lag} samples), more than {:.0} % of their spread {spread:.3e}",
            MAX_POSITION_MISMATCH * 100.0
        )));
    }
    let pairs = overlap(a.len(), b.len(), lag);
    let shared = pairs.clone().count();
    let mut sum = vec![0.0; n];
    for (i, j) in pairs {
        for (s, (x, y)) in sum.iter_mut().zip(a.tau[i].iter().zip(&b.tau[j])) {
            *s += (x - y).powi(2);
        }
    }
    let count = shared.max(1) as f64;
    Ok(NoiseFloor {
        per_joint: sum.iter().map(|s| (s / count / 2.0).sqrt()).collect(),
        source: FloorSource::Repeats {
            runs: names.iter().map(|s| s.to_string()).collect(),
            lag,
            position_rms: mismatch,
            samples: shared,
        },
    })
}

/// Samples per second of `d` (its median step).
fn rate(d: &Dataset) -> f64 {
    let mut steps: Vec<f64> = d.t.windows(2).map(|w| w[1] - w[0]).collect();
    if steps.is_empty() {
        return 0.0;
    }
    let mid = steps.len() / 2;
    let (_, m, _) = steps.select_nth_unstable_by(mid, f64::total_cmp);
    1.0 / *m
}

/// The sample pairs `(i, i + lag)` both runs have.
fn overlap(na: usize, nb: usize, lag: i64) -> impl Iterator<Item = (usize, usize)> + Clone {
    let start = (-lag).max(0) as usize;
    let end = (na as i64).min(nb as i64 - lag).max(0) as usize;
    (start..end.max(start)).map(move |i| (i, (i as i64 + lag) as usize))
}

/// The lag of `b` behind `a` (samples, |lag| ≤ `max_lag`, at least half of
/// the shorter run shared) with the smallest RMS position difference, and
/// that RMS.
fn align(a: &Dataset, b: &Dataset, max_lag: i64) -> Result<(i64, f64), DiagnoseError> {
    let need = a.len().min(b.len()) / 2;
    let mut best: Option<(i64, f64)> = None;
    for lag in -max_lag..=max_lag {
        let pairs = overlap(a.len(), b.len(), lag);
        let count = pairs.clone().count();
        if count == 0 || count < need {
            continue;
        }
        let sum: f64 = pairs
            .map(|(i, j)| {
                a.q[i]
                    .iter()
                    .zip(&b.q[j])
                    .map(|(x, y)| (x - y).powi(2))
                    .sum::<f64>()
            })
            .sum();
        let rms = (sum / (count * a.joints.len().max(1)) as f64).sqrt();
        if best.is_none_or(|(_, r)| rms < r) {
            best = Some((lag, rms));
        }
    }
    best.ok_or(DiagnoseError::NotRepeats {
        why: "the runs are too short to share half their samples".into(),
    })
}

/// The positions' RMS about their mean, over every joint.
fn spread(d: &Dataset) -> f64 {
    let n = d.joints.len();
    let mut dev = 0.0;
    for i in 0..n {
        let mean = d.q.iter().map(|q| q[i]).sum::<f64>() / d.len().max(1) as f64;
        dev += d.q.iter().map(|q| (q[i] - mean).powi(2)).sum::<f64>();
    }
    (dev / (d.len() * n).max(1) as f64).sqrt()
}

/// Samples per Welch window of [`looks_low_passed`].
const LOW_PASS_WINDOW: usize = 256;

/// Whether signal `x` (its `segments`: sample ranges no window crosses)
/// looks low-pass filtered: the white-noise level its spectrum shows near Nyquist (the
/// mean Welch power over 0.8–1 × Nyquist,
/// [`crate::data::spectrum::welch_add`], windows of 256 samples within
/// each segment, as a variance) under 1 % of what its first differences
/// give (`mean Δx² / 2`). For white noise on a slow signal the two agree;
/// after a low-pass filter the differences see the signal's slope and the
/// band near Nyquist is empty (down to rounding). A signal with no segment
/// of 256 samples or no differences is not judged (false).
pub fn looks_low_passed(x: &[f64], segments: &[std::ops::Range<usize>]) -> bool {
    let l = LOW_PASS_WINDOW;
    let fft = rustfft::FftPlanner::new().plan_fft_forward(l);
    let mut psd = vec![0.0; l / 2 + 1];
    let (mut windows, mut diff2, mut diffs) = (0usize, 0.0, 0usize);
    for s in segments {
        let seg = &x[s.clone()];
        crate::data::spectrum::welch_add(seg, l, fft.as_ref(), &mut psd);
        windows += if seg.len() >= l {
            (seg.len() - l) / (l / 2) + 1
        } else {
            0
        };
        diff2 += seg.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>();
        diffs += seg.len().saturating_sub(1);
    }
    if windows == 0 || diffs == 0 {
        return false;
    }
    let w2: f64 = (0..l)
        .map(|k| crate::data::spectrum::blackman_harris(k, l).powi(2))
        .sum();
    let top = &psd[(0.8 * (l / 2) as f64) as usize..];
    let white = top.iter().sum::<f64>() / top.len() as f64 / (windows as f64 * w2);
    let differences = diff2 / diffs as f64 / 2.0;
    white < 0.01 * differences
}

#[cfg(test)]
mod tests {
    use super::looks_low_passed;

    /// White noise is not low-passed, nor is a slow sine with white noise
    /// on it; the same noise through the readers' zero-phase Butterworth
    /// low-pass at 30 Hz (fs 200 Hz) is.
    #[test]
    fn a_low_passed_residual_is_told_from_white_noise() {
        // a deterministic pseudo-random sequence
        let mut x = 0x2545_f491_4f6c_dd1d_u64;
        let white: Vec<f64> = (0..4000)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let smooth = crate::data::filter::filtfilt(&white, 30.0, 200.0);
        let slow: Vec<f64> = (white.iter().enumerate())
            .map(|(k, w)| 5.0 * (k as f64 * 0.01).sin() + w)
            .collect();
        let at = |r: &[f64]| looks_low_passed(r, &[0..r.len()]);
        assert!(!at(&white));
        assert!(at(&smooth));
        assert!(!at(&slow));
        assert!(!at(&vec![0.0; 100]));
    }
}
