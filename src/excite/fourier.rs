//! A periodic Fourier-series motion per joint,
//! `qⱼ(t) = cⱼ + Σₖ aⱼₖ sin(k ω t) + bⱼₖ cos(k ω t)`, fitted inside the
//! joints' limits: each joint's oscillation is scaled down until its range,
//! peak velocity and peak acceleration (on a grid of 64 points per period
//! and harmonic, less a 3 % margin) fit, and centred in its range.

use super::error::ExciteError;
use super::limits::JointLimits;
use crate::sim::trajectory::Trajectory;

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

/// q, q̇, q̈ of `ab` (one joint, offset 0) at t.
pub fn joint_state(omega: f64, ab: &[f64], t: f64) -> [f64; 3] {
    let h = ab.len() / 2;
    let mut s = [0.0; 3];
    for k in 0..h {
        let w = (k + 1) as f64 * omega;
        let (sn, cs) = (w * t).sin_cos();
        let (a, b) = (ab[k], ab[h + k]);
        s[0] += a * sn + b * cs;
        s[1] += w * (a * cs - b * sn);
        s[2] -= w * w * (a * sn + b * cs);
    }
    s
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
                let s = joint_state(self.omega, ab, period * i as f64 / grid as f64);
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

/// The exact (q, q̇, q̈) of a Fourier trajectory at t (`None` for another).
pub fn exact_state(traj: &Trajectory, t: f64) -> Option<[Vec<f64>; 3]> {
    let Trajectory::Fourier {
        omega,
        offset,
        a,
        b,
    } = traj
    else {
        return None;
    };
    let mut out = [vec![], vec![], vec![]];
    for j in 0..offset.len() {
        let ab: Vec<f64> = a[j].iter().chain(&b[j]).copied().collect();
        let s = joint_state(*omega, &ab, t);
        out[0].push(offset[j] + s[0]);
        out[1].push(s[1]);
        out[2].push(s[2]);
    }
    Some(out)
}
