//! A periodic Fourier-series motion per joint,
//! `qⱼ(t) = cⱼ + Σₖ aⱼₖ sin(k ω t) + bⱼₖ cos(k ω t)`, fitted inside the
//! joints' limits: each joint's oscillation is scaled down until its range,
//! peak velocity and peak acceleration (on a grid of 64 points per period
//! and harmonic, less a 3 % margin) fit, and centred in its range.

use super::error::ExciteError;
use super::limits::JointLimits;
use crate::sim::trajectory::{Trajectory, harmonic_state};

/// The fraction of the position range and of the velocity and acceleration
/// limits kept free (for the peaks between grid points).
pub const RATE_MARGIN: f64 = 0.03;

/// Grid points per period and harmonic on which peaks are taken.
pub const GRID: usize = 64;

/// One joint's oscillation: sine and cosine coefficients per harmonic.
#[derive(Clone, Debug)]
pub struct Coefficients {
    /// Base frequency ω (rad/s).
    pub omega: f64,
    /// Per joint, `[a₁ … a_H, b₁ … b_H]`.
    pub ab: Vec<Vec<f64>>,
}

impl Coefficients {
    /// The motion scaled into `limits` and centred, as a [`Trajectory`].
    pub fn fitted(&self, limits: &[JointLimits]) -> Result<Trajectory, ExciteError> {
        let h = self.ab.first().map_or(0, |v| v.len() / 2);
        let grid = GRID * h.max(1);
        let period = 2.0 * std::f64::consts::PI / self.omega;
        let (mut offset, mut a, mut b) = (vec![], vec![], vec![]);
        for (ab, lim) in self.ab.iter().zip(limits) {
            let (mut lo, mut hi, mut v, mut acc) =
                (f64::INFINITY, f64::NEG_INFINITY, 0.0f64, 0.0f64);
            for i in 0..grid {
                let s = harmonic_state(
                    self.omega,
                    (&ab[..h], &ab[h..]),
                    period * i as f64 / grid as f64,
                );
                (lo, hi) = (lo.min(s[0]), hi.max(s[0]));
                (v, acc) = (v.max(s[1].abs()), acc.max(s[2].abs()));
            }
            let room = lim.position.1 - lim.position.0;
            if !(room > 0.0) {
                return Err(ExciteError::NoRoom {
                    joint: lim.joint.clone(),
                    why: format!("its range less the margins is {room}"),
                });
            }
            let keep = 1.0 - RATE_MARGIN;
            let ratio = |limit: f64, peak: f64| {
                if peak > 0.0 {
                    limit / peak
                } else {
                    f64::INFINITY
                }
            };
            let s = [
                1.0,
                ratio(keep * room, hi - lo),
                ratio(keep * lim.velocity, v),
                ratio(keep * lim.acceleration, acc),
            ]
            .into_iter()
            .fold(f64::INFINITY, f64::min);
            offset.push(0.5 * (lim.position.0 + lim.position.1) - s * 0.5 * (lo + hi));
            a.push(ab[..h].iter().map(|x| x * s).collect());
            b.push(ab[h..].iter().map(|x| x * s).collect());
        }
        Ok(Trajectory::Fourier {
            omega: self.omega,
            offset,
            a,
            b,
        })
    }
}
