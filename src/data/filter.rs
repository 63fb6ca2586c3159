//! Offline signal processing: zero-phase Butterworth low-pass and
//! differentiation, as used to get q̇ and q̈ from encoder positions.
//!
//! The low-pass is a 2nd-order Butterworth section designed by the bilinear
//! transform with pre-warping (so the −3 dB point of one pass is exactly at
//! `cutoff`), run forward then backward (`filtfilt`): zero phase, magnitude
//! `|H(f)|² = 1 / (1 + (tan(πf/fs)/tan(πfc/fs))⁴)`. The ends are padded by odd
//! reflection so that a ramp passes undistorted.

/// Biquad coefficients `(b0, b1, b2, a1, a2)` (a0 = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    /// 2nd-order Butterworth low-pass at `cutoff` Hz for sampling rate `fs` Hz.
    pub fn butterworth_lowpass(cutoff: f64, fs: f64) -> Self {
        let k = (std::f64::consts::PI * cutoff / fs).tan();
        let q = std::f64::consts::FRAC_1_SQRT_2;
        let norm = 1.0 / (1.0 + k / q + k * k);
        let b0 = k * k * norm;
        Self {
            b: [b0, 2.0 * b0, b0],
            a: [2.0 * (k * k - 1.0) * norm, (1.0 - k / q + k * k) * norm],
        }
    }

    /// Squared magnitude of one pass at frequency f (Hz): the gain of the
    /// zero-phase forward–backward filter.
    pub fn filtfilt_gain(cutoff: f64, fs: f64, f: f64) -> f64 {
        let r = (std::f64::consts::PI * f / fs).tan() / (std::f64::consts::PI * cutoff / fs).tan();
        1.0 / (1.0 + r.powi(4))
    }

    fn run(&self, x: &[f64]) -> Vec<f64> {
        let mut y = Vec::with_capacity(x.len());
        // start in steady state for the first value
        let x0 = x.first().copied().unwrap_or(0.0);
        let (mut x1, mut x2, mut y1, mut y2) = (x0, x0, x0, x0);
        for &xi in x {
            let yi =
                self.b[0] * xi + self.b[1] * x1 + self.b[2] * x2 - self.a[0] * y1 - self.a[1] * y2;
            x2 = x1;
            x1 = xi;
            y2 = y1;
            y1 = yi;
            y.push(yi);
        }
        y
    }
}

/// Zero-phase low-pass of `x` (sampled at `fs` Hz) with −6 dB at `cutoff` Hz.
/// Fewer than 3 samples, or a cut-off that is not in (0, fs/2), return `x`
/// unchanged: callers check the cut-off against the rate first (the CSV
/// reader and `SimConfig::validate` make that an error).
pub fn filtfilt(x: &[f64], cutoff: f64, fs: f64) -> Vec<f64> {
    let n = x.len();
    if n < 3 || !(cutoff > 0.0 && cutoff < fs / 2.0) {
        return x.to_vec();
    }
    let pad = (3.0 * fs / cutoff).ceil() as usize;
    let pad = pad.min(n - 1);
    // odd reflection at both ends
    let mut ext = Vec::with_capacity(n + 2 * pad);
    for i in (1..=pad).rev() {
        ext.push(2.0 * x[0] - x[i]);
    }
    ext.extend_from_slice(x);
    for i in 1..=pad {
        ext.push(2.0 * x[n - 1] - x[n - 1 - i]);
    }
    let f = Biquad::butterworth_lowpass(cutoff, fs);
    let mut y = f.run(&ext);
    y.reverse();
    let mut y = f.run(&y);
    y.reverse();
    y[pad..pad + n].to_vec()
}

/// Derivative by central differences (one-sided at the ends) for samples
/// at times `t` (s), which need not be uniform.
pub fn differentiate(x: &[f64], t: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n < 2 {
        return vec![0.0; n];
    }
    (0..n)
        .map(|i| {
            let (a, b) = if i == 0 {
                (0, 1)
            } else if i == n - 1 {
                (n - 2, n - 1)
            } else {
                (i - 1, i + 1)
            };
            (x[b] - x[a]) / (t[b] - t[a])
        })
        .collect()
}

/// q̈ from q̇: zero-phase low-pass at `cutoff_hz`, then central differences.
pub fn estimate_qdd(t: &[f64], qd: &[Vec<f64>], cutoff_hz: f64) -> Vec<Vec<f64>> {
    let n = qd.first().map_or(0, |v| v.len());
    let fs = if t.len() > 1 {
        (t.len() - 1) as f64 / (t[t.len() - 1] - t[0])
    } else {
        1.0
    };
    let mut out = vec![vec![0.0; n]; t.len()];
    for j in 0..n {
        let x: Vec<f64> = qd.iter().map(|r| r[j]).collect();
        let d = differentiate(&filtfilt(&x, cutoff_hz, fs), t);
        for (k, v) in d.into_iter().enumerate() {
            out[k][j] = v;
        }
    }
    out
}
