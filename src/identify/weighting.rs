//! Per-joint weighting of the least-squares term (weighted least squares).
//!
//! The fit's residual is `Σ_j w_j ‖A_j θ − τ_j‖²` over the joints j (A_j
//! joint j's regressor rows over every sample): ordinary least squares
//! (every `w_j = 1`) lets the joints with the largest noise decide, which
//! on an arm whose torques span two orders of magnitude across joints
//! wastes the quiet ones. With [`JointWeighting::Noise`] the SDP is solved
//! with equal weights, whence each joint's residual RMS σ̂_j, then with
//! `w_j ∝ 1/σ̂_j²`, σ̂ re-estimated from each solution until it settles
//! (iterated feasible weighted least squares: the first σ̂ of a quiet
//! joint holds the loud joints' noise the equal fit let in). The
//! weights are scaled to mean 1, so the prior's weight means what it
//! means unweighted. Weighting needs the per-joint Gram matrices of the
//! reduction ([`Reduced::joint_grams`]); the training RMS reported is the
//! unweighted one.

use super::error::IdentifyError;
use super::reduce::Reduced;
use faer::Mat;
use serde::Serialize;

/// How the joints' rows are weighted in the fit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "snake_case")]
pub enum JointWeighting {
    /// Every row weighs 1 (ordinary least squares).
    #[default]
    Equal,
    /// Joint j's rows weigh `1/σ̂_j²` (scaled to mean 1), σ̂_j its residual
    /// RMS after an equally weighted fit.
    Noise,
}

impl JointWeighting {
    /// The name in options and JSON (`equal`, `noise`).
    pub fn as_str(self) -> &'static str {
        match self {
            JointWeighting::Equal => "equal",
            JointWeighting::Noise => "noise",
        }
    }
}

/// Weights `∝ 1/σ_j²`, scaled to mean 1, for per-joint noise levels
/// `sigma` (N·m; a σ below 1e-3 of the largest, or below 1e-9 N·m, counts
/// as that: a joint the model fits exactly does not take every weight, and
/// the weights differ by at most 1e6).
pub fn noise_weights(sigma: &[f64]) -> Vec<f64> {
    let top = sigma.iter().cloned().fold(0.0, f64::max);
    let floor = (1e-3 * top).max(1e-9);
    let raw: Vec<f64> = sigma.iter().map(|s| 1.0 / s.max(floor).powi(2)).collect();
    let mean = raw.iter().sum::<f64>() / raw.len().max(1) as f64;
    raw.iter().map(|w| w / mean).collect()
}

/// The most weighted solves of one fit ([`JointWeighting::Noise`]).
pub const PASSES: usize = 10;

/// Whether the noise estimates moved by under 1 % (relative) on every
/// joint from `a` to `b`.
pub fn settled(a: &[f64], b: &[f64]) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (y - x).abs() <= 1e-2 * x.abs().max(f64::MIN_POSITIVE))
}

/// `red` with joint j's rows weighted by `w[j]`: the Gram matrix
/// `Σ_j w_j G_j`; the per-joint matrices are kept unweighted (for the
/// unweighted residuals). An error when `red` did not keep them.
pub fn weighted(red: &Reduced, w: &[f64]) -> Result<Reduced, IdentifyError> {
    if red.joint_grams.len() != w.len() {
        return Err(IdentifyError::JointGramsMissing {
            joints: w.len(),
            kept: red.joint_grams.len(),
        });
    }
    let p1 = red.p + 1;
    let mut gram = Mat::<f64>::zeros(p1, p1);
    for (g, &wj) in red.joint_grams.iter().zip(w) {
        gram += g * wj;
    }
    let mut out = Reduced::from_gram(gram, red.samples)?;
    out.row_range = red.row_range.clone();
    out.joint_grams = red.joint_grams.clone();
    out.reduce_time_s = red.reduce_time_s;
    Ok(out)
}

/// Per joint, the residual RMS of `theta` on `red` (`√(RSS_j / samples)`),
/// from its per-joint Gram matrices; an error when they were not kept.
pub fn joint_rms(red: &Reduced, theta: &[f64], joints: usize) -> Result<Vec<f64>, IdentifyError> {
    let rss = red
        .joint_rss(theta)
        .ok_or(IdentifyError::JointGramsMissing {
            joints,
            kept: red.joint_grams.len(),
        })?;
    Ok(rss
        .iter()
        .map(|r| (r / red.samples as f64).sqrt())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::noise_weights;

    /// Weights are 1/σ² scaled to mean 1; a zero σ is floored, not
    /// infinite.
    #[test]
    fn weights_are_inverse_variances_of_mean_one() {
        let w = noise_weights(&[1.0, 0.5, 2.0]);
        let raw = [1.0, 4.0, 0.25];
        let mean = raw.iter().sum::<f64>() / 3.0;
        for (a, b) in w.iter().zip(raw) {
            assert!((a - b / mean).abs() < 1e-12, "{w:?}");
        }
        let z = noise_weights(&[0.0, 1.0]);
        assert!(
            z.iter().all(|x| x.is_finite()) && z[0] > 1e5 * z[1],
            "{z:?}"
        );
        let none = noise_weights(&[0.0, 0.0]);
        assert_eq!(none, vec![1.0, 1.0]);
    }
}
