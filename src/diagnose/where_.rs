//! Where the gap lies: the held-out residual `τ − τ_model` per joint, broken
//! down by motion regime, position, frequency band and time, with whiteness
//! and cross-correlation checks.

use rustfft::{FftPlanner, num_complex::Complex};
use serde::Serialize;

/// Residual statistics of one group of samples of one joint.
#[derive(Clone, Debug, Serialize)]
pub struct Bin {
    /// What the group is.
    pub label: String,
    /// Samples in it.
    pub samples: usize,
    /// RMS of the residual (N·m).
    pub rms: f64,
    /// Mean of the residual (N·m).
    pub bias: f64,
}

/// One joint's analysis.
#[derive(Clone, Debug, Serialize)]
pub struct JointWhere {
    /// Joint name.
    pub joint: String,
    /// RMS of the residual (N·m).
    pub rms: f64,
    /// Mean of the residual (N·m).
    pub bias: f64,
    /// RMS of the measured torque (N·m), the scale.
    pub torque_rms: f64,
    /// Noise-floor estimate from first differences, `RMS(Δr)/√2` (N·m):
    /// white measurement noise shows up here; slow model errors do not.
    pub noise_floor: f64,
    /// The measured torque looks low-pass filtered
    /// ([`super::floor::looks_low_passed`]): `noise_floor` is then a lower
    /// bound. (The torque, not the residual: a model's Coulomb steps at
    /// velocity reversals put broadband content into the residual of
    /// filtered data.)
    pub low_passed: bool,
    /// By velocity: near zero, reversals, and |q̇| bins with sign.
    pub by_velocity: Vec<Bin>,
    /// By acceleration magnitude.
    pub by_acceleration: Vec<Bin>,
    /// By position quartile.
    pub by_position: Vec<Bin>,
    /// By time (consecutive fifths).
    pub by_time: Vec<Bin>,
    /// Residual variance per frequency band, `(label, share of variance)`.
    pub spectrum: Vec<(String, f64)>,
    /// Autocorrelation at lags 1..=20 samples.
    pub autocorrelation: Vec<f64>,
    /// The 99 % band for white noise, `2.576/√N`.
    pub whiteness_band: f64,
    /// Ljung–Box Q over 20 lags (χ²₂₀ 99 % quantile: 37.57).
    pub ljung_box_q: f64,
    /// Correlation of the residual with q, q̇, sign(q̇), q̈ and τ.
    pub cross_correlation: Vec<(String, f64)>,
}

fn stats(label: String, r: &[f64], idx: impl Iterator<Item = usize>) -> Bin {
    let v: Vec<f64> = idx.map(|k| r[k]).collect();
    let n = v.len().max(1) as f64;
    Bin {
        label,
        samples: v.len(),
        rms: crate::data::rms(v.iter().copied()),
        bias: v.iter().sum::<f64>() / n,
    }
}

fn corr(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()) as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma).powi(2);
        sbb += (y - mb).powi(2);
    }
    if saa > 0.0 && sbb > 0.0 {
        sab / (saa * sbb).sqrt()
    } else {
        0.0
    }
}

fn quantile(v: &[f64], q: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[((s.len() - 1) as f64 * q) as usize]
}

