//! The raw-log low-pass cut-off chosen by held-out torque error.
//!
//! The spectrum of q ([`crate::data::spectrum::choose_cutoff`]) says where
//! the motion meets the position noise, not where the torques and q̈ are
//! clean: on a 1 kHz log it picks hundreds of hertz, and q̈ comes out as
//! noise. Here each cut-off of a grid — from [`LOWEST_HZ`] up to the
//! spectrum's choice, a factor √2 apart, the spectrum's choice the top —
//! is scored by what it leads to:
//!
//! 1. every training log made uniform once (repeats dropped, split at
//!    gaps, resampled: [`crate::data::prepare::uniform_segments`]);
//! 2. per cut-off, each segment low-passed and differentiated as `identify`
//!    would, the ends trimmed by the *lowest* cut-off's period for every
//!    candidate (the same samples for all), every `stride`-th sample kept
//!    (at most [`MAX_SCORED`] in all; the candidates are scored in
//!    parallel);
//! 3. the model's regressor (its links and its friction columns) fitted by
//!    least squares on [`FOLDS`] − 1 of [`FOLDS`] blocks of time of every
//!    segment against the torques low-passed at that cut-off (what the
//!    identification fits), and scored on the block left out against the
//!    **raw torques** (resampled, not filtered): the same target for every
//!    candidate, so a low cut-off cannot win by smoothing its own target;
//! 4. the score is the mean over joints of the held-out RMS pooled over the
//!    folds; the lowest wins, and the whole curve is kept ([`CutoffCurve`]).
//!
//! The raw torques' own noise adds the same amount to every candidate's
//! mean square, so the ranking is that of the error against the true
//! torque. The fit is unconstrained (a tiny ridge for the directions the
//! data do not see): the cut-off is chosen for the data, before any
//! constraint level or prior.

use super::error::IdentifyError;
use super::gram::{add_products, scattered};
use crate::data::prepare::{filter_segment, uniform_segments};
use crate::data::spectrum;
use crate::data::{DataError, RawLog, Velocity};
use crate::dynamics::{Data, Model, regressor_blocks, regressor_row_columns};
use faer::Mat;
use rayon::prelude::*;
use serde::Serialize;

/// The grid's lowest cut-off (Hz): below it a robot's excitation (periods
/// of seconds, a few harmonics) is cut.
pub const LOWEST_HZ: f64 = 2.0;
/// The ratio between neighbouring cut-offs of the grid.
pub const RATIO: f64 = std::f64::consts::SQRT_2;
/// The most samples scored per candidate (over every segment).
pub const MAX_SCORED: usize = 2000;
/// Blocks of time per segment; each is held out in turn.
pub const FOLDS: usize = 5;

/// The cut-off chosen and the curve it was chosen from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CutoffCurve {
    /// The cut-offs tried, increasing (Hz).
    pub cutoffs_hz: Vec<f64>,
    /// Per cut-off, each joint's held-out RMS against the raw torques,
    /// pooled over the folds (N·m).
    pub heldout_rms: Vec<Vec<f64>>,
    /// Per cut-off, the mean over joints of `heldout_rms` (N·m).
    pub mean_rms: Vec<f64>,
    /// The cut-off of the lowest `mean_rms` (Hz).
    pub chosen_hz: f64,
    /// What the spectrum of q chose (the grid's top, Hz).
    pub spectrum_hz: f64,
    /// Samples scored per candidate.
    pub scored_samples: usize,
}

impl CutoffCurve {
    /// How the cut-off was chosen, in words (for a file's report).
    pub fn words(&self) -> String {
        let curve: Vec<String> = (self.cutoffs_hz.iter().zip(&self.mean_rms))
            .map(|(c, r)| format!("{c:.3} Hz {r:.4}"))
            .collect();
        format!(
            "by held-out torque error ({FOLDS} blocks of time of the training logs, {} samples scored against the raw torques; mean RMS in N·m: {}); the spectrum gave {:.3} Hz",
            self.scored_samples,
            curve.join(", "),
            self.spectrum_hz
        )
    }
}

