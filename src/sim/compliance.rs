//! Joint–motor compliance: series elasticity and backlash.
//!
//! The motor side (what the encoders measure) follows the excitation θ(t)
//! exactly; the link side q_L is driven through a spring–damper with an
//! optional dead band of half-width b:
//!
//! ```text
//! τ_s = K · dz(θ − q_L, b) + D · (θ̇ − q̇_L) · [|θ − q_L| > b]
//! dz(x, b) = x − b·sign(x) for |x| > b, 0 otherwise
//! M(q_L) q̈_L + C(q_L, q̇_L) q̇_L + g(q_L) = τ_s          (links only)
//! ```
//!
//! integrated with RK4 at 10 kHz (after a 0.5 s pre-roll so the start-up
//! transient has decayed). The actuator torque then carries τ_s in place of
//! the rigid links' torque at θ; the rotors' spin and the friction stay on
//! the motor side, while each rotor's housing rides on the link it is
//! mounted on ([`crate::dynamics::Model::link_side`]).

use super::error::SimError;
use super::trajectory::Trajectory;
use crate::dynamics::{Data, Model, forward_dynamics};

/// Seconds of the link side integrated before the first sample, so that
/// the start-up transient has decayed (the trajectory is needed from then).
pub const PRE_ROLL_S: f64 = 0.5;

/// Spring, damper and dead band (joint side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compliance {
    /// Stiffness K (N·m/rad).
    pub stiffness: f64,
    /// Damping D (N·m·s/rad).
    pub damping: f64,
    /// Dead-band half-width b (rad); 0 for pure elasticity.
    pub backlash: f64,
}

impl Compliance {
    /// The transmitted torque for deflection `x = θ − q_L` and its rate.
    pub fn torque(&self, x: f64, xd: f64) -> f64 {
        let b = self.backlash;
        if x.abs() <= b {
            0.0
        } else {
            self.stiffness * (x - b * x.signum()) + self.damping * xd
        }
    }
}

/// Link-side states and transmitted torques at `times` (s, the trajectory's
/// clock): `(q_L, q̇_L, τ_s)` per sample, the motor side following the
/// trajectory exactly from [`PRE_ROLL_S`] before the first time.
pub fn simulate_link_side(
    links: &Model,
    traj: &Trajectory,
    times: &[f64],
    c: &Compliance,
) -> Result<Vec<(Vec<f64>, Vec<f64>, Vec<f64>)>, SimError> {
    let motor = |t: f64| {
        traj.state(t)
            .map(|(q, qd, _)| (q, qd))
            .ok_or(SimError::Workspace { t })
    };
    integrate(links, &motor, times, c, PRE_ROLL_S, 1e-4)
}

fn integrate(
    links: &Model,
    motor: &dyn Fn(f64) -> Result<(Vec<f64>, Vec<f64>), SimError>,
    times: &[f64],
    c: &Compliance,
    pre: f64,
    dt: f64,
) -> Result<Vec<(Vec<f64>, Vec<f64>, Vec<f64>)>, SimError> {
    let n = links.dof();
    let mut data = Data::new(links);
    let t_first = times.first().copied().unwrap_or(0.0);
    let (q0, qd0) = motor(t_first - pre)?;
    let mut x: Vec<f64> = q0.iter().chain(qd0.iter()).copied().collect();
    let rhs = |t: f64, x: &[f64], data: &mut Data| -> Result<(Vec<f64>, Vec<f64>), SimError> {
        let (th, thd) = motor(t)?;
        let tau: Vec<f64> = (0..n)
            .map(|i| c.torque(th[i] - x[i], thd[i] - x[n + i]))
            .collect();
        let qdd = forward_dynamics(links, data, &x[..n], &x[n..], &tau)?;
        let mut dx = x[n..].to_vec();
        dx.extend(qdd.iter());
        Ok((dx, tau))
    };
    let mut t = t_first - pre;
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target - 1e-12 {
            let h = dt.min(target - t);
            let add = |a: &[f64], b: &[f64], s: f64| {
                a.iter()
                    .zip(b)
                    .map(|(p, q)| p + s * q)
                    .collect::<Vec<f64>>()
            };
            let (k1, _) = rhs(t, &x, &mut data)?;
            let (k2, _) = rhs(t + h / 2.0, &add(&x, &k1, h / 2.0), &mut data)?;
            let (k3, _) = rhs(t + h / 2.0, &add(&x, &k2, h / 2.0), &mut data)?;
            let (k4, _) = rhs(t + h, &add(&x, &k3, h), &mut data)?;
            for i in 0..2 * n {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            if !x.iter().all(|v| v.is_finite()) {
                return Err(SimError::Diverged { t });
            }
            t += h;
        }
        let (_, tau) = rhs(t, &x, &mut data)?;
        out.push((x[..n].to_vec(), x[n..].to_vec(), tau));
    }
    Ok(out)
}
