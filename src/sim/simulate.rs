//! Generating a data set: trajectory → true robot → measurement → offline
//! processing, plus the JSON record that reproduces it.

use super::robot::{Effects, TrueRobot};
use super::trajectory::{Shell, Trajectory};
use crate::data::filter::{differentiate, filtfilt};
use crate::data::{Dataset, estimate_qdd};
use crate::dynamics::Model;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// How a data set is made (written beside it as JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    /// Robot (built-in name or URDF path).
    pub robot: String,
    /// Duration (s).
    pub seconds: f64,
    /// Sampling rate (Hz).
    pub rate_hz: f64,
    /// The excitation.
    pub trajectory: Trajectory,
    /// Effects of the true robot.
    pub effects: Effects,
    /// Torque noise σ (N·m), Gaussian, white.
    pub noise_sigma: f64,
    /// Encoder counts per motor turn (0: no quantisation); the joint
    /// resolution is `2π / (counts · N)`.
    pub encoder_counts: f64,
    /// Cut-off (Hz) of the zero-phase filter of the offline processing.
    pub cutoff_hz: f64,
    /// RNG seed.
    pub seed: u64,
    /// Whether q̇, q̈ are estimated from the (quantised) positions as the
    /// paper did offline (true unless the data are noise-free and unquantised,
    /// in which case the exact states are written).
    pub processed: bool,
}

impl SimConfig {
    /// Defaults for a robot: 1 kHz, σ = 0.3 N·m, 2¹⁴ counts, 30 Hz cut-off;
    /// the shell for cheetah3-leg, a multi-sine otherwise.
    pub fn for_model(
        robot: &str,
        model: &Model,
        seconds: f64,
        effects: Effects,
        seed: u64,
    ) -> Self {
        let trajectory = if model.name == "cheetah3-leg" {
            Trajectory::Shell(Shell::default())
        } else {
            Trajectory::fourier_for(model, seed)
        };
        Self {
            robot: robot.into(),
            seconds,
            rate_hz: 1000.0,
            trajectory,
            effects,
            noise_sigma: 0.3,
            encoder_counts: 16384.0,
            cutoff_hz: 30.0,
            seed,
            processed: true,
        }
    }
}

/// Simulates; `progress(done, total)` is called every 1000 samples.
pub fn simulate(
    model: &Model,
    cfg: &SimConfig,
    mut progress: impl FnMut(usize, usize),
) -> Result<Dataset, String> {
    if !(cfg.seconds > 0.0
        && cfg.rate_hz > 0.0
        && cfg.noise_sigma >= 0.0
        && cfg.encoder_counts >= 0.0)
    {
        return Err(
            "seconds and rate must be positive, noise and encoder counts non-negative".into(),
        );
    }
    let robot = TrueRobot::new(model, cfg.effects.clone())?;
    let n = (cfg.seconds * cfg.rate_hz).round() as usize;
    let nj = model.dof();
    let dt = 1.0 / cfg.rate_hz;
    let mut d = Dataset {
        joints: model.joint_names().iter().map(|s| s.to_string()).collect(),
        t: vec![],
        q: vec![],
        qd: vec![],
        qdd: vec![],
        tau: vec![],
    };
    let (mut qs, mut qds, mut qdds) = (vec![], vec![], vec![]);
    for k in 0..n {
        let t = k as f64 * dt;
        let (q, qd, qdd) = cfg
            .trajectory
            .state(t)
            .ok_or_else(|| format!("the trajectory leaves the workspace at t = {t} s"))?;
        let (qx, qdx, qddx) = if robot.delay() > 0.0 {
            cfg.trajectory
                .state(t - robot.delay())
                .ok_or("delay outside the workspace")?
        } else {
            (q.clone(), qd.clone(), qdd.clone())
        };
        for (i, j) in model.joints.iter().enumerate() {
            if q[i] < j.limits.0 || q[i] > j.limits.1 {
                return Err(format!(
                    "joint '{}' leaves its limits at t = {t} s (q = {})",
                    j.name, q[i]
                ));
            }
        }
        d.t.push(t);
        d.q.push(q);
        d.qd.push(qd);
        d.qdd.push(qdd);
        qs.push(qx);
        qds.push(qdx);
        qdds.push(qddx);
        if k % 1000 == 999 {
            progress(k + 1, n);
        }
    }
    d.tau = robot.torques(&qs, &qds, &qdds)?;
    if let Some(c) = robot.compliance() {
        // the links' rigid torque at the motor-side state is replaced by the
        // spring torque that actually drives them
        let links = robot.links_model();
        let rigid = crate::dynamics::predict::predict_torques(
            &links,
            &crate::dynamics::params_file::Friction {
                viscous: vec![0.0; nj],
                coulomb: vec![0.0; nj],
            },
            &qs,
            &qds,
            &qdds,
        )
        .map_err(|e| e.to_string())?;
        let times: Vec<f64> = d.t.iter().map(|t| t - robot.delay()).collect();
        let link_side = super::compliance::simulate_link_side(&links, &cfg.trajectory, &times, &c)?;
        let gain = if robot.effects().has("torque_gain") {
            1.0 + robot.effects().param("gain_error")
        } else {
            1.0
        };
        for k in 0..n {
            for i in 0..nj {
                d.tau[k][i] += gain * (link_side[k].2[i] - rigid[k][i]);
            }
        }
    }
    let mut rng = rand::rngs::StdRng::seed_from_u64(cfg.seed);
    if cfg.noise_sigma > 0.0 {
        let normal = Normal::new(0.0, cfg.noise_sigma).map_err(|e| e.to_string())?;
        for row in d.tau.iter_mut() {
            for v in row.iter_mut() {
                *v += normal.sample(&mut rng);
            }
        }
    }
    if cfg.processed {
        for j in 0..nj {
            let gear = model.rotor_of(j).map_or(1.0, |r| r.gear_ratio);
            let res = if cfg.encoder_counts > 0.0 {
                2.0 * std::f64::consts::PI / (cfg.encoder_counts * gear)
            } else {
                0.0
            };
            let raw: Vec<f64> =
                d.q.iter()
                    .map(|q| {
                        if res > 0.0 {
                            (q[j] / res).round() * res
                        } else {
                            q[j]
                        }
                    })
                    .collect();
            let qf = filtfilt(&raw, cfg.cutoff_hz, cfg.rate_hz);
            let qd = filtfilt(&differentiate(&raw, &d.t), cfg.cutoff_hz, cfg.rate_hz);
            for k in 0..n {
                d.q[k][j] = qf[k];
                d.qd[k][j] = qd[k];
            }
        }
        d.qdd = estimate_qdd(&d.t, &d.qd, cfg.cutoff_hz);
    }
    progress(n, n);
    Ok(d)
}
