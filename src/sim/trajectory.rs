//! Excitation trajectories: the paper's foot-on-an-ellipsoidal-shell motion
//! for `cheetah3-leg` (through its inverse kinematics, [`cheetah_ik`]), and a
//! multi-sine (Fourier series) per joint for any robot; a robot
//! description's [`Excitation`] says which. Both give exact q(t); q̇ and q̈ come from 4th-order central
//! differences of it with a 0.1 ms step (error far below any noise level).
//! A third kind, [`SampledTrajectory`], is samples of (q, q̇, q̈) read from a
//! file and interpolated.

pub use super::sampled::SampledTrajectory;
use crate::dynamics::Model;
pub use crate::dynamics::leg_kinematics::{Shell, cheetah_ik};
use crate::dynamics::sidecar::{Excitation, MultiSine};
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};

/// A trajectory q(t) with derivatives.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Trajectory {
    /// The paper's shell motion (cheetah3-leg only).
    Shell(Shell),
    /// `qⱼ(t) = cⱼ + Σₖ aⱼₖ sin(k ω t) + bⱼₖ cos(k ω t)`.
    Fourier {
        /// Base frequency ω (rad/s).
        omega: f64,
        /// Offsets cⱼ.
        offset: Vec<f64>,
        /// Sine coefficients, per joint, per harmonic.
        a: Vec<Vec<f64>>,
        /// Cosine coefficients.
        b: Vec<Vec<f64>>,
    },
    /// Samples of (q, q̇, q̈) interpolated (a trajectory file); t is the
    /// time since its first sample.
    Sampled(SampledTrajectory),
}

impl Trajectory {
    /// The robot's default excitation for `seed`.
    pub fn for_excitation(e: &Excitation, model: &Model, seed: u64) -> Self {
        match e {
            Excitation::MultiSine(m) => Self::multi_sine(model, m, seed),
            Excitation::LegShell(s) => Trajectory::Shell(*s),
        }
    }

    /// A random multi-sine (5 harmonics of 0.2 Hz with `seed`) kept inside
    /// 90 % of each joint's range (±1 rad around 0 for unlimited joints).
    pub fn fourier_for(model: &Model, seed: u64) -> Self {
        Self::multi_sine(model, &MultiSine::default(), seed)
    }

    /// A random multi-sine with `seed`: coefficients uniform in ±1/k for
    /// harmonic k, scaled so that each joint stays inside
    /// `range_fraction` of its range (±1 rad around 0 for unlimited joints).
    pub fn multi_sine(model: &Model, spec: &MultiSine, seed: u64) -> Self {
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let harmonics = spec.harmonics;
        let mut offset = vec![];
        let (mut a, mut b) = (vec![], vec![]);
        for j in &model.joints {
            let (lo, hi) = j.limits;
            let (mid, half) = if lo.is_finite() && hi.is_finite() {
                (0.5 * (lo + hi), 0.5 * (hi - lo))
            } else {
                (0.0, 1.0)
            };
            let mut aj: Vec<f64> = (0..harmonics)
                .map(|k| rng.random_range(-1.0..1.0) / (k + 1) as f64)
                .collect();
            let mut bj: Vec<f64> = (0..harmonics)
                .map(|k| rng.random_range(-1.0..1.0) / (k + 1) as f64)
                .collect();
            let total: f64 = aj.iter().chain(&bj).map(|x| x.abs()).sum();
            let s = spec.range_fraction * half / total;
            aj.iter_mut().for_each(|x| *x *= s);
            bj.iter_mut().for_each(|x| *x *= s);
            offset.push(mid);
            a.push(aj);
            b.push(bj);
        }
        Trajectory::Fourier {
            omega: 2.0 * std::f64::consts::PI * spec.base_hz,
            offset,
            a,
            b,
        }
    }

    /// Number of joints it moves.
    pub fn joints(&self) -> usize {
        match self {
            Trajectory::Shell(_) => 3,
            Trajectory::Fourier { offset, .. } => offset.len(),
            Trajectory::Sampled(s) => s.joints(),
        }
    }