/// Analyses one joint's residual `r` against its signals (sampled at `fs` Hz).
#[allow(clippy::too_many_arguments)]
pub fn analyse_joint(
    joint: &str,
    r: &[f64],
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    tau: &[f64],
    sampling: &Sampling,
) -> JointWhere {
    let n = r.len();
    let fs = sampling.fs;
    let all = stats("all".into(), r, 0..n);
    let edges = [0.0, 1.0, 5.0, 20.0, fs / 2.0];
    let spectrum = band_shares(r, all.bias, sampling, &edges);
    let autocorrelation = autocorrelation(r, 20);
    JointWhere {
        joint: joint.into(),
        rms: all.rms,
        bias: all.bias,
        torque_rms: crate::data::rms(tau.iter().copied()),
        noise_floor: noise_floor(r, sampling.segments),
        low_passed: super::floor::looks_low_passed(tau, sampling.segments),
        by_velocity: by_velocity(r, qd, fs),
        by_acceleration: by_acceleration(r, qdd),
        by_position: by_position(r, q),
        by_time: (0..5)
            .map(|b| {
                stats(
                    format!("time fifth {}", b + 1),
                    r,
                    (b * n / 5)..((b + 1) * n / 5),
                )
            })
            .collect(),
        spectrum,
        ljung_box_q: ljung_box(&autocorrelation, n),
        autocorrelation,
        whiteness_band: 2.576 / (n.max(1) as f64).sqrt(),
        cross_correlation: cross_correlation(r, q, qd, qdd, tau),
    }
}

/// How the residual was sampled: the rate (Hz) and the segments (sample
/// ranges, in order, covering the residual) that no difference or spectrum
/// crosses (a file boundary or a gap in the recording).
#[derive(Clone, Debug)]
pub struct Sampling<'a> {
    /// Samples per second within a segment.
    pub fs: f64,
    /// The segments.
    pub segments: &'a [std::ops::Range<usize>],
}

/// The white-noise level of `r` from its first differences within each
/// segment: `√(mean Δr² / 2)`.
fn noise_floor(r: &[f64], segments: &[std::ops::Range<usize>]) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for s in segments {
        for w in r[s.clone()].windows(2) {
            sum += (w[1] - w[0]).powi(2);
            count += 1;
        }
    }
    if count > 0 {
        (sum / count as f64 / 2.0).sqrt()
    } else {
        0.0
    }
}

/// The residual near zero velocity, at velocity reversals (within 20 ms),
/// and in bands of positive and negative velocity.
fn by_velocity(r: &[f64], qd: &[f64], fs: f64) -> Vec<Bin> {
    let n = r.len();
    let vmax = qd.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let slow = 0.05 * vmax.max(1e-9);
    let window = (0.02 * fs).ceil() as usize;
    let reversal: Vec<bool> = (0..n)
        .map(|k| {
            let lo = k.saturating_sub(window);
            let hi = (k + window).min(n - 1);
            (lo..hi).any(|j| qd[j].signum() != qd[j + 1].signum())
        })
        .collect();
    let mut bins = vec![
        stats(
            "near zero velocity".into(),
            r,
            (0..n).filter(|&k| qd[k].abs() < slow),
        ),
        stats(
            "at velocity reversals".into(),
            r,
            (0..n).filter(|&k| reversal[k]),
        ),
    ];
    for (lo, hi) in [(0.05f64, 0.35f64), (0.35, 0.7), (0.7, 1.01)] {
        for s in [1.0, -1.0] {
            bins.push(stats(
                format!(
                    "{} velocity, {:.0}–{:.0} % of max",
                    if s > 0.0 { "positive" } else { "negative" },
                    100.0 * lo,
                    100.0 * hi.min(1.0)
                ),
                r,
                (0..n).filter(|&k| qd[k] * s > lo * vmax && qd[k] * s <= hi * vmax),
            ));
        }
    }
    bins
}

/// The residual in bands of |q̈|.
fn by_acceleration(r: &[f64], qdd: &[f64]) -> Vec<Bin> {
    let n = r.len();
    let amax = qdd.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-9);
    [(0.0f64, 0.2f64), (0.2, 0.5), (0.5, 1.01)]
        .iter()
        .map(|&(lo, hi)| {
            stats(
                format!("|q̈| {:.0}–{:.0} % of max", 100.0 * lo, 100.0 * hi.min(1.0)),
                r,
                (0..n).filter(|&k| qdd[k].abs() >= lo * amax && qdd[k].abs() < hi * amax),
            )
        })
        .collect()
}

