//! A floating-base robot moved while suspended from a harness: the base
//! follows a smooth random twist (its pose integrated from it), the joints
//! a random Fourier motion, and a six-axis load cell between harness and
//! base measures the one contact wrench, the base rows of the inverse
//! dynamics (`M a + h = [w; τ]`). Noise: on the wrench (the load cell), the
//! base twist and its derivative (the IMU), the joint states (encoders) and
//! the joint torques; the quaternion stays of unit norm.

use super::error::SimError;
use super::trajectory::harmonic_state;
use crate::data::{Dataset, Samples};
use crate::dynamics::{Data, Model, RootJoint, WrenchFrame};
use crate::moments::InertialParams;
use nalgebra::{UnitQuaternion, Vector3};
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, Normal};

/// Noise standard deviations of the suspended log's sensors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatingNoise {
    /// Load cell force (N).
    pub force: f64,
    /// Load cell moment (N·m).
    pub moment: f64,
    /// Gyroscope and base linear velocity (rad/s, m/s).
    pub twist: f64,
    /// Base acceleration, linear and angular (m/s², rad/s²).
    pub twist_rate: f64,
    /// Joint positions (rad), velocities ×10, accelerations ×100.
    pub encoder: f64,
    /// Joint torques (N·m).
    pub torque: f64,
}

impl FloatingNoise {
    /// Every sensor exact.
    pub fn none() -> Self {
        Self {
            force: 0.0,
            moment: 0.0,
            twist: 0.0,
            twist_rate: 0.0,
            encoder: 0.0,
            torque: 0.0,
        }
    }
}

impl Default for FloatingNoise {
    /// A small robot's sensors: 0.2 N and 0.01 N·m on the load cell, 0.01
    /// rad/s, 0.05 m/s², 1e-4 rad and 0.02 N·m.
    fn default() -> Self {
        Self {
            force: 0.2,
            moment: 0.01,
            twist: 0.01,
            twist_rate: 0.05,
            encoder: 1e-4,
            torque: 0.02,
        }
    }
}

/// Effects the nominal (URDF) model lacks, put into a floating-base log for
/// a diagnosis to find.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct FloatingEffects {
    /// Every joint's viscous (N·m·s/rad) and Coulomb (N·m) friction, in the
    /// measured joint torques.
    pub joint_friction: Option<[f64; 2]>,
    /// A constant bias on every contact's measured wrench (force N, moment
    /// N·m, in the contact's columns' axes): a load cell's zero drift.
    pub wrench_offset: Option<[f64; 6]>,
    /// A point mass (kg) fixed to the base at a point (m, base frame): a
    /// battery or payload the URDF lacks.
    pub payload: Option<(f64, [f64; 3])>,
}

impl FloatingEffects {
    /// The effects a name switches on, each of a fixed size (the
    /// command line's `--floating-effects` and Python's `effects`).
    pub const NAMED: [&'static str; 3] = ["joint_friction", "wrench_offset", "payload"];

    /// The effects `names` switch on ([`NAMED`](Self::NAMED)): 0.01
    /// N·m·s/rad viscous and 0.05 N·m Coulomb friction at every joint;
    /// every contact's sensor off by [1, −0.5, 2] N and [0.05, 0.02, −0.03]
    /// N·m; 0.3 kg on the base at [0.05, 0, 0.03] m (base frame).
    pub fn named<S: AsRef<str>>(names: &[S]) -> Result<Self, SimError> {
        let mut e = Self::default();
        for name in names {
            match name.as_ref() {
                "joint_friction" => e.joint_friction = Some([0.01, 0.05]),
                "wrench_offset" => e.wrench_offset = Some([1.0, -0.5, 2.0, 0.05, 0.02, -0.03]),
                "payload" => e.payload = Some((0.3, [0.05, 0.0, 0.03])),
                other => {
                    return Err(SimError::UnknownEffect {
                        name: other.to_string(),
                        known: Self::NAMED.join(", "),
                    });
                }
            }
        }
        Ok(e)
    }

    /// The names of the effects switched on.
    pub fn names(&self) -> Vec<&'static str> {
        let on = [
            (self.joint_friction.is_some(), "joint_friction"),
            (self.wrench_offset.is_some(), "wrench_offset"),
            (self.payload.is_some(), "payload"),
        ];
        on.iter().filter(|(o, _)| *o).map(|(_, n)| *n).collect()
    }

    /// The true robot: `ff` with the payload in its base.
    pub fn truth(&self, ff: &Model) -> Result<Model, SimError> {
        ff.need_free_flyer("a floating-base simulation")?;
        let mut t = ff.clone();
        if let Some((m, [x, y, z])) = self.payload {
            if !(m.is_finite() && m > 0.0 && [x, y, z].iter().all(|v| v.is_finite())) {
                return Err(SimError::Setting {
                    setting: "payload mass",
                    value: m,
                    requirement: "a finite mass > 0 at a finite point",
                });
            }
            let com = nalgebra::Vector3::new(x, y, z);
            let point = InertialParams::from_mass_com_inertia(m, com, nalgebra::Matrix3::zeros());
            if let RootJoint::FreeFlyer(base) = &mut t.root {
                base.inertia = base.inertia.plus(&point);
            }
        }
        Ok(t)
    }

