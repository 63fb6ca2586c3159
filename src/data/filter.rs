//! Offline signal processing: zero-phase Butterworth low-pass and
//! differentiation, as used to get q̇ and q̈ from encoder positions.
//!
//! The low-pass is a 2nd-order Butterworth section designed by the bilinear
//! transform with pre-warping (so the −3 dB point of one pass is exactly at
//! `cutoff`), run forward then backward (`filtfilt`): zero phase, magnitude
//! `|H(f)|² = 1 / (1 + (tan(πf/fs)/tan(πfc/fs))⁴)`. The ends are padded by odd
//! reflection so that a ramp passes undistorted.

use crate::dynamics::Samples;

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
            let (a, b) = stencil(i, n);
            (x[b] - x[a]) / (t[b] - t[a])
        })
        .collect()
}

/// The samples the derivative at `i` of `n` (≥ 2) differences: central
/// inside, one-sided at the ends.
fn stencil(i: usize, n: usize) -> (usize, usize) {
    if i == 0 {
        (0, 1)
    } else if i == n - 1 {
        (n - 2, n - 1)
    } else {
        (i - 1, i + 1)
    }
}

/// [`filtfilt`] of every column of `x` (rows: samples at `fs` Hz), all
/// columns in one sweep: the same values as column by column, without
/// copying a column out.
pub fn filtfilt_columns(x: &Samples, cutoff: f64, fs: f64) -> Samples {
    let (n, w) = (x.len(), x.width());
    if n < 3 || w == 0 || !(cutoff > 0.0 && cutoff < fs / 2.0) {
        return x.clone();
    }
    let pad = ((3.0 * fs / cutoff).ceil() as usize).min(n - 1);
    // odd reflection at both ends, row by row
    let mut ext = Samples::with_capacity(w, n + 2 * pad);
    for i in (1..=pad).rev() {
        ext.push_with(|j| 2.0 * x[0][j] - x[i][j]);
    }
    for r in x {
        ext.push(r);
    }
    for i in 1..=pad {
        ext.push_with(|j| 2.0 * x[n - 1][j] - x[n - 1 - i][j]);
    }
    let f = Biquad::butterworth_lowpass(cutoff, fs);
    let buf = ext.as_flat_mut();
    f.run_rows(buf, w, false);
    f.run_rows(buf, w, true);
    ext.keep(pad..pad + n);
    ext
}

impl Biquad {
    /// [`Biquad::run`] in place on each column of the row-major `buf`
    /// (`w` columns), backward when `reverse`; the states of all columns
    /// advance together (one row at a time).
    fn run_rows(&self, buf: &mut [f64], w: usize, reverse: bool) {
        let rows = buf.len() / w;
        let at = |k: usize| if reverse { rows - 1 - k } else { k };
        let first = buf[at(0) * w..at(0) * w + w].to_vec();
        let (mut x1, mut x2) = (first.clone(), first.clone());
        let (mut y1, mut y2) = (first.clone(), first);
        for k in 0..rows {
            let row = &mut buf[at(k) * w..at(k) * w + w];
            for j in 0..w {
                let xi = row[j];
                let yi = self.b[0] * xi + self.b[1] * x1[j] + self.b[2] * x2[j]
                    - self.a[0] * y1[j]
                    - self.a[1] * y2[j];
                (x2[j], x1[j], y2[j], y1[j]) = (x1[j], xi, y1[j], yi);
                row[j] = yi;
            }
        }
    }
}

/// [`differentiate`] of every column of `x` (rows: samples at times `t`).
pub fn differentiate_columns(x: &Samples, t: &[f64]) -> Samples {
    let n = x.len();
    if n < 2 {
        return Samples::zeros(n, x.width());
    }
    let mut out = Samples::with_capacity(x.width(), n);
    for i in 0..n {
        let (a, b) = stencil(i, n);
        let dt = t[b] - t[a];
        out.push_with(|j| (x[b][j] - x[a][j]) / dt);
    }
    out
}

/// q̈ from q̇: zero-phase low-pass at `cutoff_hz`, then central differences.
pub fn estimate_qdd(t: &[f64], qd: &Samples, cutoff_hz: f64) -> Samples {
    let fs = if t.len() > 1 {
        (t.len() - 1) as f64 / (t[t.len() - 1] - t[0])
    } else {
        1.0
    };
    differentiate_columns(&filtfilt_columns(qd, cutoff_hz, fs), t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All columns at once give, bit for bit, what each column alone gives.
    #[test]
    fn columns_together_equal_columns_alone() {
        let (n, w, fs) = (300, 3, 200.0);
        let t: Vec<f64> = (0..n)
            .map(|k| k as f64 / fs + 1e-4 * (k % 3) as f64)
            .collect();
        let x = Samples::from_rows(
            &(0..n)
                .map(|k| {
                    (0..w)
                        .map(|j| ((k * (j + 1)) as f64 * 0.07).sin() + j as f64)
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>(),
        );
        let f = filtfilt_columns(&x, 12.0, fs);
        let d = differentiate_columns(&f, &t);
        for j in 0..w {
            let fj = filtfilt(&x.column(j), 12.0, fs);
            assert_eq!(f.column(j), fj, "filter, column {j}");
            assert_eq!(
                d.column(j),
                differentiate(&fj, &t),
                "derivative, column {j}"
            );
        }
    }
}