/// A training log made uniform: its segments and rate.
struct Uniform {
    segments: Vec<RawLog>,
    fs: f64,
}

/// Chooses the cut-off for `raws` (the training logs as read) by held-out
/// torque error of `model`'s regressor (module doc); `None` when no log is
/// raw (each has q̈: prepared, nothing to choose) or has torques, or when
/// the logs are too short for any candidate to be scored (the spectrum's
/// cut-off then stands, and the files' reports say so).
pub fn choose_cutoff(
    raws: &[RawLog],
    model: &Model,
    velocity: Velocity,
) -> Result<Option<CutoffCurve>, IdentifyError> {
    let logs: Vec<Uniform> = (raws.iter())
        .filter(|r| r.qdd.is_none() && r.tau.is_some() && !r.is_empty())
        .map(|r| uniform_segments(r.clone()).map(|(segments, fs)| Uniform { segments, fs }))
        .collect::<Result<_, DataError>>()
        .map_err(IdentifyError::Data)?;
    if logs.is_empty() {
        return Ok(None);
    }
    let top = (logs.iter())
        .map(|u| spectrum::choose_cutoff(&u.segments, u.fs).0)
        .fold(0.0, f64::max);
    let nyquist = logs
        .iter()
        .map(|u| 0.4 * u.fs)
        .fold(f64::INFINITY, f64::min);
    let grid = grid(top.min(nyquist));
    let trims: Vec<usize> = logs
        .iter()
        .map(|u| (u.fs / grid[0]).ceil() as usize)
        .collect();
    let total: usize = (logs.iter().zip(&trims))
        .flat_map(|(u, t)| {
            u.segments
                .iter()
                .map(move |s| s.len().saturating_sub(2 * t))
        })
        .sum();
    let stride = total.div_ceil(MAX_SCORED).max(1);
    let heldout_rms = (grid.par_iter())
        .map(|&c| score(&logs, &trims, stride, c, model, velocity))
        .collect::<Result<Vec<_>, _>>()?;
    let mean_rms: Vec<f64> = (heldout_rms.iter())
        .map(|r| r.iter().sum::<f64>() / r.len().max(1) as f64)
        .collect();
    let best = (0..grid.len())
        .filter(|&i| mean_rms[i].is_finite())
        .min_by(|&a, &b| mean_rms[a].total_cmp(&mean_rms[b]));
    let Some(best) = best else {
        // blocks too short to score any candidate: the spectrum's choice
        // stands (the files' reports say it is the spectrum's)
        return Ok(None);
    };
    Ok(Some(CutoffCurve {
        chosen_hz: grid[best],
        cutoffs_hz: grid,
        heldout_rms,
        mean_rms,
        spectrum_hz: top,
        scored_samples: total.div_ceil(stride),
    }))
}

/// Reads the training logs `paths` for `joints` as
/// [`crate::data::read_logs`] does, except that without a cut-off in
/// `opts` and with a raw log among them, the cut-off is chosen here
/// ([`choose_cutoff`]) and every raw log prepared with it (their reports
/// say so); each file is read once.
pub fn read_training(
    paths: &[&std::path::Path],
    joints: &[&str],
    opts: &crate::data::ReadOptions,
    model: &Model,
) -> Result<(crate::data::Reading, Option<CutoffCurve>), IdentifyError> {
    let t0 = std::time::Instant::now();
    let raws = crate::data::read_raw_logs(paths, joints, opts)?;
    let read_s = t0.elapsed().as_secs_f64();
    let choice = match opts.cutoff_hz {
        Some(_) => None,
        None => choose_cutoff(&raws, model, opts.velocity)?,
    };
    let t0 = std::time::Instant::now();
    let o = crate::data::ReadOptions {
        cutoff_hz: choice.as_ref().map(|c| c.chosen_hz).or(opts.cutoff_hz),
        ..opts.clone()
    };
    let mut reading = crate::data::prepare_logs(raws, joints, &o)?;
    (reading.read_s, reading.filter_s) = (read_s, t0.elapsed().as_secs_f64());
    if let Some(c) = &choice {
        mark_chosen(&mut reading.files, &c.words());
    }
    Ok((reading, choice))
}