    /// The friction and the offset, added to an exact log's torques and
    /// wrenches (before the noise).
    pub(super) fn apply(&self, log: &mut Dataset) {
        if let Some([b, c]) = self.joint_friction {
            use crate::dynamics::{DEFAULT_STRIBECK_VELOCITY as VS, FrictionTerm as F};
            for (tau, qd) in log.tau.iter_mut().zip(log.qd.iter()) {
                for (t, &qd) in tau.iter_mut().zip(qd) {
                    *t += b * F::Viscous.basis(qd, 0.0, VS) + c * F::Coulomb.basis(qd, 0.0, VS);
                }
            }
        }
        if let Some(o) = self.wrench_offset {
            for ch in &mut log.contacts {
                ch.wrench
                    .iter_mut()
                    .enumerate()
                    .for_each(|(i, w)| *w += o[i % 6]);
            }
        }
    }
}

/// The motion's amplitudes and the log's rate and length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SuspendedConfig {
    /// Seconds of log.
    pub seconds: f64,
    /// Samples per second.
    pub rate: f64,
    /// Random seed of the motion and the noise.
    pub seed: u64,
    /// Joint amplitude per harmonic (rad).
    pub joint_amplitude: f64,
    /// Base angular velocity amplitude per harmonic (rad/s); the linear
    /// velocity's is a tenth of it in m/s.
    pub base_amplitude: f64,
    /// Sensor noise.
    pub noise: FloatingNoise,
    /// Effects the nominal model lacks.
    pub effects: FloatingEffects,
}

impl Default for SuspendedConfig {
    fn default() -> Self {
        Self {
            seconds: 20.0,
            rate: 200.0,
            seed: 1,
            joint_amplitude: 0.3,
            base_amplitude: 0.6,
            noise: FloatingNoise::default(),
            effects: FloatingEffects::default(),
        }
    }
}

const HARMONICS: usize = 4;
const BASE_FREQUENCY: f64 = 0.1;

/// Random Fourier coefficients (a, b) for `channels` signals.
pub(super) fn coefficients(
    rng: &mut StdRng,
    channels: usize,
    amplitude: f64,
) -> Vec<[Vec<f64>; 2]> {
    let mut c = || {
        (0..HARMONICS)
            .map(|_| amplitude * rng.random_range(-1.0..1.0))
            .collect()
    };
    (0..channels).map(|_| [c(), c()]).collect()
}

/// The exact `[x, ẋ, ẍ]` of every channel at t.
pub(super) fn channels(coef: &[[Vec<f64>; 2]], t: f64) -> Vec<[f64; 3]> {
    let omega = 2.0 * std::f64::consts::PI * BASE_FREQUENCY;
    (coef.iter())
        .map(|[a, b]| harmonic_state(omega, (a, b), t))
        .collect()
}

/// The exact motion (`q`, `v`, `a` of the free-flyer) at the log's times;
/// the pose integrated from the body-frame twist (20 steps a sample, each
/// the exact rotation of the step's midpoint angular velocity, so the
/// quaternion stays of unit norm).
fn motion(ff: &Model, cfg: &SuspendedConfig, rng: &mut StdRng) -> [Vec<f64>; 3] {
    let n = ff.dof();
    let joints = coefficients(rng, n, cfg.joint_amplitude);
    let mut base = coefficients(rng, 6, cfg.base_amplitude);
    base[..3]
        .iter_mut()
        .flatten()
        .flatten()
        .for_each(|x| *x *= 0.1);
    let samples = (cfg.seconds * cfg.rate).round() as usize;
    let dt = 1.0 / cfg.rate;
    let (mut p, mut rot) = (Vector3::new(0.0, 0.0, 0.5), UnitQuaternion::identity());
    let [mut q, mut v, mut a] = [Vec::new(), Vec::new(), Vec::new()];
    for k in 0..samples {
        let t = k as f64 * dt;
        let (b, j) = (channels(&base, t), channels(&joints, t));
        let c = rot.coords;
        q.extend([p.x, p.y, p.z, c.x, c.y, c.z, c.w]);
        q.extend(j.iter().map(|s| s[0]));
        v.extend(b.iter().map(|s| s[1]).chain(j.iter().map(|s| s[1])));
        a.extend(b.iter().map(|s| s[2]).chain(j.iter().map(|s| s[2])));
        (p, rot) = integrate_pose(&base, (p, rot), t, dt);
    }
    [q, v, a]
}

