//! The low-pass cut-off chosen from the data: where the positions' power
//! spectrum meets its noise floor.
//!
//! Welch's estimate of each joint's q spectrum (windows of [`WINDOW`]
//! samples, half overlapping, linear trend removed, a 4-term
//! Blackman–Harris window whose −92 dB side lobes keep the large
//! low-frequency motion from leaking over the floor); the noise floor is
//! the median over the upper half of the band. The excitation's band ends
//! where the spectrum, averaged over 4 bins and followed up from its peak,
//! first falls below [`SNR`] times the floor; the edge is the highest of the
//! joints'. The cut-off is
//! [`MARGIN`] times that edge, within `[fs/100, 0.4 fs]`. The same
//! signal-to-noise ratio holds for q̈ and τ's inertial part, which are q
//! weighted by f⁴ in the same bins.

use super::raw::RawLog;
use rustfft::{Fft, FftPlanner, num_complex::Complex};

/// Samples per Welch window (shorter segments use their largest power of 2).
pub const WINDOW: usize = 1024;
/// How far above the noise floor the excitation's band reaches.
pub const SNR: f64 = 10.0;
/// The cut-off over the band's edge.
pub const MARGIN: f64 = 1.5;

/// The cut-off (Hz) for uniform segments sampled at `fs` Hz, and how it
/// was chosen (for the report).
pub fn choose_cutoff(segments: &[RawLog], fs: f64) -> (f64, String) {
    let longest = segments.iter().map(RawLog::len).max().unwrap_or(0);
    let l = WINDOW.min(prev_power_of_two(longest));
    let fallback = (
        0.1 * fs,
        format!("fs/10 = {:.3} Hz: too little data for a spectrum", 0.1 * fs),
    );
    if l < 64 {
        return fallback;
    }
    let nj = segments.first().map_or(0, |s| s.q.width());
    let fft = FftPlanner::new().plan_fft_forward(l);
    let mut edge: f64 = 0.0;
    for j in 0..nj {
        let psd = welch(segments, j, l, &*fft);
        let upper: Vec<f64> = psd[l / 4..].to_vec();
        let floor = median(upper);
        if !(floor > 0.0) {
            continue;
        }
        // from the motion's peak up to where the spectrum meets the floor
        let mean4 = |f: usize| psd[f..f + 4].iter().sum::<f64>() / 4.0;
        let last = psd.len().saturating_sub(4);
        let peak = (1..last)
            .max_by(|&a, &b| psd[a].total_cmp(&psd[b]))
            .unwrap_or(1);
        let above = (peak..last).take_while(|&f| mean4(f) > SNR * floor).last();
        if let Some(f) = above {
            edge = edge.max((f + 3) as f64 * fs / l as f64);
        }
    }
    if edge <= 0.0 {
        return fallback;
    }
    let cutoff = (MARGIN * edge).clamp(fs / 100.0, 0.4 * fs);
    (
        cutoff,
        format!(
            "from the data: the positions' spectrum is {SNR}× its noise floor up to {edge:.3} Hz; cut-off {MARGIN}× that (Welch, {l}-sample windows)"
        ),
    )
}

fn prev_power_of_two(n: usize) -> usize {
    if n == 0 {
        0
    } else {
        1 << (usize::BITS - 1 - n.leading_zeros())
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Welch's power spectrum of joint `j`'s q over every segment, bins
/// `0..=l/2`.
fn welch(segments: &[RawLog], j: usize, l: usize, fft: &dyn Fft<f64>) -> Vec<f64> {
    let mut psd = vec![0.0; l / 2 + 1];
    for s in segments.iter().filter(|s| s.len() >= l) {
        welch_add(&s.q.column(j), l, fft, &mut psd);
    }
    psd
}

/// Adds Welch's power spectrum of `x` (windows of `l` samples, half
/// overlapping, each detrended and Blackman–Harris windowed; `fft` of
/// length `l`) to `psd` (bins `0..=l/2`, unnormalised); nothing when `x`
/// is shorter than `l`.
pub fn welch_add(x: &[f64], l: usize, fft: &dyn Fft<f64>, psd: &mut [f64]) {
    if x.len() < l || l < 2 {
        return;
    }
    let w: Vec<f64> = (0..l).map(|k| blackman_harris(k, l)).collect();
    for start in (0..=x.len() - l).step_by(l / 2) {
        let seg = detrended(&x[start..start + l]);
        let mut buf: Vec<Complex<f64>> = seg
            .iter()
            .zip(&w)
            .map(|(a, b)| Complex::new(a * b, 0.0))
            .collect();
        fft.process(&mut buf);
        psd.iter_mut()
            .zip(&buf)
            .for_each(|(p, c)| *p += c.norm_sqr());
    }
}

/// `x` minus its least-squares line.
fn detrended(x: &[f64]) -> Vec<f64> {
    let n = x.len() as f64;
    let mt = (n - 1.0) / 2.0;
    let mx = x.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (k, v) in x.iter().enumerate() {
        let d = k as f64 - mt;
        sxy += d * (v - mx);
        sxx += d * d;
    }
    let b = sxy / sxx;
    x.iter()
        .enumerate()
        .map(|(k, v)| v - mx - b * (k as f64 - mt))
        .collect()
}

/// The 4-term Blackman–Harris window (−92 dB side lobes), sample `k` of
/// `l`.
pub fn blackman_harris(k: usize, l: usize) -> f64 {
    let x = 2.0 * std::f64::consts::PI * k as f64 / (l - 1) as f64;
    0.35875 - 0.48829 * x.cos() + 0.14128 * (2.0 * x).cos() - 0.01168 * (3.0 * x).cos()
}