/// The raw logs among `files` say their cut-off was chosen (`how`).
pub fn mark_chosen(files: &mut [crate::data::FileReport], how: &str) {
    for f in files.iter_mut().filter(|f| !f.taken_as_prepared) {
        f.cutoff_from = how.to_string();
    }
}

/// The cut-offs from [`LOWEST_HZ`] by [`RATIO`] below `top`, and `top`
/// (just `top` when it is under [`LOWEST_HZ`]).
fn grid(top: f64) -> Vec<f64> {
    let mut g: Vec<f64> = (0..)
        .map(|k| LOWEST_HZ * RATIO.powi(k))
        .take_while(|c| *c < top / 1.05)
        .collect();
    g.push(top);
    g
}

/// One joint's rows in one fold: its regressor row restricted to the
/// columns it can be non-zero in ([`regressor_row_columns`]) and the torque
/// it is fitted to (low-passed), a row per sample (row-major), and the
/// torques it is scored against (raw).
#[derive(Default)]
struct JointRows {
    rows: Vec<f64>,
    raw: Vec<f64>,
}

/// Each joint's held-out RMS at cut-off `c`, pooled over the folds.
fn score(
    logs: &[Uniform],
    trims: &[usize],
    stride: usize,
    c: f64,
    model: &Model,
    velocity: Velocity,
) -> Result<Vec<f64>, IdentifyError> {
    let (n, p) = (model.dof(), model.regressor_columns());
    let cols = regressor_row_columns(model);
    // where each column sits in each joint's compact row
    let mut at = vec![vec![usize::MAX; p]; n];
    (cols.iter().enumerate())
        .for_each(|(j, cs)| cs.iter().enumerate().for_each(|(a, &c)| at[j][c] = a));
    let mut folds: Vec<Vec<JointRows>> = (0..FOLDS)
        .map(|_| (0..n).map(|_| JointRows::default()).collect())
        .collect();
    let mut data = Data::new(model);
    let mut row: Vec<Vec<f64>> = cols.iter().map(|c| vec![0.0; c.len()]).collect();
    let mut sample = 0usize;
    for (u, &trim) in logs.iter().zip(trims) {
        for seg in &u.segments {
            let Some(d) = filter_segment(seg, u.fs, c, velocity, trim) else {
                continue;
            };
            let raw_tau = seg.tau.as_ref().expect("logs with torques only");
            for k in (0..d.len()).step_by(stride) {
                data.load
                    .iter_mut()
                    .zip(&d.tau[k])
                    .for_each(|(l, t)| *l = *t);
                row.iter_mut().for_each(|r| r.fill(0.0));
                regressor_blocks(
                    model,
                    &mut data,
                    [&d.q[k], &d.qd[k], &d.qdd[k]],
                    |j, c0, v| (v.iter().enumerate()).for_each(|(a, x)| row[j][at[j][c0 + a]] += x),
                )
                .map_err(|source| IdentifyError::Regressor { sample, source })?;
                let fold = &mut folds[FOLDS * k / d.len()];
                for (j, jr) in fold.iter_mut().enumerate() {
                    jr.rows.extend_from_slice(&row[j]);
                    jr.rows.push(d.tau[k][j]);
                    jr.raw.push(raw_tau[k + trim][j]);
                }
                sample += 1;
            }
        }
    }
    pooled(&folds, &cols, p)
}