/// The residual in the position's quartiles.
fn by_position(r: &[f64], q: &[f64]) -> Vec<Bin> {
    let n = r.len();
    let qs = [
        quantile(q, 0.0),
        quantile(q, 0.25),
        quantile(q, 0.5),
        quantile(q, 0.75),
        quantile(q, 1.0) + 1e-12,
    ];
    (0..4)
        .map(|b| {
            stats(
                format!("q in [{:.2}, {:.2}) rad", qs[b], qs[b + 1]),
                r,
                (0..n).filter(|&k| q[k] >= qs[b] && q[k] < qs[b + 1]),
            )
        })
        .collect()
}

/// The autocorrelation of `r` at lags 1 … `lags`.
fn autocorrelation(r: &[f64], lags: usize) -> Vec<f64> {
    let n = r.len();
    (1..=lags)
        .map(|l| {
            if n > l {
                corr(&r[..n - l], &r[l..])
            } else {
                0.0
            }
        })
        .collect()
}

/// The Ljung–Box statistic of the autocorrelations `rho` of `n` samples.
fn ljung_box(rho: &[f64], n: usize) -> f64 {
    n as f64
        * (n as f64 + 2.0)
        * rho
            .iter()
            .enumerate()
            .map(|(i, r)| r * r / (n - i - 1).max(1) as f64)
            .sum::<f64>()
}

/// The residual's correlation with q, q̇, sign(q̇), q̈ and τ.
fn cross_correlation(
    r: &[f64],
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    tau: &[f64],
) -> Vec<(String, f64)> {
    let sq: Vec<f64> = qd.iter().map(|v| v.signum()).collect();
    vec![
        ("q".to_string(), corr(r, q)),
        ("q̇".to_string(), corr(r, qd)),
        ("sign(q̇)".to_string(), corr(r, &sq)),
        ("q̈".to_string(), corr(r, qdd)),
        ("τ".to_string(), corr(r, tau)),
    ]
}

/// A one-line summary of where a joint's gap lies.
pub fn summarise(w: &JointWhere) -> String {
    let worst = w
        .by_velocity
        .iter()
        .filter(|b| b.samples > 20)
        .max_by(|a, b| a.rms.total_cmp(&b.rms));
    let band = w.spectrum.iter().max_by(|a, b| a.1.total_cmp(&b.1));
    let white = w.ljung_box_q < 37.57;
    let mut s = format!(
        "{}: residual RMS {:.3} N·m ({:.0} % of the torque RMS), bias {:+.3}",
        w.joint,
        w.rms,
        100.0 * w.rms / w.torque_rms.max(1e-12),
        w.bias
    );
    if let Some(b) = worst {
        s += &format!("; largest {} ({:.3} N·m)", b.label, b.rms);
    }
    if let Some((l, share)) = band {
        s += &format!("; {:.0} % of its variance in {l}", 100.0 * share);
    }
    s += if white {
        "; residual is white"
    } else {
        "; residual is correlated (structure left)"
    };
    s
}

/// The shares of the residual's variance (about `mean`) in the frequency
/// bands between `edges` (Hz; the last band includes its upper edge), from
/// each segment's periodogram, summed (no spectrum spans a boundary): by
/// Parseval the shares sum to 1 (all 0 for a constant residual).
fn band_shares(r: &[f64], mean: f64, sampling: &Sampling, edges: &[f64]) -> Vec<(String, f64)> {
    let bands = edges.len().saturating_sub(1);
    let mut power = vec![0.0; bands];
    let mut planner = FftPlanner::new();
    for seg in sampling.segments {
        let n = seg.len();
        if n < 2 || bands == 0 {
            continue;
        }
        let mut x: Vec<Complex<f64>> = r[seg.clone()]
            .iter()
            .map(|v| Complex::new(v - mean, 0.0))
            .collect();
        planner.plan_fft_forward(n).process(&mut x);
        // the DC bin of a segment holds its mean's offset from the whole's:
        // variance too, at 0 Hz
        for (k, c) in x.iter().enumerate() {
            let f = k.min(n - k) as f64 * sampling.fs / n as f64;
            let b = edges[1..bands].iter().filter(|&&e| f >= e).count();
            power[b] += c.norm_sqr() / n as f64;
        }
    }
    let total: f64 = power.iter().sum();
    edges
        .windows(2)
        .zip(power)
        .map(|(w, p)| {
            let share = if total > 0.0 { p / total } else { 0.0 };
            (format!("{:.0}–{:.0} Hz", w[0], w[1]), share)
        })
        .collect()
}