    /// q(t); `None` if out of reach (shell).
    pub fn q(&self, t: f64) -> Option<Vec<f64>> {
        match self {
            Trajectory::Shell(s) => cheetah_ik(&s.foot(t)).map(|q| q.to_vec()),
            Trajectory::Sampled(s) => s.state(t).map(|(q, _, _)| q),
            Trajectory::Fourier {
                omega,
                offset,
                a,
                b,
            } => Some(
                (0..offset.len())
                    .map(|j| {
                        offset[j]
                            + a[j]
                                .iter()
                                .enumerate()
                                .map(|(k, c)| c * ((k + 1) as f64 * omega * t).sin())
                                .sum::<f64>()
                            + b[j]
                                .iter()
                                .enumerate()
                                .map(|(k, c)| c * ((k + 1) as f64 * omega * t).cos())
                                .sum::<f64>()
                    })
                    .collect(),
            ),
        }
    }

    /// The top frequency (Hz) of a multi-sine; `None` for the shell and
    /// samples (not estimated: the default cut-off is then 30 Hz).
    pub fn top_hz(&self) -> Option<f64> {
        match self {
            Trajectory::Fourier { omega, a, .. } => {
                let harmonics = a.iter().map(Vec::len).max().unwrap_or(0);
                Some(omega.abs() * harmonics as f64 / (2.0 * std::f64::consts::PI))
            }
            Trajectory::Shell(_) | Trajectory::Sampled(_) => None,
        }
    }

    /// The exact (q, q̇, q̈) of a Fourier series at t (its analytic
    /// derivatives); `None` for the shell and samples.
    pub fn exact_state(&self, t: f64) -> Option<[Vec<f64>; 3]> {
        let Trajectory::Fourier {
            omega,
            offset,
            a,
            b,
        } = self
        else {
            return None;
        };
        let mut out = [vec![], vec![], vec![]];
        for j in 0..offset.len() {
            let s = harmonic_state(*omega, (&a[j], &b[j]), t);
            out[0].push(offset[j] + s[0]);
            out[1].push(s[1]);
            out[2].push(s[2]);
        }
        Some(out)
    }

    /// (q, q̇, q̈) at t by 4th-order central differences of q (samples: their
    /// interpolant's, [`SampledTrajectory::state`]).
    pub fn state(&self, t: f64) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        if let Trajectory::Sampled(s) = self {
            return s.state(t);
        }
        let h = 1e-4;
        let qs: Vec<Vec<f64>> = [-2.0, -1.0, 0.0, 1.0, 2.0]
            .iter()
            .map(|k| self.q(t + k * h))
            .collect::<Option<_>>()?;
        let n = qs[0].len();
        // unwrap angle jumps across ±π between neighbouring evaluations
        let un = |j: usize, k: usize| {
            let mut v = qs[k][j];
            let c = qs[2][j];
            while v - c > std::f64::consts::PI {
                v -= 2.0 * std::f64::consts::PI;
            }
            while c - v > std::f64::consts::PI {
                v += 2.0 * std::f64::consts::PI;
            }
            v
        };
        let qd = (0..n)
            .map(|j| (un(j, 0) - 8.0 * un(j, 1) + 8.0 * un(j, 3) - un(j, 4)) / (12.0 * h))
            .collect();
        let qdd = (0..n)
            .map(|j| {
                (-un(j, 0) + 16.0 * un(j, 1) - 30.0 * qs[2][j] + 16.0 * un(j, 3) - un(j, 4))
                    / (12.0 * h * h)
            })
            .collect();
        Some((qs[2].clone(), qd, qdd))
    }
}

/// q, q̇, q̈ at t of one joint's `Σₖ aₖ sin(k ω t) + bₖ cos(k ω t)`
/// (k = 1 … H, offset 0).
pub fn harmonic_state(omega: f64, (a, b): (&[f64], &[f64]), t: f64) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (k, (a, b)) in a.iter().zip(b).enumerate() {
        let w = (k + 1) as f64 * omega;
        let (sn, cs) = (w * t).sin_cos();
        s[0] += a * sn + b * cs;
        s[1] += w * (a * cs - b * sn);
        s[2] -= w * w * (a * sn + b * cs);
    }
    s
}
