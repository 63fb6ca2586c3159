//! Excitation trajectories: the paper's foot-on-an-ellipsoidal-shell motion
//! for `cheetah3-leg`, and a multi-sine (Fourier series) per joint for any
//! robot. Both give exact q(t); q̇ and q̈ come from 4th-order central
//! differences of it with a 0.1 ms step (error far below any noise level).

use crate::dynamics::Model;
use crate::dynamics::cheetah3::{HIP_OFFSET, SHANK, THIGH};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};

/// The ellipsoidal shell the foot follows (base frame, m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Shell {
    /// Centre (m).
    pub center: [f64; 3],
    /// Semi-axes (m).
    pub semi_axes: [f64; 3],
    /// φ̇ = a_φ sin(ω_φ t): amplitude (rad/s) and frequency (rad/s).
    pub phi_rate: (f64, f64),
    /// θ̇ = a_θ sin(ω_θ t).
    pub theta_rate: (f64, f64),
}

impl Default for Shell {
    /// Our choice (the paper gives neither centre nor radii): centred under
    /// the hip, 0.45 m below the ab/ad axis, semi-axes 0.12 × 0.10 × 0.12 m;
    /// the paper's rates φ̇ = 12 sin(1.63 t), θ̇ = 3.4 sin(0.265 t).
    fn default() -> Self {
        Self {
            center: [0.0, 0.045, -0.45],
            semi_axes: [0.12, 0.10, 0.12],
            phi_rate: (12.0, 1.63),
            theta_rate: (3.4, 0.265),
        }
    }
}

impl Shell {
    /// Spherical angles at time t: φ = (a/ω)(1 − cos ωt), θ = π/2 + (a/ω)(1 − cos ωt).
    pub fn angles(&self, t: f64) -> (f64, f64) {
        let (ap, wp) = self.phi_rate;
        let (at, wt) = self.theta_rate;
        (
            ap / wp * (1.0 - (wp * t).cos()),
            std::f64::consts::FRAC_PI_2 + at / wt * (1.0 - (wt * t).cos()),
        )
    }

    /// Foot target at time t (base frame).
    pub fn foot(&self, t: f64) -> Vector3<f64> {
        let (phi, theta) = self.angles(t);
        let [a, b, c] = self.semi_axes;
        Vector3::from(self.center)
            + Vector3::new(
                a * theta.sin() * phi.cos(),
                b * theta.sin() * phi.sin(),
                c * theta.cos(),
            )
    }
}

/// Inverse kinematics of the Cheetah 3 leg, on the branch with the foot
/// below the hip (in the ab/ad frame) and the knee bent to positive angles.
/// Returns `None` when the point is out of reach.
pub fn cheetah_ik(p: &Vector3<f64>) -> Option<[f64; 3]> {
    let d = HIP_OFFSET[1];
    let r2 = p.y * p.y + p.z * p.z - d * d;
    if r2 < 0.0 {
        return None;
    }
    let zp = -r2.sqrt(); // foot below the hip in the ab/ad frame
    let qa = p.z.atan2(p.y) - zp.atan2(d);
    let xp = p.x;
    let (l1, l2) = (THIGH, SHANK);
    let c = (xp * xp + zp * zp - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if !(-1.0..=1.0).contains(&c) {
        return None;
    }
    let qk = c.acos();
    let qh = xp.atan2(-zp) - (l2 * qk.sin()).atan2(l1 + l2 * qk.cos());
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
    };
    Some([wrap(qa), wrap(qh), qk])
}

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
}

impl Trajectory {
    /// A random multi-sine (5 harmonics of 0.1 Hz·2π… with `seed`) kept inside
    /// 90 % of each joint's range (±1 rad around 0 for unlimited joints).
    pub fn fourier_for(model: &Model, seed: u64) -> Self {
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let harmonics = 5;
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
            let s = 0.9 * half / total;
            aj.iter_mut().for_each(|x| *x *= s);
            bj.iter_mut().for_each(|x| *x *= s);
            offset.push(mid);
            a.push(aj);
            b.push(bj);
        }
        Trajectory::Fourier {
            omega: 2.0 * std::f64::consts::PI * 0.2,
            offset,
            a,
            b,
        }
    }

    /// q(t); `None` if out of reach (shell).
    pub fn q(&self, t: f64) -> Option<Vec<f64>> {
        match self {
            Trajectory::Shell(s) => cheetah_ik(&s.foot(t)).map(|q| q.to_vec()),
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

    /// (q, q̇, q̈) at t by 4th-order central differences of q.
    pub fn state(&self, t: f64) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
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