#[cfg(test)]
mod band_tests {
    use super::{Sampling, band_shares};

    fn one(fs: f64, n: usize) -> (f64, Vec<std::ops::Range<usize>>) {
        (fs, vec![0..n])
    }

    #[test]
    fn band_shares_are_shares_of_the_variance() {
        let fs = 1000.0;
        let edges = [0.0, 1.0, 5.0, 20.0, 500.0];
        // 10 Hz (variance 0.5) and 100 Hz (variance 0.125), 3 s, with an offset
        let r: Vec<f64> = (0..3000)
            .map(|k| {
                let t = k as f64 / fs;
                2.0 + (std::f64::consts::TAU * 10.0 * t).sin()
                    + 0.5 * (std::f64::consts::TAU * 100.0 * t).sin()
            })
            .collect();
        let (fs, seg) = one(fs, r.len());
        let at = Sampling { fs, segments: &seg };
        let s = band_shares(&r, 2.0, &at, &edges);
        let total: f64 = s.iter().map(|b| b.1).sum();
        assert!((total - 1.0).abs() < 1e-12, "{s:?}");
        assert!(
            (s[2].1 - 0.8).abs() < 1e-9 && (s[3].1 - 0.2).abs() < 1e-9,
            "{s:?}"
        );
        assert!(s[0].1 < 1e-12 && s[1].1 < 1e-12, "{s:?}");
        assert_eq!(s[2].0, "5–20 Hz");
        // a constant residual has no variance to share
        assert!(
            band_shares(
                &[1.0; 100],
                1.0,
                &Sampling {
                    fs,
                    segments: &[0..100]
                },
                &edges
            )
            .iter()
            .all(|b| b.1 == 0.0)
        );
    }
}

#[cfg(test)]
mod segment_tests {
    use super::{Sampling, band_shares, noise_floor};
    use std::f64::consts::TAU;

    /// Two recordings of a 10 Hz residual joined with a phase jump: per
    /// segment, all its variance is at 10 Hz and the noise floor is the
    /// sine's own; spanning the boundary, the jump leaks into every band
    /// and raises the floor.
    #[test]
    fn no_spectrum_or_difference_crosses_a_segment_boundary() {
        let fs = 1000.0;
        let edges = [0.0, 1.0, 5.0, 20.0, 500.0];
        let sine = |k: usize, phase: f64| (TAU * 10.0 * k as f64 / fs + phase).sin();
        let r: Vec<f64> = (0..1500)
            .map(|k| sine(k, 0.0))
            .chain((0..1500).map(|k| sine(k, 2.0)))
            .collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let two = [0..1500, 1500..3000];
        let split = Sampling { fs, segments: &two };
        let s = band_shares(&r, mean, &split, &edges);
        assert!((s[2].1 - 1.0).abs() < 1e-9, "{s:?}");
        let whole = Sampling {
            fs,
            segments: &[0..3000],
        };
        let joined = band_shares(&r, mean, &whole, &edges);
        assert!(joined[2].1 < 1.0 - 1e-4, "{joined:?}");
        let (a, b) = (noise_floor(&r, &two), noise_floor(&r, &[0..3000]));
        let own = TAU * 10.0 / fs / 2.0; // √(mean Δ² / 2) of a unit sine
        assert!(
            (a - own).abs() < 1e-3 * own && b > 1.05 * a,
            "{a} {b} {own}"
        );
    }
}