/// The pose at `t + dt` from the pose at t: `ṗ = R v`, `Ṙ = R [ω]×`.
fn integrate_pose(
    base: &[[Vec<f64>; 2]],
    (mut p, mut rot): (Vector3<f64>, UnitQuaternion<f64>),
    t: f64,
    dt: f64,
) -> (Vector3<f64>, UnitQuaternion<f64>) {
    const STEPS: usize = 20;
    let h = dt / STEPS as f64;
    let twist = |t: f64| {
        let s = channels(base, t);
        (
            Vector3::new(s[0][1], s[1][1], s[2][1]),
            Vector3::new(s[3][1], s[4][1], s[5][1]),
        )
    };
    for i in 0..STEPS {
        let t0 = t + i as f64 * h;
        // midpoint twist over the step: exact exponential of a constant ω
        let (vl, w) = twist(t0 + 0.5 * h);
        let step = UnitQuaternion::from_scaled_axis(w * h);
        let mid = rot * UnitQuaternion::from_scaled_axis(w * (0.5 * h));
        p += mid * vl * h;
        rot = rot * step;
    }
    (p, rot)
}

/// A suspended log of the robot `ff` (the nominal model; the truth is it
/// with `cfg.effects`): the harness wrench at the base frame (local axes)
/// and the joint torques, with noise.
pub fn simulate_suspended(ff: &Model, cfg: &SuspendedConfig) -> Result<Dataset, SimError> {
    let truth = cfg.effects.truth(ff)?;
    let ff = &truth;
    let samples = cfg.seconds * cfg.rate;
    if !(cfg.rate > 0.0 && (10.0..=1e7).contains(&samples)) {
        return Err(SimError::Setting {
            setting: "seconds × rate",
            value: samples,
            requirement: "between 10 and 1e7 samples at a positive rate",
        });
    }
    let mut rng = StdRng::seed_from_u64(cfg.seed);
    let [q, v, a] = motion(ff, cfg, &mut rng);
    let (nq, nv, n) = (ff.nq(), ff.nv(), ff.dof());
    let samples = q.len() / nq;
    let mut data = Data::new(ff);
    let (mut wrench, mut tau) = (
        Vec::with_capacity(6 * samples),
        Vec::with_capacity(n * samples),
    );
    for k in 0..samples {
        let g = crate::dynamics::rnea(
            ff,
            &mut data,
            &q[k * nq..(k + 1) * nq],
            &v[k * nv..(k + 1) * nv],
            &a[k * nv..(k + 1) * nv],
        )?;
        wrench.extend(g.iter().take(6));
        tau.extend(g.iter().skip(6));
    }
    let harness = [(ff.body_names()[0].clone(), WrenchFrame::Local)];
    let mut log = Dataset::for_model(ff, &harness);
    for k in 0..samples {
        let state = (
            &q[k * nq..(k + 1) * nq],
            &v[k * nv..(k + 1) * nv],
            &a[k * nv..(k + 1) * nv],
        );
        log.push_state(k as f64 / cfg.rate, state, Some(&tau[k * n..(k + 1) * n]));
    }
    log.contacts[0].wrench = wrench;
    cfg.effects.apply(&mut log);
    add_noise(&mut log, &cfg.noise, &mut rng)?;
    Ok(log)
}

/// The sensors' noise on an exact log: on every contact's force and
/// moment, the base twist and its rate, the joint states and torques (the
/// quaternion and base position are left exact).
pub(super) fn add_noise(
    log: &mut Dataset,
    noise: &FloatingNoise,
    rng: &mut StdRng,
) -> Result<(), SimError> {
    let (nf, nm, nt) = (
        normal(noise.force)?,
        normal(noise.moment)?,
        normal(noise.torque)?,
    );
    for c in &mut log.contacts {
        for (i, w) in c.wrench.iter_mut().enumerate() {
            *w += if i % 6 < 3 {
                nf.sample(rng)
            } else {
                nm.sample(rng)
            };
        }
    }
    (log.tau.as_flat_mut().iter_mut()).for_each(|x| *x += nt.sample(rng));
    // (the simulators' logs are of a free flyer: `truth` refuses a fixed base)
    let base = log.base.as_mut().expect("a floating-base log");
    let (nb, nj) = (normal(noise.twist)?, normal(10.0 * noise.encoder)?);
    add_state_noise((&mut base.twist, &mut log.qd), (nb, nj), rng);
    let (nb, nj) = (normal(noise.twist_rate)?, normal(100.0 * noise.encoder)?);
    add_state_noise((&mut base.accel, &mut log.qdd), (nb, nj), rng);
    let ne = normal(noise.encoder)?;
    (log.q.as_flat_mut().iter_mut()).for_each(|x| *x += ne.sample(rng));
    Ok(())
}

/// Noise on each sample's base part (`nb`), then its joint part (`nj`).
fn add_state_noise(
    (base, joints): (&mut Samples, &mut Samples),
    (nb, nj): (Normal<f64>, Normal<f64>),
    rng: &mut StdRng,
) {
    for (b, j) in base.iter_mut().zip(joints.iter_mut()) {
        b.iter_mut().for_each(|x| *x += nb.sample(rng));
        j.iter_mut().for_each(|x| *x += nj.sample(rng));
    }
}

/// A normal distribution of standard deviation `sigma` (finite, ≥ 0).
fn normal(sigma: f64) -> Result<Normal<f64>, SimError> {
    Normal::new(0.0, sigma)
        .ok()
        .filter(|_| sigma.is_finite())
        .ok_or(SimError::Setting {
            setting: "noise",
            value: sigma,
            requirement: "a finite standard deviation ≥ 0",
        })
}