/// Each joint's held-out RMS pooled over `folds` (`p` columns; joint j's
/// rows in columns `cols[j]`), each fold predicted by the fit on the
/// others; NaN when a fold has nothing to score.
fn pooled(
    folds: &[Vec<JointRows>],
    cols: &[Vec<usize>],
    p: usize,
) -> Result<Vec<f64>, IdentifyError> {
    let n = cols.len();
    if folds.iter().any(|f| f[0].raw.is_empty()) {
        return Ok(vec![f64::NAN; n]);
    }
    // each fold's normal equations [G b] (lower triangle of the products
    // of its rows [y τ], scattered into the p columns)
    let mats: Vec<Mat<f64>> = (folds.iter())
        .map(|f| {
            let grams: Vec<Mat<f64>> = (f.iter().zip(cols))
                .map(|(jr, cs)| {
                    let mut g = Mat::zeros(cs.len() + 1, cs.len() + 1);
                    add_products(&mut g, &jr.rows, jr.raw.len());
                    g
                })
                .collect();
            let with_tau: Vec<Vec<usize>> = cols
                .iter()
                .map(|c| c.iter().copied().chain([p]).collect())
                .collect();
            scattered(p + 1, &with_tau, &grams, false).0
        })
        .collect();
    let total = mats
        .iter()
        .fold(Mat::<f64>::zeros(p + 1, p + 1), |a, m| a + m);
    let (mut sum, mut count) = (vec![0.0; n], 0usize);
    for (f, m) in folds.iter().zip(&mats) {
        let theta = solve_lower_normal(&(&total - m), p)?;
        for (j, (jr, cs)) in f.iter().zip(cols).enumerate() {
            let th: Vec<f64> = cs.iter().map(|&c| theta[c]).collect();
            let rows = jr.rows.chunks_exact(cs.len() + 1);
            sum[j] += (rows.zip(&jr.raw))
                .map(|(r, t)| (r.iter().zip(&th).map(|(a, b)| a * b).sum::<f64>() - t).powi(2))
                .sum::<f64>();
        }
        count += f[0].raw.len();
    }
    Ok(sum
        .iter()
        .map(|s| (s / count.max(1) as f64).sqrt())
        .collect())
}

/// `G⁻¹ b` for the lower triangle of `[G b]ᵀ`-shaped sums `m` ((p + 1)²:
/// G its first p rows and columns, b its last row), with a ridge of
/// 1e-10 of G's mean diagonal; by Cholesky on the calling thread.
fn solve_lower_normal(m: &Mat<f64>, p: usize) -> Result<Vec<f64>, IdentifyError> {
    let trace: f64 = (0..p).map(|i| m[(i, i)]).sum();
    let ridge = 1e-10 * (trace / p as f64).max(f64::MIN_POSITIVE);
    let g = Mat::<f64>::from_fn(p, p, |i, j| {
        m[(i.max(j), i.min(j))] + if i == j { ridge } else { 0.0 }
    });
    let b: Vec<f64> = (0..p).map(|i| m[(p, i)]).collect();
    crate::linalg::spd_solve(g, &b).ok_or(IdentifyError::Factorisation {
        what: "Cholesky factorisation of a cut-off candidate's Gram matrix",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_rises_by_root_two_to_the_spectrum_choice() {
        let g = grid(10.0);
        assert_eq!(g.len(), 6, "{g:?}");
        assert!((g[0] - 2.0).abs() < 1e-12 && (g[4] - 8.0).abs() < 1e-9);
        assert_eq!(*g.last().unwrap(), 10.0);
        assert_eq!(grid(1.5), vec![1.5]);
    }

    /// A log with q̈ is prepared: nothing to choose.
    #[test]
    fn a_prepared_log_has_no_choice() {
        let model = crate::dynamics::cheetah3::model();
        let mut log = RawLog {
            path: "p.csv".into(),
            t: (0..100).map(|k| 1e-3 * k as f64).collect(),
            q: crate::dynamics::Samples::zeros(100, 3),
            qd: None,
            qdd: Some(crate::dynamics::Samples::zeros(100, 3)),
            tau: Some(crate::dynamics::Samples::zeros(100, 3)),
            warnings: vec![],
        };
        let none = choose_cutoff(std::slice::from_ref(&log), &model, Velocity::Differentiate);
        assert_eq!(none.unwrap(), None);
        log.qdd = None;
        log.tau = None;
        let none = choose_cutoff(&[log], &model, Velocity::Differentiate);
        assert_eq!(none.unwrap(), None, "no torques: nothing to score");
    }
}
